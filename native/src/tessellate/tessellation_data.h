// What a Tessellation holds (TessellationImpl), shared by the files that build it (tessellation_builder.h and its
// parts, tessellation_layers.cpp) and those that read it (tessellation.cpp, tessellation_evaluate.cpp).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "base/large_allocator.h"
#include "kernels/kernels.h"
#include "loopsub/tessellation.h"

namespace loopsub {

struct KeptInput;
struct InputTopologyParts;

struct TessellationImpl {
    std::shared_ptr<const KeptInput> input;  // what the build read of the mesh alone (InputTopology)
    int levels = 0;
    int threads = 1;
    int num_input_vertices = 0;
    std::int64_t num_points = 0;
    // The result's arrays, tens of megabytes at high rates: sized once (reserved from the first pass's counts) in huge
    // pages and written once, without being zeroed first (LargeVector), which a one-shot job (the CLI) paid for in
    // page faults and passes over memory.
    detail::LargeVector<std::int32_t> triangles, parent_triangles, corner_face_points;
    detail::LargeVector<float> parameters;  // (u, v) per face point
    // A sample per face point, the normals' rows. In a triangle that is a patch of the input, its triangle's blocks
    // of weights (below) say everything. Elsewhere: at a vertex of the level, the limit plan's point and normal row;
    // in a regular patch of the level, the patch and the weights at its place there; else a stencil of its own.
    enum class Kind : std::uint8_t { Vertex, Patch, Stencil, InputPatch };
    struct Sample {
        Kind kind;
        std::uint8_t band;  // Vertex, Patch, Stencil: whose plans (below)
        std::int32_t a, b;  // Vertex: vertex, normal row; Patch: patch, weights; Stencil: stencil; InputPatch: none
    };
    detail::LargeVector<Sample> samples;
    detail::LargeVector<std::int32_t> sample_point;  // the point a sample places, -1 where an earlier sample places it
    // Per input triangle: its first sample (and one more), and its patch among input_patch_points (-1: through the
    // plans, on the submesh) with the blocks of weights of its points (kernels.h, PatchFn), one per part of its
    // pattern: its corners, each edge's points, its inner points (-1: none).
    static constexpr int kParts = 5;
    static constexpr int kInnerPart = kParts - 1;  // a triangle's own points, numbered one after the other
    std::vector<std::int32_t> face_first_sample, face_patch, face_blocks;
    std::vector<std::int32_t> input_patch_points;  // 12 per patch of the input's own points
    // The input's vertices of no triangle with a surface (loose, or of triangles without one): their input positions.
    std::vector<std::int32_t> lone_vertices;
    // A block per part of a pattern, its rate and its patch's shape, shared by every triangle that has the same: its
    // samples, its stride and where its weights start.
    struct Block {
        int count, stride;
        std::size_t first;
    };
    std::vector<Block> blocks;
    std::vector<float> block_weights;
    detail::PatchFn patch_kernel = nullptr;
    // The input triangles that are no patch themselves, in bands by the levels their rates need: each band's plans
    // (control points and limit) on the mesh of its triangles and those around their corners, whose vertices are the
    // input's `vertices`.
    struct Band {
        int levels = 0, limit_levels = 0;
        std::vector<std::int32_t> vertices;
        std::unique_ptr<Plan> control, limit;
        mutable std::vector<float> positions, control_points, limit_points, limit_normals;
    };
    std::vector<Band> bands;
    std::vector<std::int32_t> patch_points;  // 12 per patch (phantoms -1, weighted 0)
    std::vector<float> patch_weights;        // 36 per weight set: position, d/ds, d/dt of each of 12 points
    std::vector<std::int64_t> stencil_offsets{0};
    std::vector<std::int32_t> stencil_points;
    std::vector<float> stencil_weights;  // position, d/ds, d/dt per entry
    // Face-varying layers: each its input level as a mesh of its own, cut by the same rates, whose face points are
    // this tessellation's one for one; or (FaceVaryingInterpolation::All) linear in each triangle, from the caller's
    // value at each input corner.
    struct Layer {
        int num_values = 0;
        std::vector<std::int32_t> base_values;       // per vertex of the layer's mesh: the caller's value
        std::unique_ptr<Tessellation> surface;       // none: linear
        std::vector<std::int32_t> face_point_point;  // the surface's point at each face point
        std::vector<std::int32_t> corner_values;     // linear: the caller's value at each input corner
    };
    std::vector<Layer> layers;
    std::vector<std::int32_t> face_point_parent;  // each face point's input triangle (the linear layers read it)
    std::uint64_t estimated_bytes = 0;            // Tessellation::estimated_bytes
};

// Cuts the face-varying layers of `mesh` as the surface of `d` is cut (tessellation_layers.cpp).
void add_face_varying_layers(TessellationImpl& d, const MeshView& mesh, const Options& options,
                             const TessellationRates& rates, const InputTopologyParts* reuse);

namespace detail {

[[noreturn]] inline void tessellation_fail(const std::string& message) { throw InputError("tessellation: " + message); }

}  // namespace detail
}  // namespace loopsub
