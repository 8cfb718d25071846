#include "plan/validation.h"

#include <cmath>
#include <string>

#include "base/common.h"
#include "topology/topology.h"

namespace loopsub::detail {

namespace {

bool finite_non_negative(float value) { return std::isfinite(value) && value >= 0.0f; }

}  // namespace

void validate_options(const Options& options) {
    if (options.levels < 0 || options.levels > kMaxLevels)
        fail("levels must be between 0 and " + std::to_string(kMaxLevels) + ", got " + std::to_string(options.levels));
    if (options.threads < 1 || options.threads > kMaxThreads)
        fail("threads must be between 1 and " + std::to_string(kMaxThreads) + ", got " +
             std::to_string(options.threads));
    if (!finite_non_negative(options.crease_threshold))
        fail("crease threshold must be a finite number >= 0, got " + std::to_string(options.crease_threshold));
}

void validate_mesh(const MeshView& mesh) {
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
    for (int k = 0; k < mesh.num_holes; ++k)
        if (mesh.hole_triangles[k] < 0 || mesh.hole_triangles[k] >= mesh.num_triangles)
            fail("hole " + std::to_string(k) + " refers to triangle " + std::to_string(mesh.hole_triangles[k]) +
                 ", outside 0.." + std::to_string(mesh.num_triangles - 1));

    // `what` and `which` name the element only once it fails: building the name for every triangle cost more than the
    // checks.
    auto check_index = [&](Index v, const char* what, int which) {
        if (v < 0 || v >= mesh.num_vertices)
            fail(std::string(what) + " " + std::to_string(which) + " refers to vertex " + std::to_string(v) +
                 ", outside 0.." + std::to_string(mesh.num_vertices - 1) + " (the mesh has " +
                 std::to_string(mesh.num_vertices) + " vertices)");
    };
    for (int f = 0; f < mesh.num_triangles; ++f) {
        const Index* v = mesh.triangles + 3 * std::size_t(f);
        for (int k = 0; k < 3; ++k) check_index(v[k], "triangle", f);
        if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0])
            fail("triangle " + std::to_string(f) + " is degenerate: it repeats a vertex (" + std::to_string(v[0]) +
                 ", " + std::to_string(v[1]) + ", " + std::to_string(v[2]) + ")");
    }
    for (int k = 0; k < mesh.num_crease_edges; ++k) {
        check_index(mesh.crease_edges[2 * k], "crease edge", k);
        check_index(mesh.crease_edges[2 * k + 1], "crease edge", k);
        if (!finite_non_negative(mesh.crease_sharpness[k]))
            fail("crease edge " + std::to_string(k) + " has sharpness " + std::to_string(mesh.crease_sharpness[k]) +
                 "; it must be a finite number >= 0");
    }
    for (int k = 0; k < mesh.num_corners; ++k) {
        check_index(mesh.corner_vertices[k], "corner", k);
        if (!finite_non_negative(mesh.corner_sharpness[k]))
            fail("corner " + std::to_string(k) + " has sharpness " + std::to_string(mesh.corner_sharpness[k]) +
                 "; it must be a finite number >= 0");
    }
    for (int k = 0; k < mesh.num_cones; ++k) check_index(mesh.cone_vertices[k], "cone", k);
}

void validate_vertex_values(ChannelsView<const float> in, int num_vertices, float largest, int summed_terms,
                            const char* element) {
    for (int v = 0; v < num_vertices; ++v)
        for (int c = 0; c < in.num_channels; ++c) {
            const float value = in.data[c * in.channel_stride + std::size_t(v) * in.element_stride];
            if (!std::isfinite(value))
                fail(element + (" " + std::to_string(v)) + " has a non-finite value (" + std::to_string(value) +
                     ") in channel " + std::to_string(c));
            if (std::fabs(value) > largest)
                fail(element + (" " + std::to_string(v)) + " has a value too large to refine (" + shortest(value) +
                     ") in channel " + std::to_string(c) + ": sums of up to " + std::to_string(summed_terms) +
                     " values must stay finite, so values are limited to +-" + shortest(largest));
        }
}

void validate_face_varying_values(const float* in, std::size_t num_triangles, int num_channels) {
    const std::size_t corner = std::size_t(num_channels), face = 3 * corner;
    for (std::size_t i = 0; i < face * num_triangles; ++i)
        if (!std::isfinite(in[i]))
            fail("evaluate_face_varying: triangle " + std::to_string(i / face) + ", corner " +
                 std::to_string(i % face / corner) + " has a non-finite value (" + shortest(in[i]) + ") in channel " +
                 std::to_string(i % corner));
}

}  // namespace loopsub::detail
