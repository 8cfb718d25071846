// A loopsub mesh and options as OpenSubdiv's: the one adapter the tests' references (Far in osd_reference.cpp, Bfr in
// bfr_reference.cpp) and the benchmark's OpenSubdiv rows build their refiners with. Public API only
// (tests/lint/check_layers.py).
#pragma once

#include <memory>

#include <opensubdiv/far/topologyRefiner.h>
#include <opensubdiv/sdc/options.h>

#include "loopsub/loopsub.h"

namespace loopsub::testing {

// Our options as OpenSubdiv's Sdc::Options: boundary interpolation, creasing method and face-varying interpolation.
OpenSubdiv::Sdc::Options sdc_options(Boundary boundary, CreaseMethod crease_method,
                                     FaceVaryingInterpolation face_varying);
inline OpenSubdiv::Sdc::Options sdc_options(const Options& options) {
    return sdc_options(options.boundary, options.crease_method, options.face_varying);
}

// The mesh as the base level of a Far::TopologyRefiner (Sdc::SCHEME_LOOP, `sdc`), not yet refined: its triangles,
// crease edges and corners with their sharpness, holes, and its first face-varying layer, if it has one, as
// face-varying channel 0 (OpenSubdiv has no cones: cone tags are left out). Throws std::runtime_error when OpenSubdiv
// refuses the mesh.
std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> osd_topology_refiner(const MeshView& mesh,
                                                                       const OpenSubdiv::Sdc::Options& sdc);

}  // namespace loopsub::testing
