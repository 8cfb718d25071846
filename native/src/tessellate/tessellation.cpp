// A Tessellation: the points of every input triangle's pattern (topology/tessellation_pattern.h), each placed on the
// limit surface. An input triangle that is a regular patch itself (level_patches.h) takes every point from the box
// spline of the input's own points, whatever its rates. The others go through plans of the levels their rates need,
// made on the mesh of those triangles and the triangles around their corners (all that shapes them): with L levels,
// 2^L at least their largest rate, no point lies inside a level-L triangle at an input vertex (where the surface is
// irregular) other than the vertex itself, so a point at a vertex of a level takes the limit plan's point and normal,
// and every other point a stencil over the level's control points, a box spline where its triangle is a regular patch
// and the refined neighbourhood's (local_refinement.h) where a semi-sharp edge or a non-manifold one leaves the
// triangle irregular.
//
// This file: the public API's constructor and queries. The build: tessellation_builder.h (its parts), kept_input.h
// (what depends on the mesh alone), tessellation_rates.h, tessellation_layers.cpp; the frame:
// tessellation_evaluate.cpp.
#include "loopsub/tessellation.h"

#include <algorithm>
#include <memory>
#include <string>

#include "tessellate/kept_input.h"
#include "tessellate/tessellation_builder.h"
#include "tessellate/tessellation_data.h"

namespace loopsub {

Tessellation::Tessellation(const MeshView& mesh, const Options& options, const TessellationRates& rates,
                           const InputTopology& reuse)
    : impl_(std::make_unique<TessellationImpl>()) {
    if (mesh.triangle_edges)
        detail::tessellation_fail("triangle_edges are not supported (edges are read by their ends)");
    impl_->threads = std::max(1, options.threads);
    impl_->patch_kernel = detail::kernel_functions(detail::resolve_kernel(options.kernel)).patch;
    MeshView surface = mesh;
    surface.face_varying = nullptr, surface.num_face_varying = 0;
    const InputTopologyParts* kept = reuse.parts_.get();
    detail::TessellationBuilder(*impl_, surface, options).build(rates, kept != nullptr ? kept->surface : nullptr);
    if (mesh.num_face_varying > 0) add_face_varying_layers(*impl_, mesh, options, rates, kept);
}

int Tessellation::num_face_varying_layers() const { return int(impl_->layers.size()); }

Tessellation::~Tessellation() = default;
Tessellation::Tessellation(Tessellation&&) noexcept = default;
Tessellation& Tessellation::operator=(Tessellation&&) noexcept = default;

int Tessellation::num_points() const { return int(impl_->num_points); }
std::uint64_t Tessellation::estimated_bytes() const { return impl_->estimated_bytes; }

InputTopology Tessellation::input_topology() const {
    auto parts = std::make_shared<InputTopologyParts>();
    parts->surface = impl_->input;
    for (const TessellationImpl::Layer& layer : impl_->layers)
        parts->layers.push_back(layer.surface ? layer.surface->input_topology() : InputTopology());
    InputTopology topology;
    topology.parts_ = std::move(parts);
    return topology;
}
int Tessellation::num_triangles() const { return int(impl_->triangles.size() / 3); }
const std::int32_t* Tessellation::triangles() const { return impl_->triangles.data(); }
const std::int32_t* Tessellation::parent_triangles() const { return impl_->parent_triangles.data(); }
int Tessellation::num_face_points() const { return int(impl_->samples.size()); }
const std::int32_t* Tessellation::corner_face_points() const { return impl_->corner_face_points.data(); }
const float* Tessellation::face_point_parameters() const { return impl_->parameters.data(); }
int Tessellation::levels() const { return impl_->levels; }
const std::vector<InputProblem>& Tessellation::notes() const { return impl_->input->plan->notes(); }

Tessellation::Edges Tessellation::output_edges() const {
    const auto& corners = impl_->triangles;
    const std::size_t num_points = std::size_t(impl_->num_points);
    // Each side of each triangle, under its smaller end: a side already there under that end is an edge found again.
    // A point's sides are few (its valence), so a bucket is searched linearly.
    std::vector<std::int32_t> bucket_first(num_points + 1, 0);
    auto lower_end = [&](std::size_t c) {
        const std::size_t face = c - c % 3;
        return std::min(corners[c], corners[face + (c + 1) % 3]);
    };
    for (std::size_t c = 0; c < corners.size(); ++c) ++bucket_first[std::size_t(lower_end(c)) + 1];
    for (std::size_t p = 0; p < num_points; ++p) bucket_first[p + 1] += bucket_first[p];
    std::vector<std::int32_t> bucket_size(num_points, 0), bucket_edges(corners.size());
    Edges out;
    out.triangle_edges.resize(corners.size());
    out.edge_vertices.reserve(corners.size());  // closed: 1.5 edges a triangle; open: up to 3
    for (std::size_t c = 0; c < corners.size(); ++c) {
        const std::size_t face = c - c % 3;
        const std::int32_t a = corners[c], b = corners[face + (c + 1) % 3];
        const std::size_t low = std::size_t(std::min(a, b));
        const std::int32_t high = std::max(a, b);
        const std::int32_t* first = &bucket_edges[std::size_t(bucket_first[low])];
        const std::int32_t* last = first + bucket_size[low];
        // Every edge in the bucket has `low` as an end; the one whose other end is `high` is this side's.
        const std::int32_t* found = std::find_if(first, last, [&](std::int32_t e) {
            return out.edge_vertices[2 * std::size_t(e)] == high || out.edge_vertices[2 * std::size_t(e) + 1] == high;
        });
        if (found == last) {  // a new edge, appended to the bucket (at `last`)
            bucket_edges[std::size_t(bucket_first[low]) + std::size_t(bucket_size[low]++)] =
                std::int32_t(out.edge_vertices.size() / 2);
            out.edge_vertices.push_back(a), out.edge_vertices.push_back(b);
        }
        out.triangle_edges[c] = *found;
    }
    return out;
}

}  // namespace loopsub
