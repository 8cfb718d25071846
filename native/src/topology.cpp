#include "topology.h"

#include <algorithm>
#include <numeric>
#include <utility>

#include "parallel.h"

namespace loopsub::detail {

namespace {

inline int next_corner(int corner) { return corner == 2 ? 0 : corner + 1; }
inline int prev_corner(int corner) { return corner == 0 ? 2 : corner - 1; }

// Prefix sums of per-item counts: offsets has one more entry than counts.
LargeVector<Index> offsets_from_counts(const LargeVector<Index>& counts) {
    LargeVector<Index> offsets(counts.size() + 1);
    offsets[0] = 0;
    std::partial_sum(counts.begin(), counts.end(), offsets.begin() + 1);
    return offsets;
}

void fill_edge_faces(Topology& t) {
    const int ne = t.num_edges(), nf = t.num_faces();
    LargeVector<Index> counts(ne, 0);
    for (Index e : t.face_edges) ++counts[e];
    t.edge_face_offsets = offsets_from_counts(counts);
    t.edge_faces.resize(t.edge_face_offsets[ne]);
    LargeVector<Index> cursor(t.edge_face_offsets.begin(), t.edge_face_offsets.end() - 1);
    for (int f = 0; f < nf; ++f)
        for (int k = 0; k < 3; ++k) t.edge_faces[cursor[t.face_edges[3 * f + k]]++] = f;
}

void fill_vertex_edges(Topology& t) {
    const int ne = t.num_edges();
    LargeVector<Index> counts(t.num_vertices, 0);
    for (Index v : t.edge_vertices) ++counts[v];
    t.vertex_edge_offsets = offsets_from_counts(counts);
    t.vertex_edges.resize(t.vertex_edge_offsets[t.num_vertices]);
    LargeVector<Index> cursor(t.vertex_edge_offsets.begin(), t.vertex_edge_offsets.end() - 1);
    for (int e = 0; e < ne; ++e) {
        t.vertex_edges[cursor[t.edge_vertices[2 * e]]++] = e;
        t.vertex_edges[cursor[t.edge_vertices[2 * e + 1]]++] = e;
    }
}

// The winged-edge neighbourhood by lookup, for the base level (refined levels derive it).
void fill_neighbourhood(Topology& t) {
    t.vertex_vertices.resize(t.vertex_edges.size());
    for (int v = 0; v < t.num_vertices; ++v)
        for (Index k = t.vertex_edge_offsets[v]; k < t.vertex_edge_offsets[v + 1]; ++k) t.vertex_vertices[k] = t.other_end(t.vertex_edges[k], v);
    const int ne = t.num_edges();
    t.edge_opposite_c.resize(ne);
    t.edge_opposite_d.resize(ne);
    for (int e = 0; e < ne; ++e) {
        const int faces = t.edge_face_count(e);
        const Index* f = &t.edge_faces[t.edge_face_offsets[e]];
        t.edge_opposite_c[e] = faces > 0 ? t.opposite_vertex(f[0], e) : t.edge_vertices[2 * e];
        t.edge_opposite_d[e] = faces > 1 ? t.opposite_vertex(f[1], e) : t.edge_vertices[2 * e + 1];
    }
}

}  // namespace

int Topology::max_valence() const {
    int largest = 0;
    for (int v = 0; v < num_vertices; ++v) largest = std::max(largest, valence(v));
    return largest;
}

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

Topology build_base_topology(const Index* triangles, int num_triangles, int num_vertices) {
    Topology t;
    t.num_vertices = num_vertices;
    t.face_vertices.assign(triangles, triangles + 3 * std::size_t(num_triangles));
    const int num_corners = 3 * num_triangles;

    // Bucket the corners' edges by their lower vertex, in corner order, so that finding an edge's first
    // corner is a scan of a bucket of about half a valence: no hashing, no sort.
    LargeVector<Index> bucket_counts(num_vertices, 0);
    auto low_end = [&](int c) {
        const Index a = t.face_vertices[c], b = t.face_vertices[c - c % 3 + next_corner(c % 3)];
        return a < b ? a : b;
    };
    auto high_end = [&](int c) {
        const Index a = t.face_vertices[c], b = t.face_vertices[c - c % 3 + next_corner(c % 3)];
        return a < b ? b : a;
    };
    for (int c = 0; c < num_corners; ++c) ++bucket_counts[low_end(c)];
    const LargeVector<Index> bucket_offsets = offsets_from_counts(bucket_counts);
    LargeVector<Index> bucket(num_corners);
    {
        LargeVector<Index> cursor(bucket_offsets.begin(), bucket_offsets.end() - 1);
        for (int c = 0; c < num_corners; ++c) bucket[cursor[low_end(c)]++] = c;
    }

    t.face_edges.resize(num_corners);
    t.edge_vertices.reserve(num_corners);  // at most one edge per corner
    for (int c = 0; c < num_corners; ++c) {
        const Index lo = low_end(c), hi = high_end(c);
        int first = c;
        for (Index k = bucket_offsets[lo]; k < bucket_offsets[lo + 1]; ++k) {
            if (high_end(bucket[k]) == hi) {
                first = bucket[k];
                break;
            }
        }
        if (first == c) {
            t.face_edges[c] = t.num_edges();
            t.edge_vertices.push_back(t.face_vertices[c]);
            t.edge_vertices.push_back(t.face_vertices[c - c % 3 + next_corner(c % 3)]);
        } else {
            t.face_edges[c] = t.face_edges[first];
        }
    }
    fill_edge_faces(t);
    fill_vertex_edges(t);
    fill_neighbourhood(t);
    return t;
}

Topology refine_topology(const Topology& p, Refined what, int threads) {
    const int nv = p.num_vertices, ne = p.num_edges(), nf = p.num_faces();
    const bool faces_only = what == Refined::FacesOnly, full = what == Refined::Full;
    Topology c;
    c.num_vertices = nv + ne;
    const Index interior_base = 2 * ne;
    const std::size_t child_edges = 2 * std::size_t(ne) + 3 * std::size_t(nf);

    // Every array is sized first; then each thread fills its share of faces, edges and vertices. Each child slot
    // is written by exactly one parent element, and every offset has a closed form in the parent's, so the parts
    // need no synchronisation.
    c.face_vertices.resize(12 * std::size_t(nf));
    if (!faces_only) {
        c.edge_vertices.resize(2 * child_edges);
        c.face_edges.resize(12 * std::size_t(nf));
        c.edge_opposite_c.resize(child_edges);
        c.edge_opposite_d.resize(child_edges);
        // An old vertex keeps its valence (the halves of its edges, in order); the midpoint of edge e has its two
        // halves and, per face of e, the two interior edges that meet it.
        c.vertex_edge_offsets.resize(std::size_t(c.num_vertices) + 1);
        c.vertex_vertices.resize(std::size_t(p.vertex_edge_offsets[nv]) + 2 * std::size_t(ne) + 2 * std::size_t(p.edge_face_offsets[ne]));
        if (full) {
            // A half of parent edge e has e's faces; an interior edge has two.
            c.edge_face_offsets.resize(child_edges + 1);
            c.edge_faces.resize(2 * std::size_t(p.edge_face_offsets[ne]) + 6 * std::size_t(nf));
            c.vertex_edges.resize(c.vertex_vertices.size());
        }
    }
    // (A FacesOnly child's parent may lack its edge faces and vertex edges: it was refined ForStencils.)
    const Index faces_of_halves = faces_only ? 0 : 2 * p.edge_face_offsets[ne];
    const Index edges_of_old = faces_only ? 0 : p.vertex_edge_offsets[nv];

    run_levels(std::max(1, threads), 1, [&](int, int part, int parts) {
        auto slice = [part, parts](int n) {
            return std::pair<int, int>(int(std::int64_t(n) * part / parts), int(std::int64_t(n) * (part + 1) / parts));
        };
        const auto [f0, f1] = slice(nf);
        const auto [e0, e1] = slice(ne);
        const auto [v0, v1] = slice(nv);

        for (int f = f0; f < f1; ++f) {
            const Index* v = &p.face_vertices[3 * f];
            const Index m0 = nv + p.face_edges[3 * f], m1 = nv + p.face_edges[3 * f + 1], m2 = nv + p.face_edges[3 * f + 2];
            Index* out = &c.face_vertices[12 * std::size_t(f)];
            out[0] = v[0], out[1] = m0, out[2] = m2;
            out[3] = v[1], out[4] = m1, out[5] = m0;
            out[6] = v[2], out[7] = m2, out[8] = m1;
            out[9] = m0, out[10] = m1, out[11] = m2;
        }
        if (faces_only) return;

        for (int e = e0; e < e1; ++e) {
            const Index a = p.edge_vertices[2 * e], b = p.edge_vertices[2 * e + 1], m = nv + e;
            c.edge_vertices[4 * e + 0] = a, c.edge_vertices[4 * e + 1] = m;
            c.edge_vertices[4 * e + 2] = m, c.edge_vertices[4 * e + 3] = b;
        }
        for (int f = f0; f < f1; ++f) {
            const Index* v = &p.face_vertices[3 * f];
            const Index* fe = &p.face_edges[3 * f];
            const Index interior = interior_base + 3 * f;  // interior edge k joins midpoints k and k + 1
            for (int k = 0; k < 3; ++k) {
                const std::size_t edge = 2 * std::size_t(interior + k);
                c.edge_vertices[edge] = nv + fe[k];
                c.edge_vertices[edge + 1] = nv + fe[next_corner(k)];
            }
            Index* out = &c.face_edges[12 * std::size_t(f)];
            for (int k = 0; k < 3; ++k) {
                // Corner child k = (v_k, m_k, m_{k-1}): half of edge k at v_k, interior edge k-1, half of edge k-1 at v_k.
                out[3 * k + 0] = child_edge_at(p, fe[k], v[k]);
                out[3 * k + 1] = interior + prev_corner(k);
                out[3 * k + 2] = child_edge_at(p, fe[prev_corner(k)], v[k]);
            }
            out[9] = interior, out[10] = interior + 1, out[11] = interior + 2;
        }

        // Edge faces: a half of parent edge e lies in the corner child, at its end, of each face of e; interior
        // edge k of face f lies in the corner child k + 1 and the middle child.
        // Opposite vertices: a half lies in a corner child (v_k, m_k, m_{k-1}), opposite the other midpoint there;
        // interior edge k lies opposite v_{k+1} in its corner child and opposite m_{k-1} in the middle child.
        for (int e = e0; e < e1; ++e) {
            const Index count = p.edge_face_count(e);
            if (full) {
                c.edge_face_offsets[2 * e] = 2 * p.edge_face_offsets[e];
                c.edge_face_offsets[2 * e + 1] = 2 * p.edge_face_offsets[e] + count;
            }
            Index* at_a = full ? &c.edge_faces[c.edge_face_offsets[2 * e]] : nullptr;
            Index* at_b = full ? at_a + count : nullptr;
            const Index a = p.edge_vertices[2 * e], b = p.edge_vertices[2 * e + 1], m = nv + e;
            Index opposite_at_a[2] = {a, m}, opposite_at_b[2] = {m, b};  // (c, d) when faces are missing
            int face = 0;
            for (Index k = p.edge_face_offsets[e]; k < p.edge_face_offsets[e + 1]; ++k, ++face) {
                const Index f = p.edge_faces[k];
                const Index* fe = &p.face_edges[3 * f];
                const int local = fe[0] == e ? 0 : fe[1] == e ? 1 : 2;  // edge `local` runs from corner local to local+1
                const bool a_first = p.face_vertices[3 * f + local] == a;
                if (full) {
                    *at_a++ = 4 * f + (a_first ? local : next_corner(local));
                    *at_b++ = 4 * f + (a_first ? next_corner(local) : local);
                }
                if (face < 2) {
                    const Index before = nv + fe[prev_corner(local)], after = nv + fe[next_corner(local)];
                    opposite_at_a[face] = a_first ? before : after;
                    opposite_at_b[face] = a_first ? after : before;
                }
            }
            c.edge_opposite_c[2 * e] = opposite_at_a[0], c.edge_opposite_d[2 * e] = opposite_at_a[1];
            c.edge_opposite_c[2 * e + 1] = opposite_at_b[0], c.edge_opposite_d[2 * e + 1] = opposite_at_b[1];
        }
        for (int f = f0; f < f1; ++f) {
            const Index* fe = &p.face_edges[3 * f];
            for (int k = 0; k < 3; ++k) {
                const Index edge = interior_base + 3 * f + k;
                if (full) {
                    const Index first = faces_of_halves + 2 * (3 * f + k);
                    c.edge_face_offsets[edge] = first;
                    c.edge_faces[first] = 4 * f + next_corner(k);
                    c.edge_faces[first + 1] = 4 * f + 3;
                }
                c.edge_opposite_c[edge] = p.face_vertices[3 * f + next_corner(k)];
                c.edge_opposite_d[edge] = nv + fe[prev_corner(k)];
            }
        }
        if (full && part + 1 == parts) c.edge_face_offsets[child_edges] = faces_of_halves + 6 * nf;

        for (int v = v0; v < v1; ++v) {
            c.vertex_edge_offsets[v] = p.vertex_edge_offsets[v];
            // Pointer arithmetic, not &vector[i]: a loose vertex has no ring, and its offset may be the arrays' end
            // (or the arrays empty, when no vertex has an edge).
            Index* neighbours = c.vertex_vertices.data() + p.vertex_edge_offsets[v];
            for (Index k = p.vertex_edge_offsets[v]; k < p.vertex_edge_offsets[v + 1]; ++k) *neighbours++ = nv + p.vertex_edges[k];
            if (!full) continue;
            Index* edges = c.vertex_edges.data() + p.vertex_edge_offsets[v];
            for (Index k = p.vertex_edge_offsets[v]; k < p.vertex_edge_offsets[v + 1]; ++k) *edges++ = child_edge_at(p, p.vertex_edges[k], v);
        }
        for (int e = e0; e < e1; ++e) {
            const Index first = edges_of_old + 2 * e + 2 * p.edge_face_offsets[e];
            c.vertex_edge_offsets[nv + e] = first;
            Index* neighbours = c.vertex_vertices.data() + first;
            Index* edges = full ? c.vertex_edges.data() + first : nullptr;
            *neighbours++ = p.edge_vertices[2 * e];
            *neighbours++ = p.edge_vertices[2 * e + 1];
            if (full) *edges++ = 2 * e, *edges++ = 2 * e + 1;
            for (Index k = p.edge_face_offsets[e]; k < p.edge_face_offsets[e + 1]; ++k) {
                const Index f = p.edge_faces[k];
                const Index* fe = &p.face_edges[3 * f];
                const int local = fe[0] == e ? 0 : fe[1] == e ? 1 : 2;
                *neighbours++ = nv + fe[next_corner(local)];
                *neighbours++ = nv + fe[prev_corner(local)];
                if (full) {
                    *edges++ = interior_base + 3 * f + local;               // joins midpoints local and local + 1
                    *edges++ = interior_base + 3 * f + prev_corner(local);  // joins midpoints local - 1 and local
                }
            }
        }
        if (part + 1 == parts) c.vertex_edge_offsets[c.num_vertices] = Index(c.vertex_vertices.size());
    });
    return c;
}

std::vector<std::uint8_t> non_manifold_edges(const Topology& t) {
    std::vector<std::uint8_t> flags(t.num_edges(), 0);
    for (int e = 0; e < t.num_edges(); ++e) {
        const int count = t.edge_face_count(e);
        if (count > 2) {
            flags[e] = 1;
        } else if (count == 2) {
            // Consistently wound neighbours run along a shared edge in opposite directions.
            int direction = 0;
            for (Index k = t.edge_face_offsets[e]; k < t.edge_face_offsets[e + 1]; ++k) {
                const Index f = t.edge_faces[k];
                for (int corner = 0; corner < 3; ++corner)
                    if (t.face_edges[3 * f + corner] == e) direction += t.face_vertices[3 * f + corner] == t.edge_vertices[2 * e] ? 1 : -1;
            }
            flags[e] = direction != 0;
        }
    }
    return flags;
}

std::vector<std::uint8_t> non_manifold_vertices(const Topology& t, const std::vector<std::uint8_t>& non_manifold_edge) {
    std::vector<std::uint8_t> flags(t.num_vertices, 0);
    for (int v = 0; v < t.num_vertices; ++v) {
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

VertexNeighbourhood::VertexNeighbourhood(const Topology& level, const Topology* parent_if_derived)
    : level_(level), parent_(parent_if_derived) {}

void VertexNeighbourhood::edges(Index v, std::vector<Index>& out) const {
    out.clear();
    if (!parent_) {
        out.assign(level_.vertex_edges.begin() + level_.vertex_edge_offsets[v], level_.vertex_edges.begin() + level_.vertex_edge_offsets[v + 1]);
        return;
    }
    const Topology& p = *parent_;
    const Index nv = p.num_vertices, interior_base = 2 * p.num_edges();
    if (v < nv) {
        for (Index k = p.vertex_edge_offsets[v]; k < p.vertex_edge_offsets[v + 1]; ++k) out.push_back(child_edge_at(p, p.vertex_edges[k], v));
        return;
    }
    const Index e = v - nv;
    out.push_back(2 * e);
    out.push_back(2 * e + 1);
    for (Index k = p.edge_face_offsets[e]; k < p.edge_face_offsets[e + 1]; ++k) {
        const Index f = p.edge_faces[k];
        const Index* fe = &p.face_edges[3 * f];
        const int local = fe[0] == e ? 0 : fe[1] == e ? 1 : 2;
        out.push_back(interior_base + 3 * f + local);
        out.push_back(interior_base + 3 * f + prev_corner(local));
    }
}

int VertexNeighbourhood::edge_face_count(Index e) const {
    if (!parent_) return level_.edge_face_count(e);
    return e < 2 * parent_->num_edges() ? parent_->edge_face_count(e / 2) : 2;
}

int VertexNeighbourhood::faces_between(Index v, Index from, Index to) const {
    if (!parent_) return detail::faces_between(level_, v, from, to);
    // An old vertex's fan is its parent's, a child face per parent face; a midpoint sees three child faces of
    // each parent face between its two halves.
    if (v < parent_->num_vertices) return detail::faces_between(*parent_, v, from / 2, to / 2);
    const Index e = v - parent_->num_vertices;
    return (from == 2 * e && to == 2 * e + 1) || (from == 2 * e + 1 && to == 2 * e) ? 3 : -1;
}

}  // namespace loopsub::detail
