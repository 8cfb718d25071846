#include "topology/topology.h"

#include <algorithm>
#include <cassert>
#include <cstring>
#include <numeric>
#include <utility>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "base/parallel.h"
#include "topology/triangle_corners.h"

namespace loopsub::detail {

namespace {

// Where edge e sits in face f's edges (edge k runs from corner k to corner k + 1).
inline int local_edge(const Index* face_edges, Index e) { return face_edges[0] == e ? 0 : face_edges[1] == e ? 1 : 2; }

// The vertices opposite the two halves of a face's edge `local` (fe: the face's edges) in that face: at_a opposite
// the half at the edge's first vertex, at_b opposite the other. A half lies in a corner child (v_k, m_k, m_{k-1}),
// opposite the other midpoint there; a_first: the face's corner `local` is the edge's first vertex.
inline void face_wings(Index nv, const Index* fe, int local, bool a_first, Index& at_a, Index& at_b) {
    const Index before = nv + fe[prev_corner(local)], after = nv + fe[next_corner(local)];
    at_a = a_first ? before : after;
    at_b = a_first ? after : before;
}

// The ring of the midpoint of edge e: its ends, then per face of e the two midpoints it is joined to there, which are
// the wings of e's halves in that face (face_wings: at a, then at b). The plan reads the level before the last's rings
// back from its wing tables (fill_tables_from_parent). Each returns the ring's next free entry.
inline Index* midpoint_ring_ends(const Topology& p, Index e, Index* ring) {
    ring[0] = p.edge_vertices[2 * e], ring[1] = p.edge_vertices[2 * e + 1];
    return ring + 2;
}
inline Index* midpoint_ring_face(Index nv, const Index* fe, int local, bool a_first, Index* ring) {
    face_wings(nv, fe, local, a_first, ring[0], ring[1]);
    return ring + 2;
}

// The midpoint's edges inside a face of its edge (the edge is the face's edge `local`), in its ring's order: interior
// edge local joins midpoints local and local + 1, edge local - 1 joins local - 1 and local, and the one to the
// midpoint next to the edge's first vertex comes first.
inline void midpoint_face_edges(Index interior_base, Index f, int local, bool a_first, Index edges[2]) {
    edges[0] = interior_base + 3 * f + (a_first ? prev_corner(local) : local);
    edges[1] = interior_base + 3 * f + (a_first ? local : prev_corner(local));
}

// A stored level read through the calls the derivations below make of a parent, which a VertexNeighbourhood answers
// for a level known through its own parent.
struct StoredLevel {
    const Topology& t;
    int num_vertices() const { return t.num_vertices; }
    int num_edges() const { return t.num_edges(); }
    int num_faces() const { return t.num_faces(); }
    int max_valence() const { return t.max_valence; }
    int max_edge_face_count() const { return t.max_edge_face_count; }
    void edge_ends(Index e, Index ends[2]) const {
        ends[0] = t.edge_vertices[2 * std::size_t(e)], ends[1] = t.edge_vertices[2 * std::size_t(e) + 1];
    }
    void face_vertices(Index f, Index out[3]) const { std::copy_n(&t.face_vertices[3 * std::size_t(f)], 3, out); }
    void face_edges(Index f, Index out[3]) const { std::copy_n(&t.face_edges[3 * std::size_t(f)], 3, out); }
    void face(Index f, Index vertices[3], Index edges[3]) const { face_vertices(f, vertices), face_edges(f, edges); }
    int edge_face_count(Index e) const { return t.edge_face_count(e); }
    template <typename Visit>
    void for_each_edge_face(Index e, const Visit& visit) const {
        for (Index k = t.edge_face_offsets[e]; k < t.edge_face_offsets[e + 1]; ++k) visit(t.edge_faces[k]);
    }
    void edges(Index v, std::vector<Index>& out) const {
        out.assign(t.vertex_edges.begin() + t.vertex_edge_offsets[v],
                   t.vertex_edges.begin() + t.vertex_edge_offsets[v + 1]);
    }
    int faces_between(Index v, Index from, Index to) const { return detail::faces_between(t, v, from, to); }
    void fan(Index v, std::vector<FanCorner>& out) const;
};

// The child's connectivity around single elements, from any parent level P (StoredLevel or VertexNeighbourhood) through
// the split's numbering (topology.h), as refine_topology writes it.

template <typename P>
Index child_edge_at_of(const P& p, Index e, Index v) {
    Index ends[2];
    p.edge_ends(e, ends);
    assert(ends[0] == v || ends[1] == v);
    return 2 * e + (ends[0] == v ? 0 : 1);
}

// The corners of child face c (4f + j of parent face f: the corner child (v_j, m_j, m_j-1), or the middle child (m_0,
// m_1, m_2)) and, where asked, its edges (the corner child's half of edge j, the interior edge across, its half of
// edge j - 1; the middle child's three interior edges).
template <typename P>
void child_face_of(const P& p, Index c, Index vertices[3], Index* edges) {
    const Index f = c / 4, nv = p.num_vertices(), interior = 2 * p.num_edges() + 3 * f;
    const int j = int(c % 4);
    Index v[3], e[3];
    p.face(f, v, e);
    if (j == 3) {
        for (int k = 0; k < 3; ++k) vertices[k] = nv + e[k];
        if (edges) edges[0] = interior, edges[1] = interior + 1, edges[2] = interior + 2;
        return;
    }
    vertices[0] = v[j], vertices[1] = nv + e[j], vertices[2] = nv + e[prev_corner(j)];
    if (!edges) return;
    edges[0] = child_edge_at_of(p, e[j], v[j]);
    edges[1] = interior + prev_corner(j);
    edges[2] = child_edge_at_of(p, e[prev_corner(j)], v[j]);
}

// child_edge_ends, below, from any parent.
template <typename P>
void child_edge_ends_of(const P& p, Index e, Index ends[2]) {
    const Index nv = p.num_vertices(), halves = 2 * p.num_edges();
    if (e < halves) {  // half 2h = (a, m), 2h + 1 = (m, b)
        Index parent_ends[2];
        p.edge_ends(e / 2, parent_ends);
        ends[0] = e % 2 == 0 ? parent_ends[0] : nv + e / 2;
        ends[1] = e % 2 == 0 ? nv + e / 2 : parent_ends[1];
        return;
    }
    const Index f = (e - halves) / 3;
    const int k = (e - halves) % 3;
    Index fe[3];
    p.face_edges(f, fe);
    ends[0] = nv + fe[k];
    ends[1] = nv + fe[next_corner(k)];
}

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

template <typename P>
int child_max_valence_of(const P& p) {
    return p.num_edges() > 0 ? std::max(p.max_valence(), 2 + 2 * p.max_edge_face_count()) : p.max_valence();
}
template <typename P>
int child_max_edge_face_count_of(const P& p) {
    return p.num_faces() > 0 ? std::max(p.max_edge_face_count(), 2) : p.max_edge_face_count();
}

// The vertices opposite the two halves of parent edge e in their first two faces: (C, D) of half 2e, then of half
// 2e + 1; where a face is missing, C / D repeat the half's ends.
inline void half_edge_wings(const Topology& p, Index e, Index wings[4]) {
    const Index nv = p.num_vertices, a = p.edge_vertices[2 * e], b = p.edge_vertices[2 * e + 1], m = nv + e;
    Index at_a[2] = {a, m}, at_b[2] = {m, b};
    int face = 0;
    for (Index k = p.edge_face_offsets[e]; k < p.edge_face_offsets[e + 1] && face < 2; ++k, ++face) {
        const Index f = p.edge_faces[k];
        const Index* fe = &p.face_edges[3 * f];
        const int local = local_edge(fe, e);
        face_wings(nv, fe, local, p.face_vertices[3 * f + local] == a, at_a[face], at_b[face]);
    }
    wings[0] = at_a[0], wings[1] = at_a[1], wings[2] = at_b[0], wings[3] = at_b[1];
}

// Ends and wings of interior edge k of face f (face_interior_edge).
inline void interior_edge(const Topology& p, Index f, int k, Index abcd[4]) {
    face_interior_edge(p.num_vertices, &p.face_vertices[3 * f], &p.face_edges[3 * f], k, abcd);
}

#if defined(__SSE2__)
// The SSE2 writers below (the loops that write a level's tables are bound by their count of stores, one a cycle here,
// so they store 16 bytes at a time): lane k of a vector belongs to corner k of a face, lane 3 is unused.
inline __m128i load_corners(const Index* face) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(face)); }
inline __m128i corner_before(__m128i x) { return _mm_shuffle_epi32(x, _MM_SHUFFLE(3, 1, 0, 2)); }  // lane k: x[k - 1]

// Row k = (a_k, b_k, c_k, d_k), for k < 3.
inline void corner_rows(__m128i a, __m128i b, __m128i c, __m128i d, __m128i row[3]) {
    const __m128i ab_lo = _mm_unpacklo_epi32(a, b), cd_lo = _mm_unpacklo_epi32(c, d);
    row[0] = _mm_unpacklo_epi64(ab_lo, cd_lo);
    row[1] = _mm_unpackhi_epi64(ab_lo, cd_lo);
    row[2] = _mm_unpacklo_epi64(_mm_unpackhi_epi32(a, b), _mm_unpackhi_epi32(c, d));
}

// corner_halves for the three corners of face f at once: the child edges of edge k and of edge k - 1 at v_k.
inline void corner_halves_sse2(const Topology& p, Index f, __m128i fe, __m128i& of_edge, __m128i& of_edge_before) {
    int places;
    std::memcpy(&places, &p.face_edge_places[3 * std::size_t(f)], sizeof places);
    const __m128i zero = _mm_setzero_si128();
    const __m128i starts =
        _mm_and_si128(_mm_unpacklo_epi16(_mm_unpacklo_epi8(_mm_cvtsi32_si128(places), zero), zero), _mm_set1_epi32(1));
    const __m128i twice = _mm_add_epi32(fe, fe);
    of_edge = _mm_sub_epi32(_mm_add_epi32(twice, _mm_set1_epi32(1)), starts);
    of_edge_before = corner_before(_mm_add_epi32(twice, starts));
}
#endif

// Part `part`'s places in a counting sort whose items the parts counted by key (counts[q][k]: part q's items of key
// k): a key's items from earlier parts come first, so each key keeps its items in order. Every part works its places
// out for itself (a pass over the keys, no meeting of the parts); given `offsets`, also where each key starts.
void part_places(const std::vector<LargeVector<Index>>& counts, int part, Index* places, Index* offsets) {
    const std::size_t keys = counts[0].size();
    Index start = 0;
    for (std::size_t k = 0; k < keys; ++k) {
        if (offsets) offsets[k] = start;
        Index before = start;
        for (int q = 0; q < part; ++q) before += counts[q][k];
        places[k] = before;
        for (const LargeVector<Index>& part_counts : counts) start += part_counts[k];
    }
    if (offsets) offsets[keys] = start;
}

}  // namespace

Index Topology::opposite_vertex(Index f, Index e) const {
    for (int k = 0; k < 3; ++k)
        if (face_edges[3 * f + k] == e) return face_vertices[3 * f + prev_corner(k)];
    return face_vertices[3 * f];  // not reached for an edge of f
}

Index Topology::other_edge_at_vertex(Index f, Index v, Index e) const {
    for (int k = 0; k < 3; ++k) {
        if (face_vertices[3 * f + k] != v) continue;
        const Index leaving = face_edges[3 * f + k], arriving = face_edges[3 * f + prev_corner(k)];
        return leaving == e ? arriving : leaving;
    }
    return e;  // not reached for a vertex of f
}

Topology build_base_topology(const Index* triangles, int num_triangles, int num_vertices, int threads) {
    Topology t;
    t.num_vertices = num_vertices;
    const int num_corners = 3 * num_triangles;
    // Below a few thousand triangles the parts' meetings would cost more than their share of the work.
    const int parts = num_triangles >= 2048 ? std::max(1, threads) : 1;
    auto next = [](int c) { return c % 3 == 2 ? c - 2 : c + 1; };  // the corner after c in its face

    // Corner c starts its face's edge: the edge's ends, lower and higher. The corners are bucketed by their lower end
    // in corner order, each beside its higher end, so that finding an edge's corners is a scan of a bucket of about
    // half a valence: no hashing, no sort. An edge is numbered by its first corner, in corner order, and its faces
    // are listed in corner order too: a corner's rank among its edge's corners is its face's place there.
    LargeVector<Index> low(num_corners), high(num_corners), bucket(num_corners), bucket_high(num_corners);
    LargeVector<Index> bucket_offsets(std::size_t(num_vertices) + 1), first_corner(num_corners), rank(num_corners);
    LargeVector<Index> corners_from_first(num_corners), corners_of_edge;
    std::vector<LargeVector<Index>> corners_at_low(parts, LargeVector<Index>(num_vertices, 0));
    std::vector<LargeVector<Index>> edges_at_vertex(parts, LargeVector<Index>(num_vertices, 0));
    std::vector<Index> part_edges(parts, 0), part_edge_corners(parts, 0);
    std::vector<int> part_max_edge_faces(parts, 0);
    t.face_vertices.resize(num_corners);
    t.face_edges.resize(num_corners);
    t.face_edge_places.resize(num_corners);
    t.edge_faces.resize(num_corners);
    t.vertex_edge_offsets.resize(std::size_t(num_vertices) + 1);
    auto sum_before = [](const std::vector<Index>& per_part, int part) {
        return std::accumulate(per_part.begin(), per_part.begin() + part, Index(0));
    };

    // Six steps; the edges' arrays are sized between the third and the fourth, once the edges are counted (sized for
    // the most there could be, an edge a corner, their blocks' untouched pages were faulted in by the next plan).
    auto run_step = [&](int step, int part, int) {
        const auto [f0, f1] = part_of(num_triangles, part, parts);
        const int c0 = 3 * f0, c1 = 3 * f1;
        // The part's edges, once the parts have counted theirs (step 2 writes the counts).
        const Index edge0 = step > 2 ? sum_before(part_edges, part) : 0,
                    edge1 = step > 2 ? edge0 + part_edges[part] : 0;
        switch (step) {
            case 0:
                for (int c = c0; c < c1; ++c) {
                    const Index a = triangles[c], b = triangles[next(c)];
                    t.face_vertices[c] = a;
                    low[c] = std::min(a, b), high[c] = std::max(a, b);
                    ++corners_at_low[part][low[c]];
                }
                break;
            case 1: {
                LargeVector<Index> place(num_vertices);
                part_places(corners_at_low, part, place.data(), part == 0 ? bucket_offsets.data() : nullptr);
                for (int c = c0; c < c1; ++c) {
                    const Index slot = place[low[c]]++;
                    bucket[slot] = c;
                    bucket_high[slot] = high[c];
                }
                break;
            }
            case 2: {             // each corner finds its edge's first corner; a first corner ranks the edge's corners
                Index edges = 0;  // the part's totals are written once: side by side, the parts would share a line
                for (int c = c0; c < c1; ++c) {
                    const Index hi = high[c], end = bucket_offsets[low[c] + 1];
                    Index k = bucket_offsets[low[c]];
                    while (bucket_high[k] != hi) ++k;  // c itself is in the bucket
                    first_corner[c] = bucket[k];
                    if (bucket[k] != c) continue;
                    ++edges;
                    Index corners = 0;
                    for (; k < end; ++k)
                        if (bucket_high[k] == hi) rank[bucket[k]] = corners++;
                    corners_from_first[c] = corners;
                }
                part_edges[part] = edges;
                break;
            }
            case 3: {  // the part's first corners number their edges
                Index e = edge0, edge_corners = 0;
                int max_edge_faces = 0;
                for (int c = c0; c < c1; ++c) {
                    if (first_corner[c] != c) continue;
                    t.face_edges[c] = e;
                    t.edge_vertices[2 * std::size_t(e)] = triangles[c];
                    t.edge_vertices[2 * std::size_t(e) + 1] = triangles[next(c)];
                    corners_of_edge[e] = corners_from_first[c];
                    edge_corners += corners_from_first[c];
                    max_edge_faces = std::max(max_edge_faces, int(corners_from_first[c]));
                    ++e;
                }
                part_edge_corners[part] = edge_corners;
                part_max_edge_faces[part] = max_edge_faces;
                break;
            }
            case 4: {
                for (int c = c0; c < c1; ++c) {
                    const Index first = first_corner[c];
                    const Index e = t.face_edges[first];
                    if (first != c) t.face_edges[c] = e;
                    const int starts_edge = t.face_vertices[c] == t.edge_vertices[2 * std::size_t(e)];
                    t.face_edge_places[c] = std::uint8_t(std::min(rank[c], Index(2)) << 1 | starts_edge);
                }
                Index offset = sum_before(part_edge_corners, part);
                for (Index e = edge0; e < edge1; ++e) {
                    t.edge_face_offsets[e] = offset;
                    offset += corners_of_edge[e];
                    // Where the second face is missing, the edge's second end stands in for the vertex opposite it.
                    if (corners_of_edge[e] < 2) t.edge_wing_d[e] = t.edge_vertices[2 * std::size_t(e) + 1];
                    ++edges_at_vertex[part][t.edge_vertices[2 * std::size_t(e)]];
                    ++edges_at_vertex[part][t.edge_vertices[2 * std::size_t(e) + 1]];
                }
                if (part + 1 == parts) t.edge_face_offsets[edge1] = offset;
                break;
            }
            case 5: {
                for (int c = c0; c < c1; ++c) {
                    const Index e = t.face_edges[c], f = c / 3;
                    t.edge_faces[t.edge_face_offsets[e] + rank[c]] = f;
                    if (rank[c] > 1) continue;
                    (rank[c] == 0 ? t.edge_wing_c : t.edge_wing_d)[e] = t.opposite_vertex(f, e);
                }
                LargeVector<Index> place(num_vertices);
                part_places(edges_at_vertex, part, place.data(), part == 0 ? t.vertex_edge_offsets.data() : nullptr);
                for (Index e = edge0; e < edge1; ++e) {
                    const Index a = t.edge_vertices[2 * std::size_t(e)], b = t.edge_vertices[2 * std::size_t(e) + 1];
                    const Index at_a = place[a]++;
                    t.vertex_edges[at_a] = e, t.vertex_vertices[at_a] = b;
                    const Index at_b = place[b]++;
                    t.vertex_edges[at_b] = e, t.vertex_vertices[at_b] = a;
                }
                break;
            }
        }
    };
    run_levels(parts, 3, run_step);
    const std::size_t num_edges = std::size_t(sum_before(part_edges, parts));
    t.edge_vertices.resize(2 * num_edges);
    t.edge_face_offsets.resize(num_edges + 1);
    t.edge_wing_c.resize(num_edges);
    t.edge_wing_d.resize(num_edges);
    t.vertex_edges.resize(2 * num_edges);
    t.vertex_vertices.resize(2 * num_edges);
    corners_of_edge.resize(num_edges);
    run_levels(parts, 3, [&run_step](int later, int part, int parts_) { run_step(3 + later, part, parts_); });
    for (int v = 0; v < num_vertices; ++v) t.max_valence = std::max(t.max_valence, t.valence(v));
    t.max_edge_face_count = *std::max_element(part_max_edge_faces.begin(), part_max_edge_faces.end());
    return t;
}

namespace {

// The child faces' edges of parent faces [f0, f1) (12 per face, in refine_topology's numbering) and, where `places` is
// given, their face_edge_places. Corner child k = (v_k, m_k, m_{k-1}) has the half of edge k at v_k, interior edge
// k - 1 and the half of edge k - 1 at v_k; the middle child the three interior edges. The corner children's halves
// keep the parent face's place and direction there; an interior edge has its corner child first (running from
// m_{k-1} to m_k there) and the middle child second.
// The edges of child face c (corner child k = c % 4 of parent face f = c / 4: its half of edge k, the interior edge
// across, its half of edge k - 1; the middle child: the three interior edges).
void child_face_edges(const Topology& p, Index c, Index edges[3]) {
    Index vertices[3];
    child_face_of(StoredLevel{p}, c, vertices, edges);
}

void write_child_face_edges(const Topology& p, int f0, int f1, Index* edges, std::uint8_t* places) {
    const Index interior_base = 2 * p.num_edges();
    auto write_places = [&](int f) {
        const std::uint8_t* parent = &p.face_edge_places[3 * std::size_t(f)];
        const std::uint8_t child[12] = {parent[0], 0, parent[2], parent[1], 0, parent[0],
                                        parent[2], 0, parent[1], 3,         3, 3};
        std::memcpy(places + 12 * std::size_t(f), child, sizeof child);
    };
    int f = f0;
#if defined(__SSE2__)
    // Four stores a face instead of twelve, where the parent has places (the vector loads read into the next face).
    const int vector_end = p.face_edge_places.empty() ? f0 : std::clamp(p.num_faces() - 1, f0, f1);
    for (; f < vector_end; ++f) {
        __m128i half_k, half_before;
        corner_halves_sse2(p, f, load_corners(&p.face_edges[3 * std::size_t(f)]), half_k, half_before);
        const Index interior = interior_base + 3 * f;
        __m128i row[3];  // lanes 0-2 of row k: corner child k's edges; lane 3 is overwritten, but row 2's is interior
                         // edge 0
        corner_rows(half_k, _mm_add_epi32(_mm_set1_epi32(interior), _mm_setr_epi32(2, 0, 1, 0)), half_before,
                    _mm_set1_epi32(interior), row);
        Index* out = edges + 12 * std::size_t(f);
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out), row[0]);
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 3), row[1]);
        _mm_storeu_si128(reinterpret_cast<__m128i*>(out + 6), row[2]);
        _mm_storel_epi64(reinterpret_cast<__m128i*>(out + 10), _mm_setr_epi32(interior + 1, interior + 2, 0, 0));
        if (!places) continue;
        // write_places in two stores (x86 is little-endian), not twelve byte by byte (docs/benchmark.md, "Measurements
        // behind the code").
        std::uint32_t parent;
        std::memcpy(&parent, &p.face_edge_places[3 * std::size_t(f)], sizeof parent);
        const std::uint64_t p0 = parent & 0xff, p1 = parent >> 8 & 0xff, p2 = parent >> 16 & 0xff;
        const std::uint64_t first = p0 | p2 << 16 | p1 << 24 | p0 << 40 | p2 << 48;
        const std::uint32_t last = std::uint32_t(p1) | 0x03030300u;
        std::memcpy(places + 12 * std::size_t(f), &first, sizeof first);
        std::memcpy(places + 12 * std::size_t(f) + 8, &last, sizeof last);
    }
#endif
    for (; f < f1; ++f) {
        for (int k = 0; k < 4; ++k) child_face_edges(p, 4 * f + k, edges + 12 * std::size_t(f) + 3 * k);
        if (places) write_places(f);
    }
}

// The relations a child of each Refined form holds (face_vertices always).
struct ChildRelations {
    bool edges;          // edge_vertices, face_edges, vertex_edge_offsets, edge faces and vertex edges: Full and
                         // Connectivity
    bool neighbourhood;  // the winged-edge neighbourhood, vertex_vertices and edge_wing_c / _d: Full
    bool places;         // face_edge_places: Full
};

ChildRelations relations_of(Refined what) {
    return {what != Refined::FacesOnly, what == Refined::Full, what == Refined::Full};
}

// The child with every array of its relations sized (each is then filled in parts, a slot by exactly one parent
// element), and its maxima, which follow from the parent's in closed form.
Topology sized_child(const Topology& p, const ChildRelations& has) {
    const int nv = p.num_vertices, ne = p.num_edges(), nf = p.num_faces();
    Topology c;
    c.num_vertices = nv + ne;
    c.max_valence = child_max_valence(p);
    c.max_edge_face_count = child_max_edge_face_count(p);
    c.face_vertices.resize(12 * std::size_t(nf));
    if (!has.edges) return c;  // a FacesOnly child's parent may lack its edge faces and vertex edges
    const std::size_t child_edges = 2 * std::size_t(ne) + 3 * std::size_t(nf);
    // An old vertex keeps its valence (the halves of its edges, in order); the midpoint of edge e has its two halves
    // and, per face of e, the two interior edges that meet it.
    const std::size_t ring_entries =
        std::size_t(p.vertex_edge_offsets[nv]) + 2 * std::size_t(ne) + 2 * std::size_t(p.edge_face_offsets[ne]);
    c.vertex_edge_offsets.resize(std::size_t(c.num_vertices) + 1);
    c.vertex_edge_offsets[c.num_vertices] = Index(ring_entries);
    c.edge_vertices.resize(2 * child_edges);
    c.face_edges.resize(12 * std::size_t(nf));
    if (has.places) c.face_edge_places.resize(12 * std::size_t(nf));
    if (has.neighbourhood) {
        c.edge_wing_c.resize(child_edges);
        c.edge_wing_d.resize(child_edges);
        c.vertex_vertices.resize(ring_entries);
    }
    // A half of parent edge e has e's faces; an interior edge has two.
    c.edge_face_offsets.resize(child_edges + 1);
    c.edge_face_offsets[child_edges] = 2 * p.edge_face_offsets[ne] + 6 * nf;
    c.edge_faces.resize(2 * std::size_t(p.edge_face_offsets[ne]) + 6 * std::size_t(nf));
    c.vertex_edges.resize(ring_entries);
    return c;
}

// Child faces 4f + k of parent faces [f0, f1): their corners (corner child k = (v_k, m_k, m_{k-1}), the middle child
// (m_0, m_1, m_2)) and, past FacesOnly, their edges.
void populate_child_faces(const Topology& p, Topology& c, const ChildRelations& has, int f0, int f1) {
    const Index nv = p.num_vertices;
    for (int f = f0; f < f1; ++f) {
        const Index* v = &p.face_vertices[3 * f];
        const Index m0 = nv + p.face_edges[3 * f], m1 = nv + p.face_edges[3 * f + 1], m2 = nv + p.face_edges[3 * f + 2];
        Index* out = &c.face_vertices[12 * std::size_t(f)];
        out[0] = v[0], out[1] = m0, out[2] = m2;
        out[3] = v[1], out[4] = m1, out[5] = m0;
        out[6] = v[2], out[7] = m2, out[8] = m1;
        out[9] = m0, out[10] = m1, out[11] = m2;
    }
    if (has.edges)
        write_child_face_edges(p, f0, f1, c.face_edges.data(), has.places ? c.face_edge_places.data() : nullptr);
}

// Interior edges 2E + 3f + k of parent faces [f0, f1): their ends, their wings, and their two faces (the corner child
// k + 1 and the middle child).
void populate_interior_edges(const Topology& p, Topology& c, const ChildRelations& has, int f0, int f1) {
    const Index interior_base = 2 * p.num_edges();
    const std::size_t first = std::size_t(interior_base) + 3 * std::size_t(f0);
    if (has.neighbourhood) {  // child_edges stores a face's three at a time, ends and wings
        child_edges(p, int(first), interior_base + 3 * f1, c.edge_vertices.data() + 2 * first,
                    c.edge_wing_c.data() + first, c.edge_wing_d.data() + first);
    } else {
        for (int f = f0; f < f1; ++f)
            for (int k = 0; k < 3; ++k)
                child_edge_ends(p, interior_base + 3 * f + k,
                                &c.edge_vertices[2 * (std::size_t(interior_base) + 3 * f + k)]);
    }
    const Index faces_of_halves = 2 * p.edge_face_offsets[p.num_edges()];
    for (int f = f0; f < f1; ++f) {
        for (int k = 0; k < 3; ++k) {
            const Index at = faces_of_halves + 2 * (3 * f + k);
            c.edge_face_offsets[interior_base + 3 * f + k] = at;
            c.edge_faces[at] = 4 * f + next_corner(k);
            c.edge_faces[at + 1] = 4 * f + 3;
        }
    }
}

// Halves 2e (at e's first end) and 2e + 1 of parent edges [e0, e1): their ends and, with the neighbourhood, their
// wings, which each of parent faces [f0, f1) puts in place for its edges (write_half_wings). Their faces come with
// the midpoints' rings (populate_midpoints).
void populate_halves(const Topology& p, Topology& c, const ChildRelations& has, int e0, int e1, int f0, int f1) {
    write_half_ends(p, e0, e1, c.edge_vertices.data() + 4 * std::size_t(e0));
    if (has.neighbourhood) write_half_wings(p, f0, f1, e0, e1, c.edge_wing_c.data(), c.edge_wing_d.data());
}

// Old vertices [v0, v1): each keeps its parent's offset, its edges become their halves at it, its ring the midpoints
// of its edges.
void populate_old_vertices(const Topology& p, Topology& c, const ChildRelations& has, int v0, int v1) {
    // Pointer arithmetic, not &vector[i]: a loose vertex has no ring, and its offset may be the arrays' end (or the
    // arrays empty, when no vertex has an edge).
    if (has.neighbourhood) write_child_rings(p, v0, v1, c.vertex_vertices.data() + p.vertex_edge_offsets[v0]);
    for (int v = v0; v < v1; ++v) {
        c.vertex_edge_offsets[v] = p.vertex_edge_offsets[v];
        Index* edges = c.vertex_edges.data() + p.vertex_edge_offsets[v];
        for (Index k = p.vertex_edge_offsets[v]; k < p.vertex_edge_offsets[v + 1]; ++k)
            *edges++ = child_edge_at(p, p.vertex_edges[k], v);
    }
}

// The midpoints nv + e of parent edges [e0, e1): offsets, edges (its halves, then per face of e the two interior edges
// that meet it) and rings; and the faces of e's halves. One look at each face of e (where e sits in it) gives all of
// them, rather than a pass per relation that each look again (docs/benchmark.md, "Measurements behind the code").
void populate_midpoints(const Topology& p, Topology& c, const ChildRelations& has, int e0, int e1) {
    const Index nv = p.num_vertices, interior_base = 2 * p.num_edges();
    for (int e = e0; e < e1; ++e) {
        const Index first_face = p.edge_face_offsets[e], count = p.edge_face_count(e);
        c.edge_face_offsets[2 * e] = 2 * first_face;
        c.edge_face_offsets[2 * e + 1] = 2 * first_face + count;
        Index* at_a = &c.edge_faces[2 * std::size_t(first_face)];
        Index* at_b = at_a + count;
        const Index first = child_ring_offset(p, nv + e);
        c.vertex_edge_offsets[nv + e] = first;
        Index* edges = c.vertex_edges.data() + first;
        Index* ring = has.neighbourhood ? c.vertex_vertices.data() + first : nullptr;
        const Index a = p.edge_vertices[2 * e];
        *edges++ = 2 * e, *edges++ = 2 * e + 1;
        if (ring) ring = midpoint_ring_ends(p, e, ring);
        for (Index k = first_face; k < first_face + count; ++k) {
            const Index f = p.edge_faces[k];
            const Index* fe = &p.face_edges[3 * f];
            const int local = local_edge(fe, e);
            // A half of parent edge e lies in the corner child, at its end, of each face of e.
            const bool a_first = p.face_vertices[3 * f + local] == a;
            *at_a++ = 4 * f + (a_first ? local : next_corner(local));
            *at_b++ = 4 * f + (a_first ? next_corner(local) : local);
            midpoint_face_edges(interior_base, f, local, a_first, edges);
            edges += 2;
            if (ring) ring = midpoint_ring_face(nv, fe, local, a_first, ring);
        }
    }
}

}  // namespace

Topology refine_topology(const Topology& p, Refined what, int threads) {
    const ChildRelations has = relations_of(what);
    Topology c = sized_child(p, has);
    // Each part fills its share of the parent's faces, edges and vertices: every child slot is written by exactly one
    // parent element, and every offset has a closed form in the parent's, so the parts need no synchronisation.
    run_levels(
        std::max(1, threads), 1,
        [&](int, int part, int parts) {
            const auto [f0, f1] = part_of(p.num_faces(), part, parts);
            const auto [e0, e1] = part_of(p.num_edges(), part, parts);
            const auto [v0, v1] = part_of(p.num_vertices, part, parts);
            populate_child_faces(p, c, has, f0, f1);
            if (!has.edges) return;
            populate_interior_edges(p, c, has, f0, f1);
            populate_halves(p, c, has, e0, e1, f0, f1);
            populate_old_vertices(p, c, has, v0, v1);
            populate_midpoints(p, c, has, e0, e1);
        },
        kPiecesPerThread);
    assert(follows_split_numbering(p, c));
    return c;
}

bool follows_split_numbering(const Topology& p, const Topology& c) {
    const Index nv = p.num_vertices, ne = p.num_edges(), nf = p.num_faces();
    if (c.num_vertices != nv + ne || c.num_faces() != 4 * nf) return false;
    for (Index f = 0; f < nf; ++f) {
        const Index* v = &p.face_vertices[3 * f];
        const Index* fe = &p.face_edges[3 * f];
        const Index* children = &c.face_vertices[12 * std::size_t(f)];
        for (int k = 0; k < 3; ++k) {
            const Index corner_child[3] = {v[k], nv + fe[k], nv + fe[prev_corner(k)]};
            if (!std::equal(corner_child, corner_child + 3, children + 3 * k) || children[9 + k] != nv + fe[k])
                return false;
        }
    }
    if (c.edge_vertices.empty()) return true;  // FacesOnly
    const int child_edges = 2 * ne + 3 * nf;
    if (c.num_edges() != child_edges) return false;
    for (Index e = 0; e < child_edges; ++e) {
        Index ends[2];
        child_edge_ends(p, e, ends);
        if (ends[0] != c.edge_vertices[2 * e] || ends[1] != c.edge_vertices[2 * e + 1]) return false;
    }
    // Edge i of a face joins its corners i and i + 1; the places say which end the face starts it at.
    for (std::size_t corner = 0; corner < c.face_vertices.size(); ++corner) {
        const Index e = c.face_edges[corner], from = c.face_vertices[corner];
        const Index to = c.face_vertices[corner - corner % 3 + std::size_t(next_corner(int(corner % 3)))];
        const Index a = c.edge_vertices[2 * e], b = c.edge_vertices[2 * e + 1];
        if (!((a == from && b == to) || (a == to && b == from))) return false;
        if (!c.face_edge_places.empty() && (c.face_edge_places[corner] & 1) != (a == from ? 1 : 0)) return false;
    }
    for (Index v = 0; v <= c.num_vertices; ++v)
        if (c.vertex_edge_offsets[v] != child_ring_offset(p, v)) return false;
    if (!c.edge_wing_c.empty()) {
        std::vector<Index> ends(2 * std::size_t(child_edges)), wing_c(child_edges), wing_d(child_edges),
            ring(c.vertex_vertices.size());
        detail::child_edges(p, 0, child_edges, ends.data(), wing_c.data(), wing_d.data());
        write_child_rings(p, 0, c.num_vertices, ring.data());
        if (!std::equal(wing_c.begin(), wing_c.end(), c.edge_wing_c.begin()) ||
            !std::equal(wing_d.begin(), wing_d.end(), c.edge_wing_d.begin()) ||
            !std::equal(ring.begin(), ring.end(), c.vertex_vertices.begin()))
            return false;
    }
    if (!c.vertex_edges.empty()) {
        for (Index v = 0; v < c.num_vertices; ++v)
            for (Index k = c.vertex_edge_offsets[v]; k < c.vertex_edge_offsets[v + 1]; ++k) {
                const Index e = c.vertex_edges[k];
                if (c.edge_vertices[2 * e] != v && c.edge_vertices[2 * e + 1] != v) return false;
            }
        for (Index e = 0; e < child_edges; ++e)
            for (Index k = c.edge_face_offsets[e]; k < c.edge_face_offsets[e + 1]; ++k) {
                const Index* face_edges = &c.face_edges[3 * std::size_t(c.edge_faces[k])];
                if (std::find(face_edges, face_edges + 3, e) == face_edges + 3) return false;
            }
    }
    return true;
}

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

void write_ordered_child_rings(const Topology& p, int begin, int end, std::uint8_t* apart, Index* ring) {
    const Index nv = p.num_vertices;
    const int split = std::clamp(int(nv), begin, end);  // old vertices [begin, split), midpoints [split, end)
    // An old vertex's ring is the midpoints of its parent edges. Corner child 4f + k = (v_k, m_k, m_k-1) says that
    // m_k-1 follows m_k: after the edge that leaves v in a face (its edge k) comes the one that enters v there (its
    // edge k - 1). Each edge's follower is found on its own (independent loads, where a walk around the fan would wait
    // on each step's), then the chain is read off.
    std::vector<Index> follower;
    std::vector<std::pair<Index, Index>> slots;  // (edge, its slot at v), sorted: for vertices of high valence
    constexpr Index kSearchedValence = 16;
    for (Index v = begin; v < split; ++v) {
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
    // The midpoint of edge e = (a, b) has a, b, then per face of e the midpoints next to a and to b
    // (midpoint_ring_face). Around it, the face that runs from a to b (f) gives b, then f's midpoint next to b, then
    // the one next to a, then a; the other face (g) a, g's next to a, g's next to b, b. So a disk of two faces, one
    // each way, is a, g's two, b, f's two reversed.
    for (Index e = split - nv; e < end - nv; ++e) {
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
    // then its wings in F). F's and G's vertices there are h's sides (Grandparent::edge_sides). Each kind in a loop
    // of its own: the child's midpoints, the halves' midpoints a pair at a time, the interior edges' a face at a time.
    const Index nv = g.num_vertices, ne = g.num_edges, child_vertices = nv + ne;
    const Index halves_end = child_vertices + 2 * ne;  // the first grandchild vertex on an interior edge
    assert(begin >= nv);
    const Index* corner_halves = g.corner_halves;
    auto interior_edge = [=](Index f, int k) { return halves_end + 3 * f + k; };  // the grandchild vertex on it
    const Index* const start = ring;
    *offsets++ = 0;
    auto close = [&](Index* next) { ring = next, *offsets++ = Index(ring - start); };
    Index v = begin;
    for (; v < std::min(end, child_vertices); ++v) {  // the child's midpoint R of h
        const Index h = v - nv;
        const Index* f_side = g.edge_sides + 2 * kEdgeSideSize * std::size_t(h);
        const Index* g_side = f_side + kEdgeSideSize;
        ring[0] = child_vertices + 2 * h;
        if (g_side[kInterior] < 0) {  // a boundary edge
            ring[1] = child_vertices + 2 * h + 1;
            ring[2] = f_side[kInteriorBefore];
            ring[3] = f_side[kInterior];
            close(ring + 4);
            continue;
        }
        ring[1] = g_side[kInterior];
        ring[2] = g_side[kInteriorBefore];
        ring[3] = child_vertices + 2 * h + 1;
        ring[4] = f_side[kInterior];
        ring[5] = f_side[kInteriorBefore];
        close(ring + 6);
    }
    const Index halves_stop = std::min(end, halves_end);
    while (v < halves_stop) {  // the midpoints of halves 2h = (a, R) and 2h + 1 = (R, b)
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
                close(ring + 4);
            } else {
                ring[1] = g_side[kHalfAfter];
                ring[2] = g_side[kInterior];
                ring[3] = nv + h;
                ring[4] = f_side[kInteriorBefore];
                ring[5] = f_side[kHalfBefore];
                close(ring + 6);
            }
            if (++v == halves_stop) break;
        }
        ring[0] = nv + h;
        if (boundary) {
            ring[1] = g.edge_vertices[2 * std::size_t(h) + 1];
            ring[2] = f_side[kInterior];
            ring[3] = f_side[kHalfAfter];
            close(ring + 4);
        } else {
            ring[1] = g_side[kInteriorBefore];
            ring[2] = g_side[kHalfBefore];
            ring[3] = g.edge_vertices[2 * std::size_t(h) + 1];
            ring[4] = f_side[kHalfAfter];
            ring[5] = f_side[kInterior];
            close(ring + 6);
        }
        ++v;
    }
    // The midpoint of interior edge k of face f, from m_k to m_k+1 (always two faces: the corner child k + 1 and the
    // middle child): a face's three at a time, from its corners' halves.
    auto interior_ring = [&](const Index halves[3], Index first_interior, int k) {
        const int next = next_corner(k);
        ring[0] = nv + (halves[k] >> 1);
        ring[1] = child_vertices + (halves[k] ^ 1);
        ring[2] = child_vertices + halves[next];
        ring[3] = nv + (halves[next] >> 1);
        ring[4] = first_interior + next;
        ring[5] = first_interior + prev_corner(k);
        close(ring + 6);
    };
    for (; v < end; ++v) {
        const Index f = (v - halves_end) / 3;
        interior_ring(&corner_halves[3 * std::size_t(f)], interior_edge(f, 0), int((v - halves_end) % 3));
    }
}

void child_edges(const Topology& p, int begin, int end, Index* ends, Index* c, Index* d) {
    const Index nv = p.num_vertices, halves = 2 * p.num_edges();
    auto put = [&](int e, Index a, Index b, Index wing_c, Index wing_d) {
        const int k = e - begin;
        ends[2 * k] = a, ends[2 * k + 1] = b, c[k] = wing_c, d[k] = wing_d;
    };
    // Halves 2h and 2h + 1 of parent edge h share their wings' search.
    for (int h = begin / 2; h < (std::min(end, halves) + 1) / 2; ++h) {
        Index wings[4];
        half_edge_wings(p, h, wings);
        if (2 * h >= begin) put(2 * h, p.edge_vertices[2 * h], nv + h, wings[0], wings[1]);
        if (2 * h + 1 < end) put(2 * h + 1, nv + h, p.edge_vertices[2 * h + 1], wings[2], wings[3]);
    }
    // Interior edges, three per face.
    const int interior_begin = std::max(begin, halves) - halves, interior_end = end - halves;
    for (int f = interior_begin / 3; f < (interior_end + 2) / 3; ++f) {
#if defined(__SSE2__)
        // A face whose edges are all in range, the next face's first too, in four stores rather than twelve: the
        // vector loads read that face's first corner, and the 16-byte stores of C and D spill into its slot.
        if (3 * f >= interior_begin && 3 * f + 3 < interior_end) {
            const __m128i m = _mm_add_epi32(load_corners(&p.face_edges[3 * std::size_t(f)]), _mm_set1_epi32(nv));
            const __m128i v = load_corners(&p.face_vertices[3 * std::size_t(f)]);
            const int k = halves + 3 * f - begin;
            _mm_storeu_si128(reinterpret_cast<__m128i*>(ends + 2 * k),
                             _mm_shuffle_epi32(m, _MM_SHUFFLE(2, 1, 1, 0)));  // m0 m1 m1 m2
            _mm_storel_epi64(reinterpret_cast<__m128i*>(ends + 2 * k + 4),
                             _mm_shuffle_epi32(m, _MM_SHUFFLE(0, 0, 0, 2)));  // m2 m0
            _mm_storeu_si128(reinterpret_cast<__m128i*>(c + k),
                             _mm_shuffle_epi32(v, _MM_SHUFFLE(3, 0, 2, 1)));  // v1 v2 v0
            _mm_storeu_si128(reinterpret_cast<__m128i*>(d + k),
                             _mm_shuffle_epi32(m, _MM_SHUFFLE(3, 1, 0, 2)));  // m2 m0 m1
            continue;
        }
#endif
        for (int k = 0; k < 3; ++k) {
            const int e = halves + 3 * f + k;
            if (e < begin || e >= end) continue;
            Index abcd[4];
            interior_edge(p, f, k, abcd);
            put(e, abcd[0], abcd[1], abcd[2], abcd[3]);
        }
    }
}

void write_half_ends(const Topology& p, int e0, int e1, Index* ends) {
    const Index nv = p.num_vertices;
    for (int e = e0; e < e1; ++e, ends += 4) {  // half 2e = (a, m), 2e + 1 = (m, b)
        ends[0] = p.edge_vertices[2 * e], ends[1] = ends[2] = nv + e, ends[3] = p.edge_vertices[2 * e + 1];
    }
}

void write_half_wings(const Topology& p, int f0, int f1, int e0, int e1, Index* c, Index* d) {
    const Index nv = p.num_vertices;
    // Every edge has a face; where it has no second, its halves' D wings are their own ends (as half_edge_wings).
    for (int e = e0; e < e1; ++e) {
        if (p.edge_face_count(e) >= 2) continue;
        d[2 * e] = nv + e;
        d[2 * e + 1] = p.edge_vertices[2 * e + 1];
    }
    for (int f = f0; f < f1; ++f) {
        const Index* fe = &p.face_edges[3 * f];
        const std::uint8_t* places = &p.face_edge_places[3 * std::size_t(f)];
        for (int k = 0; k < 3; ++k) {
            const int place = places[k] >> 1;
            if (place > 1) continue;
            Index* wing = place == 0 ? c : d;
            face_wings(nv, fe, k, places[k] & 1, wing[2 * fe[k]], wing[2 * fe[k] + 1]);
        }
    }
}

void child_edge_ends(const Topology& p, Index e, Index ends[2]) { child_edge_ends_of(StoredLevel{p}, e, ends); }

namespace {

// write_grandchild_faces for a parent with face_edge_places (Places: which end each face edge starts at, with no
// read of the edge's ends) or without (Refined::Connectivity).
template <bool Places>
void grandchild_faces(const Topology& p, int f0, int f1, Index* out) {
    const Index nv = p.num_vertices, interior_base = 2 * p.num_edges();
    const Index child_vertices = nv + p.num_edges();  // the grandchild's midpoint of child edge E is child_vertices + E
    out += 48 * std::size_t(f0);
    for (int f = f0; f < f1; ++f) {
        const Index* v = &p.face_vertices[3 * f];
        const Index* fe = &p.face_edges[3 * f];
        const Index m[3] = {nv + fe[0], nv + fe[1], nv + fe[2]};
        const Index interior = interior_base + 3 * f;
        // The four children as refine_topology numbers them, each with its corners and edges (edge i from corner i
        // to corner i + 1), then each child split the same way.
        Index corners[4][3], edges[4][3];
        for (int k = 0; k < 3; ++k) {
            const int before = prev_corner(k);
            corners[k][0] = v[k], corners[k][1] = m[k], corners[k][2] = m[before];
            // The halves at v_k of edge k (which v_k starts) and of edge k - 1 (which v_k ends).
            if constexpr (Places) {
                const std::uint8_t* places = &p.face_edge_places[3 * std::size_t(f)];
                edges[k][0] = 2 * fe[k] + 1 - (places[k] & 1);
                edges[k][2] = 2 * fe[before] + (places[before] & 1);
            } else {
                edges[k][0] = child_edge_at(p, fe[k], v[k]);
                edges[k][2] = child_edge_at(p, fe[before], v[k]);
            }
            edges[k][1] = interior + before;
            corners[3][k] = m[k];
            edges[3][k] = interior + k;
        }
        for (int child = 0; child < 4; ++child, out += 12) {
            const Index a = corners[child][0], b = corners[child][1], c = corners[child][2];
            const Index m0 = child_vertices + edges[child][0], m1 = child_vertices + edges[child][1],
                        m2 = child_vertices + edges[child][2];
            out[0] = a, out[1] = m0, out[2] = m2, out[3] = b, out[4] = m1, out[5] = m0;
            out[6] = c, out[7] = m2, out[8] = m1, out[9] = m0, out[10] = m1, out[11] = m2;
        }
    }
}

#if defined(__SSE2__)
// grandchild_faces<true> with 16-byte stores: 12 per face rather than 48 one index at a time, which is what bounds
// the scalar loop (the last level's 1.3M triangles are 3.9M stores). Lane k of each vector below belongs to corner
// child k; a 4 x 4 transpose turns them into the children's rows. Reads four indices (and four places) from 3f, so
// the face after f must exist.
void grandchild_faces_sse2(const Topology& p, int f0, int f1, Index* out) {
    const Index nv = p.num_vertices, interior_base = 2 * p.num_edges();
    const __m128i child_vertices = _mm_set1_epi32(nv + p.num_edges());
    auto select = [](__m128i mask, __m128i if_set, __m128i otherwise) {
        return _mm_or_si128(_mm_and_si128(mask, if_set), _mm_andnot_si128(mask, otherwise));
    };
    const __m128i lanes_0_3 = _mm_setr_epi32(-1, 0, 0, -1), lane_2 = _mm_setr_epi32(0, 0, -1, 0);
    __m128i* o = reinterpret_cast<__m128i*>(out + 48 * std::size_t(f0));
    for (int f = f0; f < f1; ++f, o += 12) {
        const __m128i v = load_corners(&p.face_vertices[3 * std::size_t(f)]);
        const __m128i fe = load_corners(&p.face_edges[3 * std::size_t(f)]);
        const __m128i m = _mm_add_epi32(fe, _mm_set1_epi32(nv));
        // Grandchild midpoints of: the half of edge k at v_k, the half of edge k - 1 at v_k, interior edge k (and k -
        // 1).
        __m128i half_k, half_before;
        corner_halves_sse2(p, f, fe, half_k, half_before);
        half_k = _mm_add_epi32(half_k, child_vertices);
        half_before = _mm_add_epi32(half_before, child_vertices);
        const __m128i interior = _mm_add_epi32(_mm_add_epi32(child_vertices, _mm_set1_epi32(interior_base + 3 * f)),
                                               _mm_setr_epi32(0, 1, 2, 0));
        const __m128i interior_before = corner_before(interior);
        // Corner child k: (v_k, m_k, m_{k-1}), its edges' midpoints half_k, interior_before_k, half_before_k.
        __m128i first[3], second[3], third[3];
        corner_rows(v, half_k, half_before, m, first);
        corner_rows(interior_before, half_k, corner_before(m), half_before, second);
        corner_rows(interior_before, half_k, interior_before, half_before, third);
        for (int k = 0; k < 3; ++k) {
            _mm_storeu_si128(o + 3 * k, first[k]);
            _mm_storeu_si128(o + 3 * k + 1, second[k]);
            _mm_storeu_si128(o + 3 * k + 2, third[k]);
        }
        // The middle child (m_0, m_1, m_2), its edges' midpoints the interior ones: (m0 i0 i2 m1) (i1 i0 m2 i2) (i1 i0
        // i1 i2).
        const __m128i i0 = _mm_shuffle_epi32(interior, _MM_SHUFFLE(0, 2, 0, 0));
        _mm_storeu_si128(o + 9, select(lanes_0_3, _mm_shuffle_epi32(m, _MM_SHUFFLE(1, 0, 0, 0)), i0));
        _mm_storeu_si128(o + 10, select(lane_2, _mm_shuffle_epi32(m, _MM_SHUFFLE(2, 2, 2, 2)),
                                        _mm_shuffle_epi32(interior, _MM_SHUFFLE(2, 0, 0, 1))));
        _mm_storeu_si128(o + 11, _mm_shuffle_epi32(interior, _MM_SHUFFLE(2, 1, 0, 1)));
    }
}
#endif

}  // namespace

void write_grandchild_faces(const Topology& p, int f0, int f1, Index* out) {
    // The places spare a read of each edge's ends from far away (docs/benchmark.md, "Measurements behind the code").
    if (p.face_edge_places.empty()) return grandchild_faces<false>(p, f0, f1, out);
#if defined(__SSE2__)
    const int vector_end = std::clamp(p.num_faces() - 1, f0, f1);  // the vector loads read into the next face
    grandchild_faces_sse2(p, f0, vector_end, out);
    f0 = vector_end;
#endif
    grandchild_faces<true>(p, f0, f1, out);
}

std::vector<std::uint8_t> non_manifold_edges(const Topology& t) {
    // Consistently wound neighbours run along a shared edge in opposite directions. An edge's first face runs along it
    // from its first end (the edge took its ends from that corner), so an edge of two faces winds inconsistently where
    // its second face does so too: a place byte of 0b11 (second face, starts the edge). One pass over the place bytes,
    // rather than counting directions per corner, which reads each corner's edge ends (docs/benchmark.md, "Measurements
    // behind the code").
    std::vector<std::uint8_t> flags(t.num_edges(), 0);
    // Plain pointers: a byte store may alias anything, so the vectors' data pointers would be read again each time.
    std::uint8_t* flag = flags.data();
    const Index* face_offsets = t.edge_face_offsets.data();
    for (int e = 0; e < t.num_edges(); ++e) flag[e] = face_offsets[e + 1] - face_offsets[e] > 2;
    const std::uint8_t* places = t.face_edge_places.data();
    const Index* corner_edges = t.face_edges.data();
    for (std::size_t c = 0; c < t.face_edge_places.size(); ++c)
        if (places[c] == (1 << 1 | 1)) flag[corner_edges[c]] = 1;
    return flags;
}

std::vector<std::uint8_t> non_manifold_vertices(const Topology& t, const std::vector<std::uint8_t>& non_manifold_edge,
                                                int threads) {
    std::vector<std::uint8_t> flags(t.num_vertices, 0);
    auto flag_part = [&](int, int part, int parts) {
        const auto [v0, v1] = part_of(t.num_vertices, part, parts);
        for (int v = v0; v < v1; ++v) {
            const Index first = t.vertex_edge_offsets[v], last = t.vertex_edge_offsets[v + 1];
            if (first == last) continue;
            int face_corners = 0;  // each face at v has two edges at v
            Index boundary_edge = -1;
            bool bad = false;
            for (Index k = first; k < last; ++k) {
                const Index e = t.vertex_edges[k];
                bad |= non_manifold_edge[e] != 0;
                face_corners += t.edge_face_count(e);
                if (t.edge_face_count(e) == 1) boundary_edge = e;
            }
            if (bad) {
                flags[v] = 1;
                continue;
            }
            const int num_faces = face_corners / 2;
            // Walk the fan from a boundary edge (or any edge) and count the faces reached.
            Index e = boundary_edge >= 0 ? boundary_edge : t.vertex_edges[first];
            const Index start = e;
            Index f = t.edge_faces[t.edge_face_offsets[e]];
            int reached = 0;
            while (true) {
                ++reached;
                e = t.other_edge_at_vertex(f, v, e);
                if (e == start || t.edge_face_count(e) != 2 || reached > num_faces) break;
                const Index* faces = &t.edge_faces[t.edge_face_offsets[e]];
                f = faces[0] == f ? faces[1] : faces[0];
            }
            flags[v] = reached != num_faces;
        }
    };
    run_levels(std::max(1, threads), 1, flag_part, kPiecesPerThread);  // taken in turn: a second thread starts late
    return flags;
}

int faces_between(const Topology& t, Index v, Index from, Index to) {
    Index e = from;
    Index f = t.edge_faces[t.edge_face_offsets[e]];
    int count = 0;
    while (true) {
        ++count;
        e = t.other_edge_at_vertex(f, v, e);
        if (e == to || e == from || t.edge_face_count(e) != 2) return count;
        const Index* faces = &t.edge_faces[t.edge_face_offsets[e]];
        f = faces[0] == f ? faces[1] : faces[0];
    }
}

}  // namespace loopsub::detail

namespace loopsub::detail {

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

int child_max_valence(const Topology& parent) { return child_max_valence_of(StoredLevel{parent}); }

int child_max_edge_face_count(const Topology& parent) { return child_max_edge_face_count_of(StoredLevel{parent}); }

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
