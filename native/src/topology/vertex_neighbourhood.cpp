// VertexNeighbourhood: the connectivity around single vertices and edges of a level, read where the level stores it
// and otherwise derived from its parent through the split's numbering (topology.h), the parent itself stored or so
// derived in turn. The derivations are written once, for any parent P that answers StoredLevel's calls
// (level_relations.h); this file holds those only it needs: an edge's faces and wings, a vertex's edges and fan. The
// plan builder classifies the few vertices next to features through it, on levels it never stores.
#include <algorithm>
#include <cassert>
#include <cstddef>
#include <vector>

#include "topology/level_relations.h"
#include "topology/topology.h"
#include "topology/triangle_corners.h"

namespace loopsub::detail {

namespace {

// Where parent edge e sits in parent face f, and whether the face's corner there is the edge's first vertex `a`.
template <typename P>
void edge_in_face(const P& p, Index f, Index e, Index a, Index fe[3], int& local, bool& a_first) {
    Index fv[3];
    p.face(f, fv, fe);
    local = local_edge(fe, e);
    a_first = fv[local] == a;
}

// The faces of child edge e, in refine_topology's order: per face of a half's parent edge the corner child at the
// half's end; inside a parent face the corner child, then the middle child.
template <typename P, typename Visit>
void for_each_child_edge_face(const P& p, Index e, const Visit& visit) {
    const Index halves = 2 * p.num_edges();
    if (e >= halves) {
        const Index f = (e - halves) / 3;
        visit(4 * f + next_corner(int((e - halves) % 3)));
        visit(4 * f + 3);
        return;
    }
    const Index h = e / 2;
    Index ends[2], fe[3];
    p.edge_ends(h, ends);
    p.for_each_edge_face(h, [&](Index f) {
        int local;
        bool a_first;
        edge_in_face(p, f, h, ends[0], fe, local, a_first);
        visit(4 * f + ((e % 2 == 0) == a_first ? local : next_corner(local)));
    });
}

// The wings of child edge e (VertexNeighbourhood::wings), from any parent.
template <typename P>
void child_wings_of(const P& p, Index e, Index& c, Index& d) {
    const Index nv = p.num_vertices(), halves = 2 * p.num_edges();
    Index fe[3];
    if (e >= halves) {
        const Index f = (e - halves) / 3;
        Index fv[3], abcd[4];
        p.face(f, fv, fe);
        face_interior_edge(nv, fv, fe, int((e - halves) % 3), abcd);
        c = abcd[2], d = abcd[3];
        return;
    }
    // As half_edge_wings: a missing face repeats the half's ends.
    const Index h = e / 2, m = nv + h;
    Index ends[2];
    p.edge_ends(h, ends);
    Index at_a[2] = {ends[0], m}, at_b[2] = {m, ends[1]};
    int face = 0;
    p.for_each_edge_face(h, [&](Index f) {
        if (face == 2) return;
        int local;
        bool a_first;
        edge_in_face(p, f, h, ends[0], fe, local, a_first);
        face_wings(nv, fe, local, a_first, at_a[face], at_b[face]);
        ++face;
    });
    c = e % 2 == 0 ? at_a[0] : at_b[0];
    d = e % 2 == 0 ? at_a[1] : at_b[1];
}

// The edges of child vertex v in refine_topology's vertex_edges order: an old vertex's halves of its parent edges; a
// midpoint's two halves, then per face of its edge the two interior edges that meet it (midpoint_face_edges).
template <typename P>
void child_vertex_edges_of(const P& p, Index v, std::vector<Index>& out) {
    const Index nv = p.num_vertices(), interior_base = 2 * p.num_edges();
    if (v < nv) {
        p.edges(v, out);
        for (Index& e : out) e = child_edge_at_of(p, e, v);
        return;
    }
    const Index e = v - nv;
    Index ends[2], fe[3];
    p.edge_ends(e, ends);
    out.resize(2 + 2 * std::size_t(p.edge_face_count(e)));
    out[0] = 2 * e, out[1] = 2 * e + 1;
    Index* next = &out[2];
    p.for_each_edge_face(e, [&](Index f) {
        int local;
        bool a_first;
        edge_in_face(p, f, e, ends[0], fe, local, a_first);
        midpoint_face_edges(interior_base, f, local, a_first, next);
        next += 2;
    });
}

// The fan of v, unsorted: each face at v starts exactly one of its edges there, found through that edge, once.
void StoredLevel::fan(Index v, std::vector<FanCorner>& out) const {
    out.clear();
    for (Index i = t.vertex_edge_offsets[v]; i < t.vertex_edge_offsets[v + 1]; ++i) {
        const Index e = t.vertex_edges[i];
        for_each_edge_face(e, [&](Index f) {
            const Index* fv = &t.face_vertices[3 * std::size_t(f)];
            const Index* fe = &t.face_edges[3 * std::size_t(f)];
            const int k = local_edge(fe, e), before = prev_corner(k);
            if (fv[k] != v) return;
            const Index edge_a = fe[k], edge_b = fe[before];
            out.push_back({3 * f + k, fv[next_corner(k)], fv[before], edge_a, edge_b,
                           t.edge_vertices[2 * std::size_t(edge_a)] == v,
                           t.edge_vertices[2 * std::size_t(edge_b)] == v});
        });
    }
}

// The fan of child vertex v, in the parent's order for an old vertex (corner 0 of corner child k of each parent face
// whose corner k it is, between the midpoints of the face's edges at it); per face of its edge (edge j there) for the
// midpoint of edge e: corner 1 of corner child j, corner 2 of corner child j + 1, corner j of the middle child.
template <typename P>
void child_fan_of(const P& p, Index v, std::vector<FanCorner>& out) {
    const Index nv = p.num_vertices();
    if (v < nv) {
        p.fan(v, out);
        for (FanCorner& c : out) {
            const Index f = c.corner / 3, k = c.corner % 3;
            c.corner = 3 * (4 * f + k);
            c.a = nv + c.edge_a, c.b = nv + c.edge_b;  // the midpoints of the edges, which the halves at v join
            c.edge_a = 2 * c.edge_a + !c.v_first_a, c.edge_b = 2 * c.edge_b + !c.v_first_b;
        }
        return;
    }
    out.clear();
    const Index e = v - nv, halves = 2 * p.num_edges();
    Index ends[2];
    p.edge_ends(e, ends);
    p.for_each_edge_face(e, [&](Index f) {
        Index fv[3], fe[3];
        p.face(f, fv, fe);
        const int j = local_edge(fe, e);
        const bool a_first = fv[j] == ends[0];
        const int next = next_corner(j), before = prev_corner(j);
        // The halves of e at v_j and at v_j+1; v is the first end of half 2e + 1 and of interior edge j.
        const Index half_at_j = 2 * e + !a_first, half_at_next = 2 * e + a_first, interior = halves + 3 * f;
        out.push_back({3 * (4 * f + j) + 1, nv + fe[before], fv[j], interior + before, half_at_j, false, !a_first});
        out.push_back({3 * (4 * f + next) + 2, fv[next], nv + fe[next], half_at_next, interior + j, a_first, true});
        out.push_back(
            {3 * (4 * f + 3) + j, nv + fe[next], nv + fe[before], interior + j, interior + before, true, false});
    });
}

}  // namespace

template <typename Derive>
decltype(auto) VertexNeighbourhood::through_parent(const Derive& derive) const {
    if (parent_) return derive(StoredLevel{*parent_});
    return derive(*derived_parent_);
}

VertexNeighbourhood::VertexNeighbourhood(const Topology* level, const Topology* parent,
                                         const VertexNeighbourhood* derived_parent, int num_vertices,
                                         const std::vector<int>* history, const Topology* base)
    : level_(level),
      parent_(parent),
      derived_parent_(derived_parent),
      num_vertices_(num_vertices),
      history_(history && !history->empty() && history->back() == num_vertices ? history : nullptr),
      base_(history_ && base && base->num_vertices == history_->front() ? base : nullptr) {
    // Counted once: the derivations ask for the parent's counts at every step.
    num_edges_ = level_ ? level_->num_edges()
                        : through_parent([](const auto& p) { return 2 * p.num_edges() + 3 * p.num_faces(); });
    num_faces_ = level_ ? level_->num_faces() : through_parent([](const auto& p) { return 4 * p.num_faces(); });
}

VertexNeighbourhood::VertexNeighbourhood(const Topology& level, const Topology* parent_if_derived,
                                         const std::vector<int>* history, const Topology* base)
    : VertexNeighbourhood(parent_if_derived ? nullptr : &level, parent_if_derived, nullptr, level.num_vertices, history,
                          base) {}

VertexNeighbourhood::VertexNeighbourhood(int num_vertices, const Topology& parent, const std::vector<int>* history,
                                         const Topology* base)
    : VertexNeighbourhood(nullptr, &parent, nullptr, num_vertices, history, base) {}

VertexNeighbourhood::VertexNeighbourhood(int num_vertices, const VertexNeighbourhood& parent,
                                         const std::vector<int>* history, const Topology* base)
    : VertexNeighbourhood(nullptr, nullptr, &parent, num_vertices, history, base) {}

int VertexNeighbourhood::max_valence() const {
    if (level_) return level_->max_valence;
    return through_parent([](const auto& p) { return child_max_valence_of(p); });
}

int VertexNeighbourhood::max_edge_face_count() const {
    if (level_) return level_->max_edge_face_count;
    return through_parent([](const auto& p) { return child_max_edge_face_count_of(p); });
}

void VertexNeighbourhood::derived_edge_ends(Index e, Index ends[2]) const {
    through_parent([&](const auto& p) { child_edge_ends_of(p, e, ends); });
}

void VertexNeighbourhood::visit_edge_faces(Index e, void (*visit)(const void* context, Index f),
                                           const void* context) const {
    auto each = [visit, context](Index f) { visit(context, f); };
    if (level_) return StoredLevel{*level_}.for_each_edge_face(e, each);
    through_parent([&](const auto& p) { for_each_child_edge_face(p, e, each); });
}

void VertexNeighbourhood::wings(Index e, Index& c, Index& d) const {
    if (level_) {
        c = level_->edge_wing_c[e], d = level_->edge_wing_d[e];
        return;
    }
    through_parent([&](const auto& p) { child_wings_of(p, e, c, d); });
}

void VertexNeighbourhood::face(Index f, Index vertices[3], Index edges[3]) const {
    if (level_) return StoredLevel{*level_}.face(f, vertices, edges);
    through_parent([&](const auto& p) { child_face_of(p, f, vertices, edges); });
}

void VertexNeighbourhood::face_edges(Index f, Index edges[3]) const {
    Index vertices[3];
    face(f, vertices, edges);
}

void VertexNeighbourhood::face_vertices(Index f, Index vertices[3]) const {
    if (level_) return StoredLevel{*level_}.face_vertices(f, vertices);
    through_parent([&](const auto& p) { child_face_of(p, f, vertices, nullptr); });
}

void VertexNeighbourhood::fan(Index v, std::vector<FanCorner>& out) const {
    if (level_) StoredLevel{*level_}.fan(v, out);
    else through_parent([&](const auto& p) { child_fan_of(p, v, out); });
    std::sort(out.begin(), out.end(), [](const FanCorner& x, const FanCorner& y) { return x.corner < y.corner; });
}

void VertexNeighbourhood::edges(Index v, std::vector<Index>& out) const {
    if (level_) return StoredLevel{*level_}.edges(v, out);
    // Sized once and written in place: the vertices next to creases ask for theirs one by one.
    through_parent([&](const auto& p) { child_vertex_edges_of(p, v, out); });
}

int VertexNeighbourhood::faces_between(Index v, Index from, Index to) const {
    // A vertex made on edge e by a split (at this level or before) sees three faces between e's halves on either side,
    // and so between their descendants at the vertex (each later split keeps a child face per face there): edge x at
    // level l has its halves 2x and 2x + 1 at level l + 1. That spares a walk of the fan per crease vertex (its crease
    // runs along e: the edges inside faces, its others, start smooth and stay so).
    if (history_ && v >= history_->front()) {
        const int level = int(history_->size()) - 1;
        const int made = int(std::upper_bound(history_->begin(), history_->end(), int(v)) - history_->begin());
        const Index e = v - (*history_)[made - 1];
        const Index a = from >> (level - made), b = to >> (level - made);
        if ((a ^ b) == 1 && a >> 1 == e) {
            assert(!level_ || detail::faces_between(*level_, v, from, to) == 3);
            return 3;
        }
    }
    // A base vertex keeps its fan through every split (a corner child per face, a half per edge, the faces of a half
    // in its edge's order), so the count is the base's between the edges the two descend from: a walk over the base's
    // small arrays rather than this level's (docs/benchmark.md, "Measurements behind the code").
    if (base_ && v < history_->front()) {
        const int splits = int(history_->size()) - 1;
        const int faces = detail::faces_between(*base_, v, from >> splits, to >> splits);
        assert(!level_ || detail::faces_between(*level_, v, from, to) == faces);
        return faces;
    }
    if (level_) return detail::faces_between(*level_, v, from, to);
    // An old vertex's fan is its parent's, a child face per parent face; a midpoint sees three child faces of
    // each parent face between its two halves.
    return through_parent([&](const auto& p) {
        if (v < p.num_vertices()) return p.faces_between(v, from / 2, to / 2);
        const Index e = v - p.num_vertices();
        return (from == 2 * e && to == 2 * e + 1) || (from == 2 * e + 1 && to == 2 * e) ? 3 : -1;
    });
}

}  // namespace loopsub::detail
