// One Loop split (refine_topology): the child's connectivity in one of the three Refined forms, derived from the
// parent through the split's numbering (topology.h) without any search. The child is sized once from the parent's
// counts (sized_child), then each part of the parent's faces, edges and vertices fills its own slots, one function per
// kind of child element (populate_*), so that the parts need no synchronisation. The edges' ends and wings and the
// vertices' rings come from the same helpers that read a child through its parent (child_edges.cpp, rings.cpp); the
// faces' edges are stored 16 bytes at a time with SSE2 where the compiler targets it (write_child_face_edges).
#include <algorithm>
#include <cassert>
#include <cstdint>
#include <cstring>

#include "base/parallel.h"
#include "topology/level_relations.h"
#include "topology/topology.h"
#include "topology/triangle_corners.h"

namespace loopsub::detail {

namespace {

// The edges of child face c (corner child k = c % 4 of parent face f = c / 4: its half of edge k, the interior edge
// across, its half of edge k - 1; the middle child: the three interior edges).
void child_face_edges(const Topology& p, Index c, Index edges[3]) {
    Index vertices[3];
    child_face_of(StoredLevel{p}, c, vertices, edges);
}

// The child faces' edges of parent faces [f0, f1) (12 per face, in refine_topology's numbering) and, where `places` is
// given, their face_edge_places. Corner child k = (v_k, m_k, m_{k-1}) has the half of edge k at v_k, interior edge
// k - 1 and the half of edge k - 1 at v_k; the middle child the three interior edges. The corner children's halves
// keep the parent face's place and direction there; an interior edge has its corner child first (running from
// m_{k-1} to m_k there) and the middle child second.
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

int child_max_valence(const Topology& parent) { return child_max_valence_of(StoredLevel{parent}); }

int child_max_edge_face_count(const Topology& parent) { return child_max_edge_face_count_of(StoredLevel{parent}); }

}  // namespace loopsub::detail
