// Our options as OpenSubdiv's Sdc::Options: the one translation the tests' references (Far in osd_reference.cpp, Bfr
// in bfr_reference.cpp) build their refiners with.
#pragma once

#include <opensubdiv/sdc/options.h>

#include "loopsub/loopsub.h"

namespace loopsub::testing {

inline OpenSubdiv::Sdc::Options sdc_options(Boundary boundary, CreaseMethod crease_method,
                                            FaceVaryingInterpolation face_varying) {
    using OpenSubdiv::Sdc::Options;
    Options sdc;
    sdc.SetVtxBoundaryInterpolation(boundary == Boundary::EdgesAndCorners ? Options::VTX_BOUNDARY_EDGE_AND_CORNER
                                    : boundary == Boundary::None          ? Options::VTX_BOUNDARY_NONE
                                                                          : Options::VTX_BOUNDARY_EDGE_ONLY);
    sdc.SetCreasingMethod(crease_method == CreaseMethod::Chaikin ? Options::CREASE_CHAIKIN : Options::CREASE_UNIFORM);
    // FaceVaryingInterpolation is declared in OpenSubdiv's order.
    sdc.SetFVarLinearInterpolation(Options::FVarLinearInterpolation(int(face_varying)));
    return sdc;
}

}  // namespace loopsub::testing
