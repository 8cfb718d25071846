#include "support/osd_adapter.h"

#include <cstddef>
#include <stdexcept>
#include <vector>

#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

namespace loopsub::testing {

using namespace OpenSubdiv;

Sdc::Options sdc_options(Boundary boundary, CreaseMethod crease_method, FaceVaryingInterpolation face_varying) {
    Sdc::Options sdc;
    sdc.SetVtxBoundaryInterpolation(boundary == Boundary::EdgesAndCorners ? Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER
                                    : boundary == Boundary::None          ? Sdc::Options::VTX_BOUNDARY_NONE
                                                                          : Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    sdc.SetCreasingMethod(crease_method == CreaseMethod::Chaikin ? Sdc::Options::CREASE_CHAIKIN
                                                                 : Sdc::Options::CREASE_UNIFORM);
    // FaceVaryingInterpolation is declared in OpenSubdiv's order.
    sdc.SetFVarLinearInterpolation(Sdc::Options::FVarLinearInterpolation(int(face_varying)));
    return sdc;
}

std::unique_ptr<Far::TopologyRefiner> osd_topology_refiner(const MeshView& mesh, const Sdc::Options& sdc) {
    const std::vector<int> vertices_per_face(std::size_t(mesh.num_triangles), 3);
    Far::TopologyDescriptor desc;
    desc.numVertices = mesh.num_vertices;
    desc.numFaces = mesh.num_triangles;
    desc.numVertsPerFace = vertices_per_face.data();
    desc.vertIndicesPerFace = mesh.triangles;
    desc.numCreases = mesh.num_crease_edges;
    desc.creaseVertexIndexPairs = mesh.crease_edges;
    desc.creaseWeights = mesh.crease_sharpness;
    desc.numCorners = mesh.num_corners;
    desc.cornerVertexIndices = mesh.corner_vertices;
    desc.cornerWeights = mesh.corner_sharpness;
    desc.numHoles = mesh.num_holes;
    desc.holeIndices = mesh.hole_triangles;
    Far::TopologyDescriptor::FVarChannel channel;
    if (mesh.num_face_varying > 0) {
        channel.numValues = mesh.face_varying[0].num_values;
        channel.valueIndices = mesh.face_varying[0].corner_values;
        desc.numFVarChannels = 1;
        desc.fvarChannels = &channel;
    }
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    std::unique_ptr<Far::TopologyRefiner> refiner(Factory::Create(desc, Factory::Options(Sdc::SCHEME_LOOP, sdc)));
    if (!refiner) throw std::runtime_error("OpenSubdiv refused the mesh");
    return refiner;
}

}  // namespace loopsub::testing
