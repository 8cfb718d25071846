// The output's edges, read off the last split's numbering: the halves of each edge of the level before, and the
// three edges inside each of its faces, which the middle child's corners (the midpoints) name; and the input edge each
// lies on, down the same numbering from the input's.
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

void Plan::output_edges(std::int32_t* edge_vertices, std::int32_t* triangle_edges, std::int32_t* triangles) const {
    require_edges(*impl_);
    // The level before: its edges' ends are read where it keeps them, as the kernels read them (a copy, as
    // level_edges makes, would be megabytes of fresh memory for one pass).
    const detail::LevelStencils& parent = impl_->stencils[levels() - 1];
    const Index nv = level_num_vertices(levels() - 1), ne = parent.num_edges;
    const Index nf = Index(num_output_triangles() / 4);
    const Index* children = output_triangles();
    // On the plan's threads: most of the time is the first touch of the arrays' pages (23 MB at 1.3 million triangles,
    // 38 MB with the triangles).
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
            if (triangles) std::copy_n(children + 12 * std::size_t(f), 12, triangles + 12 * std::size_t(f));
        }
    });
}

void Plan::output_edge_parents(const std::int32_t* side_edges, std::int32_t* parents) const {
    require_edges(*impl_);
    const PlanImpl& p = *impl_;
    // An input edge takes the greatest number its triangles' sides give it: a real edge's over a diagonal's -1.
    std::vector<Index> labels(std::size_t(p.stencils[0].num_edges), -1), next;
    for (std::size_t c = 0; c < p.input_triangle_edges.size(); ++c) {
        Index& label = labels[std::size_t(p.input_triangle_edges[c])];
        label = std::max(label, side_edges[c]);
    }
    // Down the levels by the split's numbering: both halves of edge e keep its number, the edges inside faces get -1.
    for (int level = 0; level < levels(); ++level) {
        const Index edges = p.stencils[std::size_t(level)].num_edges;
        const Index faces = Index(std::size_t(p.num_input_triangles) << (2 * level));
        const bool last = level + 1 == levels();
        if (!last) next.resize(2 * std::size_t(edges) + 3 * std::size_t(faces));
        Index* out = last ? parents : next.data();
        detail::run_levels(std::max(1, p.options.threads), 1, [&](int, int part, int parts) {
            const auto [first_edge, end_edge] = detail::part_of(edges, part, parts);
            for (Index e = first_edge; e < end_edge; ++e)
                out[2 * std::size_t(e)] = out[2 * std::size_t(e) + 1] = labels[std::size_t(e)];
            const auto [first_face, end_face] = detail::part_of(faces, part, parts);
            std::fill(out + 2 * std::size_t(edges) + 3 * std::size_t(first_face),
                      out + 2 * std::size_t(edges) + 3 * std::size_t(end_face), Index(-1));
        });
        labels.swap(next);
    }
}

}  // namespace loopsub
