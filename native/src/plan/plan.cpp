// The Plan's API, answered from what the builder left (PlanImpl, plan_data.h; building: plan_builder.cpp, the
// per-frame work: evaluate.cpp).
#include <algorithm>
#include <stdexcept>
#include <string>

#include "plan/budget.h"
#include "plan/plan_builder.h"

namespace loopsub {

using detail::estimate_for_counts;
using detail::LevelCounts;

PlanImpl::PlanImpl(const Options& plan_options) : options(plan_options) {
    copies.level_edges.resize(std::size_t(std::max(options.levels, 0)));
    copies.level_edges_ready = std::vector<std::once_flag>(copies.level_edges.size());
    copies.level_vertex_types.resize(std::size_t(std::max(options.levels, 0)) + 1);
    copies.level_vertex_types_ready = std::vector<std::once_flag>(copies.level_vertex_types.size());
}

Plan::Plan(const MeshView& mesh, const Options& options) : impl_(detail::PlanBuilder::build(mesh, options)) {}
Plan::~Plan() = default;
Plan::Plan(Plan&&) noexcept = default;
Plan& Plan::operator=(Plan&&) noexcept = default;

const Options& Plan::options() const { return impl_->options; }
int Plan::levels() const { return impl_->options.levels; }
int Plan::num_input_vertices() const { return impl_->num_input_vertices; }
int Plan::num_output_vertices() const { return impl_->level_num_vertices.back(); }
int Plan::num_output_triangles() const { return int(impl_->output_triangles.size() / 3); }
const std::int32_t* Plan::output_triangles() const { return impl_->output_triangles.data(); }

namespace {
const detail::LimitTables& limit_tables(const PlanImpl& p, const char* what) {
    if (!p.limit)
        throw std::logic_error(
            std::string(what) +
            ": the limit normals are the limit surface's; build the plan with Options::limit_surface");
    return *p.limit;
}
}  // namespace

int Plan::num_limit_normals() const {
    return num_output_vertices() + limit_tables(*impl_, "num_limit_normals").num_side_rows;
}
const std::int32_t* Plan::corner_normal_indices() const {
    const PlanImpl& p = *impl_;
    const detail::LimitTables& lt = limit_tables(p, "corner_normal_indices");
    detail::LargeVector<Index>& indices = p.copies.corner_normals;
    std::call_once(p.copies.corner_normals_ready, [&] {
        indices.assign(p.output_triangles.begin(), p.output_triangles.end());
        for (const auto& [corner, row] : lt.corner_sides) indices[std::size_t(corner)] = row;
    });
    return indices.data();
}
const std::int32_t* Plan::output_parent_triangles() const {
    const PlanImpl& p = *impl_;
    detail::LargeVector<Index>& parents = p.copies.output_parents;
    std::call_once(p.copies.output_parents_ready, [&p, &parents] {
        // Child triangle 4f + k of a level has parent f, so a level-L triangle descends from input triangle t / 4^L.
        parents.resize(p.output_triangles.size() / 3);
        const bool holes = !p.holes.empty();
        for (std::size_t t = 0; t < parents.size(); ++t)
            parents[t] = Index(std::size_t(holes ? p.kept_triangles[t] : Index(t)) >> (2 * p.options.levels));
    });
    return parents.data();
}
const std::vector<std::int32_t>& Plan::output_crease_edges() const { return impl_->output_tags.crease_edges; }
const std::vector<float>& Plan::output_crease_sharpness() const { return impl_->output_tags.crease_sharpness; }
const std::vector<std::int32_t>& Plan::output_corner_vertices() const { return impl_->output_tags.corner_vertices; }
const std::vector<float>& Plan::output_corner_sharpness() const { return impl_->output_tags.corner_sharpness; }
const std::vector<std::int32_t>& Plan::output_sharp_edges() const { return impl_->output_tags.sharp_edges; }
const std::vector<float>& Plan::output_sharp_edge_sharpness() const { return impl_->output_tags.sharp_edge_sharpness; }
const std::vector<std::int32_t>& Plan::output_crease_edge_indices() const {
    return impl_->output_tags.crease_edge_indices;
}
const std::vector<std::int32_t>& Plan::output_sharp_edge_indices() const {
    return impl_->output_tags.sharp_edge_indices;
}
Kernel Plan::kernel() const { return impl_->kernel; }
double Plan::topology_ms() const { return impl_->topology_ms; }
const std::vector<InputProblem>& Plan::notes() const { return impl_->notes; }
double Plan::last_evaluate_ms() const { return impl_->frame.evaluate_ms; }

const std::vector<std::int32_t>& Plan::level_edges(int level) const {
    if (level < 0 || level >= levels())
        throw std::out_of_range("level_edges: level " + std::to_string(level) + " is not in 0.." +
                                std::to_string(levels() - 1));
    const PlanImpl& p = *impl_;
    std::vector<Index>& edges = p.copies.level_edges[level];
    std::call_once(p.copies.level_edges_ready[level], [&p, &edges, level] {
        const detail::LevelStencils& s = p.stencils[level];
        if (!s.derived_from && !s.interior) {
            edges.assign(s.edge_ends.begin(), s.edge_ends.end());
            return;
        }
        edges.resize(2 * std::size_t(s.num_edges));
        for (Index e = 0; e < s.num_edges; ++e) s.edge_ends_of(e, &edges[2 * std::size_t(e)]);
    });
    return edges;
}
int Plan::level_num_vertices(int level) const {
    if (level < 0 || level > levels())
        throw std::out_of_range("level_num_vertices: level " + std::to_string(level) + " is not in 0.." +
                                std::to_string(levels()));
    return impl_->level_num_vertices[level];
}
const std::vector<VertexType>& Plan::level_vertex_types(int level) const {
    const PlanImpl& p = *impl_;
    const int last = p.options.levels > 0 || p.options.limit_surface ? p.options.levels : -1;
    if (level < 0 || level > last)
        throw std::out_of_range("level_vertex_types: level " + std::to_string(level) + " is not in 0.." +
                                std::to_string(last));
    std::vector<VertexType>& copy = p.copies.level_vertex_types[level];
    std::call_once(p.copies.level_vertex_types_ready[level], [&p, &copy, level] {
        if (level < int(p.level_vertex_types.size())) {
            copy.assign(p.level_vertex_types[level].begin(), p.level_vertex_types[level].end());
            return;
        }
        copy.assign(std::size_t(p.level_num_vertices.back()), VertexType::Smooth);
        for (const auto& [v, type] : p.last_level_types) copy[std::size_t(v)] = type;
    });
    return copy;
}

std::uint64_t Plan::estimate_bytes(int num_vertices, int num_triangles, int levels, int num_channels,
                                   std::int64_t num_edges) {
    const std::uint64_t triangles = std::uint64_t(std::max(num_triangles, 0));
    const LevelCounts counts{std::uint64_t(std::max(num_vertices, 0)),
                             num_edges < 0 ? triangles * 3 / 2 : std::uint64_t(num_edges), triangles};
    return estimate_for_counts(counts, levels, num_channels);
}

}  // namespace loopsub
