// Mesh connectivity as flat index arrays with offsets (OpenSubdiv's Vtr in spirit): the winged-edge information the
// rules read (docs/rules.md, "Connectivity") — per edge its vertices and faces, per vertex its edges — and no more.
#pragma once

#include <algorithm>
#include <cassert>
#include <cstdint>
#include <vector>

#include "base/large_allocator.h"

namespace loopsub::detail {

using Index = std::int32_t;

struct Topology {
    int num_vertices = 0;
    LargeVector<Index> face_vertices;  // 3 per face, counter-clockwise
    LargeVector<Index> face_edges;     // 3 per face: edge i joins corner i and corner i + 1
    LargeVector<Index> edge_vertices;  // 2 per edge
    // Faces of edge e: edge_faces[edge_face_offsets[e] .. edge_face_offsets[e + 1]).
    LargeVector<Index> edge_face_offsets, edge_faces;
    // Edges of vertex v: vertex_edges[vertex_edge_offsets[v] .. vertex_edge_offsets[v + 1]).
    LargeVector<Index> vertex_edge_offsets, vertex_edges;
    // The winged-edge neighbourhood the masks read: vertex_vertices[k] is the other end of vertex_edges[k] (the rings);
    // edge_wing_c / _d[e] are the wings of edge e, the vertices opposite it in its first and second face (its own first
    // / second vertex where the face is missing).
    LargeVector<Index> vertex_vertices, edge_wing_c, edge_wing_d;
    // Beside face_edges, per corner k of face f: bit 0 set where corner k is the first vertex of edge k, the bits
    // above the face's place among that edge's faces (0 or 1; 2 for any after the first two). What a pass in face
    // order needs to put a face's share of its edges' wings in place without looking the face up in each edge's
    // list, which, in edge order, waits on a face read from far away (write_half_wings). The base and Refined::Full
    // levels only.
    LargeVector<std::uint8_t> face_edge_places;
    // Counted at the base and carried through each split in closed form (no pass over a level): an old vertex keeps
    // its valence, a midpoint has two more than twice its edge's face count, and a child edge has its parent edge's
    // face count or, inside a face, two.
    int max_valence = 0;  // 0 for a mesh without edges
    int max_edge_face_count = 0;

    int num_faces() const { return int(face_vertices.size() / 3); }
    int num_edges() const { return int(edge_vertices.size() / 2); }
    int edge_face_count(Index e) const { return edge_face_offsets[e + 1] - edge_face_offsets[e]; }
    int valence(Index v) const { return vertex_edge_offsets[v + 1] - vertex_edge_offsets[v]; }
    Index other_end(Index e, Index v) const {
        return edge_vertices[2 * e] == v ? edge_vertices[2 * e + 1] : edge_vertices[2 * e];
    }
    // The vertex of face f that is not on edge e.
    Index opposite_vertex(Index f, Index e) const;
    // The edge of face f at vertex v other than e (both edges of f at v must exist).
    Index other_edge_at_vertex(Index f, Index v, Index e) const;
};

// Connectivity of a validated triangle list. Edges are numbered in order of first appearance, walking the
// triangles and their corners in order. Large lists are split among `threads` parts (on the team in scope).
// An edge is the triangles' edges with the same ends; given `triangle_edges` (3 per triangle: the edge from corner k
// to corner k + 1 by any numbers below 3 * num_triangles, the same number always on the same ends), it is those with
// the same number: a refined level's edges, two of which may share their ends (the edges inside the two faces at an
// interior vertex of valence 2).
Topology build_base_topology(const Index* triangles, int num_triangles, int num_vertices, int threads = 1,
                             const Index* triangle_edges = nullptr);

// Child connectivity of one Loop split, derived from the parent without any search. The split's numbering, which
// everything that reads a child through its parent relies on (child_edge_ends, child_edges, write_child_rings,
// write_grandchild_faces, VertexNeighbourhood, the fan kernels, face-varying layers, Plan::output_parent_triangles):
//   vertices  old vertex v stays v; the midpoint of parent edge e is vertex num_vertices + e
//   edges     the halves of parent edge e (ends a, b) are 2e = (a, m) and 2e + 1 = (m, b); the interior edges of parent
//             face f are 2 * num_edges + 3f + k, joining the midpoints of its edges k and k + 1
//   faces     parent face f (corners v_k, edge k from v_k to v_k+1, its midpoint m_k) gives the corner children
//             4f + k = (v_k, m_k, m_k-1) for k < 3 and the middle child 4f + 3 = (m_0, m_1, m_2)
// The winged-edge neighbourhood follows from the same numbering, without lookups.
enum class Refined {
    Full,          // everything
    Connectivity,  // no winged-edge neighbourhood (vertex_vertices, edge_wing_c / _d): a level whose stencils are
                   // derived from its parent (LevelStencils::derived_from)
    FacesOnly      // face_vertices only: the last level (with the limit surface, its pass reads the rings from the
                   // parent, write_ordered_child_rings, and its few vertices next to features through the parent,
                   // VertexNeighbourhood)
};
// `threads` share the work (each writes its own slice of every array).
Topology refine_topology(const Topology& parent, Refined what, int threads = 1);
// Whether `child`, a split of `parent` in any Refined form, holds the numbering above in every array it has, exactly as
// the derivations from the parent give it. Walks the whole level: Debug builds (the sanitizer run) assert it after
// each split. The parent must hold its edge faces and vertex edges unless the child has faces only.
bool follows_split_numbering(const Topology& parent, const Topology& child);

// The ends of child edge e, from the parent alone.
void child_edge_ends(const Topology& parent, Index e, Index ends[2]);

// Corner 3 f + k of face f, at a vertex v: the face's next corner a and previous corner b, its edges from v to a (edge
// k) and from b to v (edge k - 1), and whether v is each of the two edges' first end (which a split's numbering of
// their halves at v follows).
struct FanCorner {
    Index corner, a, b, edge_a, edge_b;
    bool v_first_a, v_first_b;
};
inline bool operator==(const FanCorner& x, const FanCorner& y) {
    return x.corner == y.corner && x.a == y.a && x.b == y.b && x.edge_a == y.edge_a && x.edge_b == y.edge_b &&
           x.v_first_a == y.v_first_a && x.v_first_b == y.v_first_b;
}

// The connectivity around single vertices and edges of a level, whether the level holds it (Refined::Full and the
// base) or not (faces only, or not stored at all): then it is derived from the parent level through the numbering, as
// refine_topology would have written it, and the parent may itself be known so, through its own parent (the last level
// of a limit plan read through its grandparent, the level between never built). Classifying the few vertices next to
// a crease needs no more.
class VertexNeighbourhood {
public:
    // `history`: where known, the vertex counts of the levels up to this one, the base's first (a plan's
    // level_num_vertices while it builds this level), which spares faces_between its walk for vertices made by a split;
    // with `base` (the base level's faces and edge faces) too, a base vertex's walk is the base's.
    VertexNeighbourhood(const Topology& level, const Topology* parent_if_derived,
                        const std::vector<int>* history = nullptr, const Topology* base = nullptr);
    // A level of `num_vertices` vertices known through `parent`: a stored level, or one itself known through its
    // parent.
    VertexNeighbourhood(int num_vertices, const Topology& parent, const std::vector<int>* history = nullptr,
                        const Topology* base = nullptr);
    VertexNeighbourhood(int num_vertices, const VertexNeighbourhood& parent, const std::vector<int>* history = nullptr,
                        const Topology* base = nullptr);
    int num_vertices() const { return num_vertices_; }
    int num_edges() const { return num_edges_; }
    int num_faces() const { return num_faces_; }
    int max_valence() const;
    int max_edge_face_count() const;
    // Inline where stored, as edge_face_count: classifying the vertices next to a crease asks for them edge by edge.
    void edge_ends(Index e, Index ends[2]) const {
        if (level_) {
            ends[0] = level_->edge_vertices[2 * e], ends[1] = level_->edge_vertices[2 * e + 1];
            return;
        }
        derived_edge_ends(e, ends);
    }
    Index other_end(Index e, Index v) const {
        Index ends[2];
        edge_ends(e, ends);
        return ends[0] == v ? ends[1] : ends[0];
    }
    // The child edge of edge e at its end vertex v (child_edge_at, below).
    Index child_edge_at(Index e, Index v) const {
        Index ends[2];
        edge_ends(e, ends);
        assert(ends[0] == v || ends[1] == v);
        return 2 * e + (ends[0] == v ? 0 : 1);
    }
    // The edges of v, in the order of its vertex_vertices.
    void edges(Index v, std::vector<Index>& out) const;
    int edge_face_count(Index e) const {
        if (level_) return level_->edge_face_count(e);
        if (parent_) return e < 2 * parent_->num_edges() ? parent_->edge_face_count(e / 2) : 2;
        return e < 2 * derived_parent_->num_edges() ? derived_parent_->edge_face_count(e / 2) : 2;
    }
    // visit(f) for each face f of edge e, in the order of Topology::edge_faces.
    template <typename Visit>
    void for_each_edge_face(Index e, const Visit& visit) const {
        // Through a plain function: a level derived from a derived one visits through its parent's visit, which
        // would otherwise make a new type of visitor for every level below.
        visit_edge_faces(
            e, [](const void* context, Index f) { (*static_cast<const Visit*>(context))(f); }, &visit);
    }
    // The vertices opposite edge e in its first two faces (each end repeated where a face is missing), as
    // Topology::edge_wing_c / _d.
    void wings(Index e, Index& c, Index& d) const;
    // The edges of face f, as Topology::face_edges.
    void face_edges(Index f, Index edges[3]) const;
    // The corners of face f, as Topology::face_vertices: derived, without a read of the level's own (large) array.
    void face_vertices(Index f, Index vertices[3]) const;
    // The corners and edges of face f at once: derived, they share their reads of the parent.
    void face(Index f, Index vertices[3], Index edges[3]) const;
    // The corners at vertex v with their faces (FanCorner), in increasing corner order. The level, or its parent, must
    // hold its edge faces and vertex edges.
    void fan(Index v, std::vector<FanCorner>& out) const;
    // faces_between (below) on this level. Derived: for a midpoint, only between its two halves (the only edges
    // at a midpoint that can be sharp); -1 otherwise.
    int faces_between(Index v, Index from, Index to) const;

private:
    VertexNeighbourhood(const Topology* level, const Topology* parent, const VertexNeighbourhood* derived_parent,
                        int num_vertices, const std::vector<int>* history, const Topology* base);
    void derived_edge_ends(Index e, Index ends[2]) const;
    void visit_edge_faces(Index e, void (*visit)(const void* context, Index f), const void* context) const;
    // Runs derive(parent) on the parent level as the derivations read it, stored or itself derived.
    template <typename Derive>
    decltype(auto) through_parent(const Derive& derive) const;

    const Topology* level_;                      // where stored, else null
    const Topology* parent_;                     // where derived from a stored parent
    const VertexNeighbourhood* derived_parent_;  // where derived from a parent known through its own
    int num_vertices_, num_edges_ = 0, num_faces_ = 0;
    const std::vector<int>* history_;
    const Topology* base_;
};

// A child level known through its parent's numbering instead of stored, exactly as refine_topology would have written
// it: the tables of forms "interior" (filled from the parent) and "derived" (a chunk at a time as the kernels run;
// LevelStencils explains the forms) are written by the functions below. The parent must hold its edge faces and vertex
// edges (Refined::Full or Connectivity, or the base).
// Where child vertex v's one-ring starts in refine_topology's vertex_vertices, for v from 0 to the number of child
// vertices: an old vertex keeps its parent's offset, after them each midpoint has its ends and two per face.
inline Index child_ring_offset(const Topology& parent, Index v) {
    const Index nv = parent.num_vertices;
    if (v <= nv) return parent.vertex_edge_offsets[v];
    const Index e = v - nv;
    return parent.vertex_edge_offsets[nv] + 2 * e + 2 * parent.edge_face_offsets[e];
}
// The one-rings of child vertices [begin, end), in refine_topology's vertex_vertices order, written from ring[0]:
// vertex v's at child_ring_offset(v) - child_ring_offset(begin).
void write_child_rings(const Topology& parent, int begin, int end, Index* ring);
// write_child_rings, but counter-clockwise around every vertex whose fan closes into one disk (in a child triangle
// (v, a, b), b follows a around v), from the numbering, without the child's faces. Vertices with apart[v] set keep
// write_child_rings' order; one whose fan is no single disk too, and gets apart[v] set.
void write_ordered_child_rings(const Topology& parent, int begin, int end, std::uint8_t* apart, Index* ring);
// A level read two splits on, for the rings of its grandchild (write_ordered_grandchild_rings): a surface, every edge
// in one or two faces (two running along it opposite ways) and every fan one fan, so that every grandchild vertex made
// by a split off the boundary has six neighbours counter-clockwise. Plain pointers into the level's arrays, which a
// plan keeps where its tables hold them.
struct Grandparent {
    Index num_vertices = 0, num_edges = 0, num_faces = 0;
    const Index* edge_vertices = nullptr;  // 2 per edge
    // 8 per edge, 4 per side: first of the face that runs along the edge from its first end (the edge its edge k),
    // then of the other (its first entry -1 for a boundary edge, whose other three are not written): the grandchild
    // vertices that face gives the rings about the edge (EdgeSide).
    const Index* edge_sides = nullptr;
    // 3 per face: the child edge of face edge k at corner k, where the edge starts in the face (the other half, at
    // corner k + 1, is this one xor 1).
    const Index* corner_halves = nullptr;
};
// The entries of a side of an edge in Grandparent::edge_sides, for the face and the edge its edge k: the grandchild
// vertices on the face's interior edges k and k - 1, on the half of its edge k - 1 at that edge's end, and on the half
// of its edge k + 1 at that edge's start.
enum EdgeSide { kInterior, kInteriorBefore, kHalfBefore, kHalfAfter, kEdgeSideSize };
// Grandparent::edge_sides and corner_halves from a level's faces [f0, f1): each writes its sides of its edges and its
// own halves, from its face edges and places; and next_at, per child edge h, the next half around the old vertex at
// its end, as write_ordered_child_rings orders a ring (2 per edge of the level; no face writes the entry of a half
// that none follows, as on a boundary).
void write_grandparent_sides(const Topology& level, int f0, int f1, Index* edge_sides, Index* corner_halves,
                             Index* next_at);
// The rings of the child's old vertices [v0, v1) of a level whose fans are one fan each, as write_ordered_child_rings
// writes them (counter-clockwise around a disk: in a child triangle (v, a, b), b follows a around v; in the order of
// the vertex's edges around a boundary) but each entry first_half_vertex plus the child edge to the neighbour (the
// grandchild's vertex on it, where first_half_vertex is the child's vertex count), from ring[0]. `next_at`:
// write_grandparent_sides', -1 where no face follows.
void write_ordered_old_vertex_halves(const Topology& level, const Index* next_at, int v0, int v1,
                                     Index first_half_vertex, Index* ring);
// What write_ordered_child_rings writes of the child of the grandparent's child, without either: the rings of
// grandchild vertices [begin, end), every one made by a split (begin >= the grandparent's vertex count), through the
// numbering of both splits, counter-clockwise where a vertex's fan is a disk (six neighbours; four on a boundary, in
// write_child_rings' order). From ring[0]; vertex begin + i's at ring[offsets[i]] to ring[offsets[i + 1]], offsets
// from 0 (end - begin + 1 of them).
void write_ordered_grandchild_rings(const Grandparent& g, int begin, int end, Index* offsets, Index* ring);

// Ends (A, B) and the vertices opposite (C, D) of child edges [begin, end), as refine_topology's edge_vertices (2 per
// edge) and edge_wing_c / _d give them; written from index 0 of each array.
void child_edges(const Topology& parent, int begin, int end, Index* ends, Index* c, Index* d);
// The ends of the halves of parent edges [e0, e1) (child edges 2 e0 .. 2 e1), written from ends[0].
void write_half_ends(const Topology& parent, int e0, int e1, Index* ends);
// The vertices opposite the halves of the parent's edges (C, D of child edges 0 .. 2 x parent edges, as child_edges
// writes them into c[e], d[e]): each of faces [f0, f1) writes its share, and each of edges [e0, e1) with fewer than
// two faces what a missing face leaves (its own ends). Needs the parent's face_edge_places; faster than child_edges'
// edge order, which waits on faces read from far away (docs/benchmark.md, "Measurements behind the code").
void write_half_wings(const Topology& parent, int f0, int f1, int e0, int e1, Index* c, Index* d);
// Ends (A, B) and wings (C, D) of the child edge inside a parent face that joins the midpoints of its edges k and
// k + 1 (face: the parent face's corners and edges, 3 each; the midpoint of parent edge e is child vertex nv + e):
// it lies opposite corner k + 1 in that corner's child and opposite the midpoint of edge k - 1 in the middle child.
inline void face_interior_edge(Index nv, const Index* face_vertices, const Index* face_edges, int k, Index abcd[4]) {
    const int next = k == 2 ? 0 : k + 1, before = k == 0 ? 2 : k - 1;
    abcd[0] = nv + face_edges[k];
    abcd[1] = nv + face_edges[next];
    abcd[2] = face_vertices[next];
    abcd[3] = nv + face_edges[before];
}
// The faces of the grandchild level (refine_topology twice, the second time FacesOnly) of parent faces [f0, f1):
// 48 indices per parent face, written from out[48 * f0].
void write_grandchild_faces(const Topology& parent, int f0, int f1, Index* out);

// A child level's Topology::max_valence and max_edge_face_count, from its parent's.
int child_max_valence(const Topology& parent);
int child_max_edge_face_count(const Topology& parent);
// Child edge of parent edge e at its end vertex v.
inline Index child_edge_at(const Topology& parent, Index e, Index v) {
    assert(parent.edge_vertices[2 * e] == v || parent.edge_vertices[2 * e + 1] == v);
    return 2 * e + (parent.edge_vertices[2 * e] == v ? 0 : 1);
}

// An edge is non-manifold when it has more than two faces, or two faces that run along it the same way. Of a base
// level (it reads face_edge_places as build_base_topology numbers them).
std::vector<std::uint8_t> non_manifold_edges(const Topology& topology);
// A vertex is non-manifold when one of its edges is, or its faces do not form a single fan.
std::vector<std::uint8_t> non_manifold_vertices(const Topology& topology,
                                                const std::vector<std::uint8_t>& non_manifold_edge,
                                                int threads = 1);  // threads share the vertices

// Number of faces met walking around vertex v from edge `from` until edge `to` (both with two faces), through
// the first face of `from`. Manifold neighbourhood required.
int faces_between(const Topology& topology, Index v, Index from, Index to);

}  // namespace loopsub::detail
