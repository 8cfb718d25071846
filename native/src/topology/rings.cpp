// The one-rings of a child level's vertices, and of a grandchild's, read through the split's numbering (topology.h)
// instead of from a stored level: in refine_topology's vertex_vertices order (write_child_rings, which the split
// itself writes its rings with), counter-clockwise around every vertex whose fan is a disk (write_ordered_child_rings,
// what the limit pass reads of a last level built as faces only), and two splits on from a grandparent whose fans are
// one fan each (write_grandparent_sides, write_ordered_old_vertex_halves, write_ordered_grandchild_rings: the last
// level of a limit plan, the level between never built).
#include <algorithm>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "topology/level_relations.h"
#include "topology/topology.h"
#include "topology/triangle_corners.h"

namespace loopsub::detail {

void write_child_rings(const Topology& p, int begin, int end, Index* ring) {
    const Index nv = p.num_vertices;
    const int split = std::clamp(int(nv), begin, end);  // old vertices [begin, split), midpoints [split, end)
    // An old vertex's ring is the midpoints of its edges, in order; consecutive vertices' edges are consecutive. The
    // bounds in locals: a store to the ring may alias them, which would have them loaded again at every step (and
    // the loop not vectorised).
    if (begin < split) {
        const Index* edges = p.vertex_edges.data();
        const Index first = p.vertex_edge_offsets[begin], last = p.vertex_edge_offsets[split];
        for (Index k = first; k < last; ++k) *ring++ = nv + edges[k];
    }
    // The midpoint of edge e: its ends, then per face of e the two midpoints it is joined to.
    for (Index e = split - nv; e < end - nv; ++e) {
        ring = midpoint_ring_ends(p, e, ring);
        for (Index k = p.edge_face_offsets[e]; k < p.edge_face_offsets[e + 1]; ++k) {
            const Index f = p.edge_faces[k];
            const Index* fe = &p.face_edges[3 * f];
            const int local = local_edge(fe, e);
            ring = midpoint_ring_face(nv, fe, local, p.face_vertices[3 * f + local] == p.edge_vertices[2 * e], ring);
        }
    }
}

namespace {

// write_ordered_child_rings for old vertices [begin, end); returns where the next ring starts. An old vertex's ring is
// the midpoints of its parent edges. Corner child 4f + k = (v_k, m_k, m_k-1) says that m_k-1 follows m_k: after the
// edge that leaves v in a face (its edge k) comes the one that enters v there (its edge k - 1). Each edge's follower is
// found on its own (independent loads, where a walk around the fan would wait on each step's), then the chain is read
// off.
Index* write_ordered_old_vertex_rings(const Topology& p, int begin, int end, std::uint8_t* apart, Index* ring) {
    const Index nv = p.num_vertices;
    std::vector<Index> follower;
    std::vector<std::pair<Index, Index>> slots;  // (edge, its slot at v), sorted: for vertices of high valence
    constexpr Index kSearchedValence = 16;
    for (Index v = begin; v < end; ++v) {
        const Index first = p.vertex_edge_offsets[v], n = p.vertex_edge_offsets[v + 1] - first;
        const Index* edges = p.vertex_edges.data() + first;
        if (n > kSearchedValence) {
            slots.resize(std::size_t(n));
            for (Index k = 0; k < n; ++k) slots[k] = {edges[k], k};
            std::sort(slots.begin(), slots.end());
        }
        auto slot_of = [&](Index e) {
            if (n <= kSearchedValence) return Index(std::find(edges, edges + n, e) - edges);
            return std::lower_bound(slots.begin(), slots.end(), std::pair<Index, Index>(e, -1))->second;
        };
        bool disk = !apart[v] && n > 0;
        follower.assign(std::size_t(n), -1);
        for (Index k = 0; disk && k < n; ++k)
            for (Index i = p.edge_face_offsets[edges[k]]; i < p.edge_face_offsets[edges[k] + 1]; ++i) {
                const Index f = p.edge_faces[i];
                const Index* fe = &p.face_edges[3 * std::size_t(f)];
                const int local = local_edge(fe, edges[k]);
                if (p.face_vertices[3 * std::size_t(f) + local] != v) continue;
                disk = follower[k] < 0;  // two faces leave v along one edge: no disk
                follower[k] = slot_of(fe[prev_corner(local)]);
            }
        // Back at its first edge after exactly n steps, the chain has met every edge of v once.
        for (Index step = 0, k = 0; disk && step < n; ++step) {
            ring[step] = nv + edges[k];
            k = follower[k];
            disk = k >= 0 && (k == 0) == (step + 1 == n);
        }
        if (!disk) {
            if (n > 0) apart[v] = 1;
            write_child_rings(p, v, v + 1, ring);  // write_child_rings' order
        }
        ring += n;
    }
    return ring;
}

// write_ordered_child_rings for the midpoints of parent edges [e0, e1). The midpoint of edge e = (a, b) has a, b, then
// per face of e the midpoints next to a and to b (midpoint_ring_face). Around it, the face that runs from a to b (f)
// gives b, then f's midpoint next to b, then the one next to a, then a; the other face (g) a, g's next to a, g's next
// to b, b. So a disk of two faces, one each way, is a, g's two, b, f's two reversed.
void write_ordered_midpoint_rings(const Topology& p, int e0, int e1, std::uint8_t* apart, Index* ring) {
    const Index nv = p.num_vertices;
    for (Index e = e0; e < e1; ++e) {
        const Index m = nv + e, at = p.edge_face_offsets[e];
        if (!apart[m] && p.edge_face_count(e) == 2) {
            Index at_a[2], at_b[2];  // per face, the midpoints next to a and to b (scalars: no store to reload)
            bool a_first[2];
            for (int i = 0; i < 2; ++i) {
                const Index f = p.edge_faces[at + i];
                const Index* fe = &p.face_edges[3 * std::size_t(f)];
                const int local = local_edge(fe, e);
                a_first[i] = p.face_vertices[3 * std::size_t(f) + local] == p.edge_vertices[2 * std::size_t(e)];
                face_wings(nv, fe, local, a_first[i], at_a[i], at_b[i]);
            }
            if (a_first[0] != a_first[1]) {
                const int f = a_first[0] ? 0 : 1, g = 1 - f;
                ring[0] = p.edge_vertices[2 * std::size_t(e)];
                ring[1] = at_a[g];
                ring[2] = at_b[g];
                ring[3] = p.edge_vertices[2 * std::size_t(e) + 1];
                ring[4] = at_b[f];
                ring[5] = at_a[f];
                ring += 6;
                continue;
            }
        }
        apart[m] = 1;
        write_child_rings(p, m, m + 1, ring);  // write_child_rings' order
        ring += child_ring_offset(p, m + 1) - child_ring_offset(p, m);
    }
}

}  // namespace

void write_ordered_child_rings(const Topology& p, int begin, int end, std::uint8_t* apart, Index* ring) {
    const Index nv = p.num_vertices;
    const int split = std::clamp(int(nv), begin, end);  // old vertices [begin, split), midpoints [split, end)
    ring = write_ordered_old_vertex_rings(p, begin, split, apart, ring);
    write_ordered_midpoint_rings(p, split - nv, end - nv, apart, ring);
}

void write_grandparent_sides(const Topology& t, int f0, int f1, Index* edge_sides, Index* corner_halves,
                             Index* next_at) {
    const Index child_vertices = t.num_vertices + t.num_edges(), halves_end = child_vertices + 2 * t.num_edges();
    for (Index f = f0; f < f1; ++f) {
        Index half[3];  // a face's side of its edge k is numbered as its half at corner k
        for (int k = 0; k < 3; ++k) {
            const std::size_t c = 3 * std::size_t(f) + std::size_t(k);
            corner_halves[c] = half[k] = 2 * t.face_edges[c] + 1 - (t.face_edge_places[c] & 1);
        }
        for (int k = 0; k < 3; ++k) {
            Index* side = edge_sides + kEdgeSideSize * std::size_t(half[k]);
            side[kInterior] = halves_end + 3 * f + k;
            side[kInteriorBefore] = halves_end + 3 * f + prev_corner(k);
            side[kHalfBefore] = child_vertices + (half[prev_corner(k)] ^ 1);
            side[kHalfAfter] = child_vertices + half[next_corner(k)];
            // The edge that leaves corner k (edge k, its half at its start) is followed around v_k by the one that
            // enters it (edge k - 1, its half at its end): write_ordered_child_rings' follower rule.
            next_at[half[k]] = half[prev_corner(k)] ^ 1;
        }
    }
}

void write_ordered_old_vertex_halves(const Topology& t, const Index* next_at, int v0, int v1, Index first_half_vertex,
                                     Index* ring) {
    for (Index v = v0; v < v1; ++v) {
        const Index first = t.vertex_edge_offsets[v], n = t.vertex_edge_offsets[v + 1] - first;
        if (n == 0) continue;
        const Index start = child_edge_at(t, t.vertex_edges[first], v);
        Index half = start, k = 0;
        for (; k < n && half >= 0; ++k, half = next_at[half]) ring[k] = first_half_vertex + half;
        // Not back where it began after n steps: no disk (a boundary), whose ring keeps the order of its edges.
        if (k < n || half != start)
            for (k = 0; k < n; ++k) ring[k] = first_half_vertex + child_edge_at(t, t.vertex_edges[first + k], v);
        ring += n;
    }
}

namespace {

// The rings write_ordered_grandchild_rings writes, one after another from ring[0]: close(next) ends the one being
// written at `next` and writes the offset where the next begins.
struct GrandchildRings {
    Index* ring;
    Index* offsets;
    const Index* start;
    void close(Index* next) { ring = next, *offsets++ = Index(ring - start); }
};

// The rings of grandchild vertices [v0, v1) that are the child's midpoints R of the grandparent's edges h.
void write_child_midpoint_rings(const Grandparent& g, Index v0, Index v1, GrandchildRings& out) {
    const Index nv = g.num_vertices, child_vertices = nv + g.num_edges;
    Index*& ring = out.ring;
    for (Index v = v0; v < v1; ++v) {
        const Index h = v - nv;
        const Index* f_side = g.edge_sides + 2 * kEdgeSideSize * std::size_t(h);
        const Index* g_side = f_side + kEdgeSideSize;
        ring[0] = child_vertices + 2 * h;
        if (g_side[kInterior] < 0) {  // a boundary edge
            ring[1] = child_vertices + 2 * h + 1;
            ring[2] = f_side[kInteriorBefore];
            ring[3] = f_side[kInterior];
            out.close(ring + 4);
            continue;
        }
        ring[1] = g_side[kInterior];
        ring[2] = g_side[kInteriorBefore];
        ring[3] = child_vertices + 2 * h + 1;
        ring[4] = f_side[kInterior];
        ring[5] = f_side[kInteriorBefore];
        out.close(ring + 6);
    }
}

// The rings of grandchild vertices [v0, v1) that are the midpoints of the halves 2h = (a, R) and 2h + 1 = (R, b) of
// the grandparent's edges h, a pair at a time.
void write_half_midpoint_rings(const Grandparent& g, Index v0, Index v1, GrandchildRings& out) {
    const Index nv = g.num_vertices, child_vertices = nv + g.num_edges;
    Index*& ring = out.ring;
    Index v = v0;
    while (v < v1) {
        const Index h = (v - child_vertices) / 2;
        const Index* f_side = g.edge_sides + 2 * kEdgeSideSize * std::size_t(h);
        const Index* g_side = f_side + kEdgeSideSize;
        const bool boundary = g_side[kInterior] < 0;
        if ((v - child_vertices) % 2 == 0) {
            ring[0] = g.edge_vertices[2 * std::size_t(h)];
            if (boundary) {
                ring[1] = nv + h;
                ring[2] = f_side[kHalfBefore];
                ring[3] = f_side[kInteriorBefore];
                out.close(ring + 4);
            } else {
                ring[1] = g_side[kHalfAfter];
                ring[2] = g_side[kInterior];
                ring[3] = nv + h;
                ring[4] = f_side[kInteriorBefore];
                ring[5] = f_side[kHalfBefore];
                out.close(ring + 6);
            }
            if (++v == v1) break;
        }
        ring[0] = nv + h;
        if (boundary) {
            ring[1] = g.edge_vertices[2 * std::size_t(h) + 1];
            ring[2] = f_side[kInterior];
            ring[3] = f_side[kHalfAfter];
            out.close(ring + 4);
        } else {
            ring[1] = g_side[kInteriorBefore];
            ring[2] = g_side[kHalfBefore];
            ring[3] = g.edge_vertices[2 * std::size_t(h) + 1];
            ring[4] = f_side[kHalfAfter];
            ring[5] = f_side[kInterior];
            out.close(ring + 6);
        }
        ++v;
    }
}

// The rings of grandchild vertices [v0, v1) that are the midpoints of the child's interior edges: that of interior
// edge k of face f, from m_k to m_k+1 (always two faces: the corner child k + 1 and the middle child), a face's three
// at a time, from its corners' halves.
void write_interior_midpoint_rings(const Grandparent& g, Index v0, Index v1, GrandchildRings& out) {
    const Index nv = g.num_vertices, ne = g.num_edges, child_vertices = nv + ne;
    const Index halves_end = child_vertices + 2 * ne;  // the first grandchild vertex on an interior edge
    const Index* corner_halves = g.corner_halves;
    auto interior_edge = [=](Index f, int k) { return halves_end + 3 * f + k; };  // the grandchild vertex on it
    Index*& ring = out.ring;
    auto interior_ring = [&](const Index halves[3], Index first_interior, int k) {
        const int next = next_corner(k);
        ring[0] = nv + (halves[k] >> 1);
        ring[1] = child_vertices + (halves[k] ^ 1);
        ring[2] = child_vertices + halves[next];
        ring[3] = nv + (halves[next] >> 1);
        ring[4] = first_interior + next;
        ring[5] = first_interior + prev_corner(k);
        out.close(ring + 6);
    };
    for (Index v = v0; v < v1; ++v) {
        const Index f = (v - halves_end) / 3;
        interior_ring(&corner_halves[3 * std::size_t(f)], interior_edge(f, 0), int((v - halves_end) % 3));
    }
}

}  // namespace

void write_ordered_grandchild_rings(const Grandparent& g, int begin, int end, Index* offsets, Index* ring) {
    // The grandparent's edge h = (a, b) has its midpoint R = nv + h in the child, and faces F (which runs from a to b,
    // h its edge k) and G (from b to a, h its edge j). Around R in the child, the follower rule of
    // write_ordered_child_rings gives its edges from the half at a: 2h, then G's interior edges j and j - 1, 2h + 1,
    // F's interior edges k and k - 1. A child edge's ring in the grandchild is (write_ordered_child_rings) its ends,
    // the other face's midpoints next to each end, then the face's that runs from the first end, reversed: for the
    // halves of h their corner children in F and G, for interior edge k of F its corner child k + 1 and F's middle
    // child. Child edges are numbered as the split says (halves 2h and 2h + 1, interior edges 2 ne + 3f + k), and a
    // grandchild vertex made by a split is the child's vertex count plus its child edge. A boundary edge has F only
    // (an edge's first face runs along it from its first end): R and its halves' midpoints are no disks, and their
    // rings keep write_child_rings' order (R's edges 2h, 2h + 1, then F's interior edges k - 1 and k; a half's ends,
    // then its wings in F). F's and G's vertices there are h's sides (Grandparent::edge_sides). Each kind in a function
    // of its own: the child's midpoints, the halves' midpoints a pair at a time, the interior edges' a face at a time.
    const Index nv = g.num_vertices, ne = g.num_edges, child_vertices = nv + ne;
    const Index halves_end = child_vertices + 2 * ne;  // the first grandchild vertex on an interior edge
    assert(begin >= nv);
    *offsets++ = 0;
    GrandchildRings out{ring, offsets, ring};
    // The child's midpoints [begin, child_stop), the halves' midpoints [child_stop, halves_stop), the interior edges'
    // [halves_stop, end).
    const Index child_stop = std::max(Index(begin), std::min(Index(end), child_vertices));
    const Index halves_stop = std::max(child_stop, std::min(Index(end), halves_end));
    write_child_midpoint_rings(g, begin, child_stop, out);
    write_half_midpoint_rings(g, child_stop, halves_stop, out);
    write_interior_midpoint_rings(g, halves_stop, end, out);
}

}  // namespace loopsub::detail
