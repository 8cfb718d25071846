#include "plan/validation.h"

#include <cmath>
#include <string>

#include "base/common.h"

namespace loopsub::detail {

void validate_options(const Options& options) {
    if (options.levels < 0 || options.levels > kMaxLevels)
        fail("levels must be between 0 and " + std::to_string(kMaxLevels) + ", got " + std::to_string(options.levels));
    if (options.threads < 1 || options.threads > kMaxThreads)
        fail("threads must be between 1 and " + std::to_string(kMaxThreads) + ", got " +
             std::to_string(options.threads));
    if (!finite_non_negative(options.crease_threshold))
        fail("crease threshold must be a finite number >= 0, got " + std::to_string(options.crease_threshold));
}

void validate_view(const MeshView& mesh) {
    if (mesh.num_vertices < 0 || mesh.num_triangles < 0 || mesh.num_crease_edges < 0 || mesh.num_corners < 0 ||
        mesh.num_cones < 0 || mesh.num_face_varying < 0 || mesh.num_holes < 0)
        fail("negative element count");
    auto require = [](const void* pointer, int count, const char* what) {
        if (count > 0 && pointer == nullptr)
            fail(std::string(what) + " is missing (null) but its count is " + std::to_string(count));
    };
    require(mesh.triangles, mesh.num_triangles, "triangles");
    require(mesh.crease_edges, mesh.num_crease_edges, "crease edges");
    require(mesh.crease_sharpness, mesh.num_crease_edges, "crease sharpness");
    require(mesh.corner_vertices, mesh.num_corners, "corner vertices");
    require(mesh.corner_sharpness, mesh.num_corners, "corner sharpness");
    require(mesh.cone_vertices, mesh.num_cones, "cone vertices");
    require(mesh.face_varying, mesh.num_face_varying, "face-varying layers");
    require(mesh.hole_triangles, mesh.num_holes, "hole triangles");
    if (mesh.triangle_edges && mesh.num_face_varying > 0)
        fail("triangle edges are given with face-varying layers, which are read by their values' ends");
    for (int k = 0; k < mesh.num_face_varying; ++k) {
        const FaceVaryingLayer& layer = mesh.face_varying[k];
        const std::string name = "face-varying layer " + std::to_string(k);
        if (layer.num_values < 0)
            fail(name + " has a negative number of values (" + std::to_string(layer.num_values) + ")");
        if (layer.corner_values == nullptr && mesh.num_triangles > 0) fail(name + " has no (null) corner values");
    }
}

void validate_mesh(const MeshView& mesh) {
    validate_view(mesh);
    check_mesh(mesh, ThrowFirst{});
}

void validate_vertex_values(ChannelsView<const float> in, int num_vertices, float largest, int summed_terms,
                            Element element, int layer) {
    check_values(in, num_vertices, element, layer, largest, summed_terms, ThrowFirst{});
}

void validate_face_varying_values(const float* in, std::size_t num_triangles, int num_channels) {
    check_corner_values(in, num_triangles, num_channels, -1, ThrowFirst{"evaluate_face_varying: "});
}

}  // namespace loopsub::detail
