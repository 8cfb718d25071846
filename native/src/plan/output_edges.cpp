// The output's edges, read off the last split's numbering: the halves of each edge of the level before, and the
// three edges inside each of its faces, which the middle child's corners (the midpoints) name.
#include <algorithm>
#include <stdexcept>

#include "base/parallel.h"
#include "plan/plan_data.h"
#include "topology/triangle_corners.h"

namespace loopsub {

namespace {

void require_edges(const PlanImpl& p) {
    if (p.options.levels < 1) throw std::logic_error("output_edges: a plan of no levels has the input's edges");
    if (!p.holes.empty())
        throw std::logic_error("output_edges: the plan has holes, whose inner edges no triangle gives");
}

}  // namespace

int Plan::num_output_edges() const {
    require_edges(*impl_);
    return 2 * impl_->stencils[levels() - 1].num_edges + 3 * num_output_triangles() / 4;
}

void Plan::output_edges(std::int32_t* edge_vertices, std::int32_t* triangle_edges) const {
    require_edges(*impl_);
    // The level before: its edges' ends are read where it keeps them, as the kernels read them (a copy, as
    // level_edges makes, would be megabytes of fresh memory for one pass).
    const detail::LevelStencils& parent = impl_->stencils[levels() - 1];
    const Index nv = level_num_vertices(levels() - 1), ne = parent.num_edges;
    const Index nf = Index(num_output_triangles() / 4);
    const Index* children = output_triangles();
    // On the plan's threads: most of the time is the first touch of the two arrays' pages (23 MB at 1.3 million
    // triangles).
    detail::run_levels(std::max(1, impl_->options.threads), 1, [&](int, int part, int parts) {
        const auto [first_edge, end_edge] = detail::part_of(ne, part, parts);
        for (Index e = first_edge; e < end_edge; ++e) {
            Index ends[2];
            parent.edge_ends_of(e, ends);
            const Index midpoint = nv + e;
            Index* out = edge_vertices + 4 * std::size_t(e);
            out[0] = ends[0], out[1] = midpoint, out[2] = midpoint, out[3] = ends[1];
        }
        const auto [first_face, end_face] = detail::part_of(nf, part, parts);
        for (Index f = first_face; f < end_face; ++f) {
            const Index* middle = children + 3 * (4 * std::size_t(f) + 3);  // m_0, m_1, m_2
            const Index inner = 2 * ne + 3 * f;
            Index fe[3], fe_first_end[3];  // the parent edge of each midpoint, and its first end
            for (int k = 0; k < 3; ++k) {
                Index* out = edge_vertices + 2 * std::size_t(inner + k);
                out[0] = middle[k], out[1] = middle[detail::next_corner(k)];
                fe[k] = middle[k] - nv;
                Index ends[2];
                parent.edge_ends_of(fe[k], ends);
                fe_first_end[k] = ends[0];
            }
            // The half of the parent edge of midpoint k at its end v.
            auto half_at = [&](int k, Index v) { return 2 * fe[k] + Index(fe_first_end[k] != v); };
            for (int k = 0; k < 3; ++k) {  // corner child (v_k, m_k, m_k-1)
                const Index v = children[3 * (4 * std::size_t(f) + k)];
                Index* out = triangle_edges + 3 * (4 * std::size_t(f) + k);
                const int before = detail::prev_corner(k);
                out[0] = half_at(k, v), out[1] = inner + before, out[2] = half_at(before, v);
            }
            Index* out = triangle_edges + 3 * (4 * std::size_t(f) + 3);
            out[0] = inner, out[1] = inner + 1, out[2] = inner + 2;
        }
    });
}

}  // namespace loopsub
