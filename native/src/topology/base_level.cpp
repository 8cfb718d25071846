// The base level: the connectivity of a validated triangle list (build_base_topology), every later level being a split
// of it (split.cpp), and Topology's own accessors. The edges are found and numbered without hashing or sorting: the
// corners are bucketed by their edge's lower end, each edge numbered by its first corner, in six steps that run in
// parts on the team's threads, each part counting for itself where its items go (part_places).
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <vector>

#include "base/parallel.h"
#include "topology/topology.h"
#include "topology/triangle_corners.h"

namespace loopsub::detail {

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

namespace {

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

// build_base_topology's work: the arrays its six steps share and a function per step, each run on one part of the
// triangles (corners [c0, c1)). Corner c starts its face's edge: the edge's ends, lower and higher. The corners are
// bucketed by their lower end in corner order, each beside its higher end, so that finding an edge's corners is a
// scan of a bucket of about half a valence: no hashing, no sort. An edge is numbered by its first corner, in corner
// order, and its faces are listed in corner order too: a corner's rank among its edge's corners is its face's place
// there.
struct BaseLevelBuild {
    const Index* triangles;
    const Index* given_edges;  // or nullptr: the edges found by their ends
    int num_triangles, num_vertices, parts;
    // Allocated in this order, the topology's arrays last (the constructor): large_allocator.h reuses freed blocks by
    // size, oldest first.
    Topology t;
    LargeVector<Index> low, high, bucket, bucket_high;
    LargeVector<Index> bucket_offsets, first_corner, rank;
    LargeVector<Index> corners_from_first, corners_of_edge;
    std::vector<LargeVector<Index>> corners_at_low, edges_at_vertex;
    std::vector<Index> part_edges, part_edge_corners;
    std::vector<int> part_max_edge_faces;

    BaseLevelBuild(const Index* triangles_, const Index* given_edges_, int num_triangles_, int num_vertices_,
                   int parts_)
        : triangles(triangles_),
          given_edges(given_edges_),
          num_triangles(num_triangles_),
          num_vertices(num_vertices_),
          parts(parts_),
          low(3 * num_triangles_),
          high(3 * num_triangles_),
          bucket(3 * num_triangles_),
          bucket_high(3 * num_triangles_),
          bucket_offsets(std::size_t(num_vertices_) + 1),
          first_corner(3 * num_triangles_),
          rank(3 * num_triangles_),
          corners_from_first(3 * num_triangles_),
          corners_at_low(parts_, LargeVector<Index>(num_vertices_, 0)),
          edges_at_vertex(parts_, LargeVector<Index>(num_vertices_, 0)),
          part_edges(parts_, 0),
          part_edge_corners(parts_, 0),
          part_max_edge_faces(parts_, 0) {
        const int num_corners = 3 * num_triangles;
        t.num_vertices = num_vertices;
        t.face_vertices.resize(num_corners);
        t.face_edges.resize(num_corners);
        t.face_edge_places.resize(num_corners);
        t.edge_faces.resize(num_corners);
        t.vertex_edge_offsets.resize(std::size_t(num_vertices) + 1);
    }

    static int next(int c) { return c % 3 == 2 ? c - 2 : c + 1; }  // the corner after c in its face
    static Index sum_before(const std::vector<Index>& per_part, int part) {
        return std::accumulate(per_part.begin(), per_part.begin() + part, Index(0));
    }

    // Six steps; the edges' arrays are sized between the third and the fourth, once the edges are counted (sized for
    // the most there could be, an edge a corner, their blocks' untouched pages were faulted in by the next plan).
    void run_step(int step, int part) {
        const auto [f0, f1] = part_of(num_triangles, part, parts);
        const int c0 = 3 * f0, c1 = 3 * f1;
        // The part's edges, once the parts have counted theirs (step 2 writes the counts).
        const Index edge0 = step > 2 ? sum_before(part_edges, part) : 0,
                    edge1 = step > 2 ? edge0 + part_edges[part] : 0;
        switch (step) {
            case 0: count_ends(part, c0, c1); break;
            case 1:
                if (!given_edges) bucket_corners(part, c0, c1);
                break;
            case 2: given_edges ? take_given_edges() : find_edges(part, c0, c1); break;
            case 3: number_edges(part, c0, c1, edge0); break;
            case 4: place_faces(part, c0, c1, edge0, edge1); break;
            case 5: link_faces_and_vertices(part, c0, c1, edge0, edge1); break;
        }
    }
    // Between the third step and the fourth.
    void size_edges() {
        const std::size_t num_edges = std::size_t(sum_before(part_edges, parts));
        t.edge_vertices.resize(2 * num_edges);
        t.edge_face_offsets.resize(num_edges + 1);
        t.edge_wing_c.resize(num_edges);
        t.edge_wing_d.resize(num_edges);
        t.vertex_edges.resize(2 * num_edges);
        t.vertex_vertices.resize(2 * num_edges);
        corners_of_edge.resize(num_edges);
    }
    Topology finish() {
        for (int v = 0; v < num_vertices; ++v) t.max_valence = std::max(t.max_valence, t.valence(v));
        t.max_edge_face_count = *std::max_element(part_max_edge_faces.begin(), part_max_edge_faces.end());
        return std::move(t);
    }

    // Step 0: each corner's edge's ends, lower and higher; the part counts its corners by lower end.
    void count_ends(int part, int c0, int c1) {
        for (int c = c0; c < c1; ++c) {
            const Index a = triangles[c], b = triangles[next(c)];
            t.face_vertices[c] = a;
            low[c] = std::min(a, b), high[c] = std::max(a, b);
            ++corners_at_low[part][low[c]];
        }
    }
    // Step 1: the corners into their buckets.
    void bucket_corners(int part, int c0, int c1) {
        LargeVector<Index> place(num_vertices);
        part_places(corners_at_low, part, place.data(), part == 0 ? bucket_offsets.data() : nullptr);
        for (int c = c0; c < c1; ++c) {
            const Index slot = place[low[c]]++;
            bucket[slot] = c;
            bucket_high[slot] = high[c];
        }
    }
    // Step 2: each corner finds its edge's first corner; a first corner ranks the edge's corners.
    void find_edges(int part, int c0, int c1) {
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
    }
    // Step 2 where the edges are given (one part): an edge's first corner is the first that names it, and the corners
    // that name it rank in corner order, as find_edges ranks those of the same ends.
    void take_given_edges() {
        const int num_corners = 3 * num_triangles;
        LargeVector<Index> first_naming(std::size_t(num_corners), -1), named(std::size_t(num_corners), 0);
        Index edges = 0;
        for (int c = 0; c < num_corners; ++c) {
            const Index given = given_edges[c];
            if (first_naming[given] < 0) first_naming[given] = c, ++edges;
            first_corner[c] = first_naming[given];
            rank[c] = named[given]++;
        }
        for (int c = 0; c < num_corners; ++c)
            if (first_corner[c] == c) corners_from_first[c] = named[given_edges[c]];
        part_edges[0] = edges;
    }
    // Step 3: the part's first corners number their edges.
    void number_edges(int part, int c0, int c1, Index edge0) {
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
    }
    // Step 4: the faces' edges and places; the edges' face offsets, and the part's edges counted by vertex.
    void place_faces(int part, int c0, int c1, Index edge0, Index edge1) {
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
    }
    // Step 5: the edges' faces and wings; the vertices' edges and rings.
    void link_faces_and_vertices(int part, int c0, int c1, Index edge0, Index edge1) {
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
    }
};

}  // namespace

Topology build_base_topology(const Index* triangles, int num_triangles, int num_vertices, int threads,
                             const Index* triangle_edges) {
    // Below a few thousand triangles the parts' meetings would cost more than their share of the work.
    const int parts = num_triangles >= 2048 && !triangle_edges ? std::max(1, threads) : 1;
    BaseLevelBuild build(triangles, triangle_edges, num_triangles, num_vertices, parts);
    run_levels(parts, 3, [&build](int step, int part, int) { build.run_step(step, part); });
    build.size_edges();
    run_levels(parts, 3, [&build](int later, int part, int) { build.run_step(3 + later, part); });
    return build.finish();
}

}  // namespace loopsub::detail
