// The regular patches of one refined level: where the Loop surface over a triangle is a box spline of 12 of the
// level's points (rules/box_spline.h), which points, and with which weights at a point of the triangle.
//
// Three kinds are regular. Smooth: the triangle's three corners are smooth vertices with six neighbours each, none of
// their edges sharp and no vertex sharpness, so that every rule that shapes the triangle's surface is the smooth one.
// Beside a crease edge: one edge of the triangle is infinitely sharp (a crease or a boundary) between two regular
// crease vertices, each with three faces on the triangle's side and no other sharp edge there, and the third corner is
// smooth as above; the three points across the crease are then phantoms, each the fourth corner of the parallelogram on
// the triangle's side of the crease (P = a + b - c), which the crease rules reproduce: the crease's vertex mask
// {1, 6, 1} / 8 and edge mask {1, 1} / 2 are the smooth masks applied to them. At a crease vertex: one corner is such a
// regular crease vertex and the triangle the middle one of its three faces on that side, the other two corners smooth;
// the two points across the crease are phantoms in the same way.
//
// Everything else (a corner of another valence, a dart, a corner, a semi-sharp edge or vertex) is irregular: its
// surface needs more refinement first.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "loopsub/loopsub.h"
#include "rules/box_spline.h"

namespace loopsub::detail {

// One key per undirected edge.
inline std::uint64_t edge_key(std::int32_t a, std::int32_t b) {
    return std::uint64_t(std::uint32_t(a < b ? a : b)) << 32 | std::uint32_t(a < b ? b : a);
}

// The keys of the edges of a triangle list, each once, in order.
std::vector<std::uint64_t> sorted_edge_keys(const std::int32_t* triangles, int num_triangles);

// The same keys, and each triangle corner's edge (corner k's, to corner k + 1): one sort of the corners by their edges'
// keys, where sorted_edge_keys sorts the keys alone (cheaper where the corners' edges are not wanted).
struct SortedEdges {
    std::vector<std::uint64_t> keys;
    std::vector<std::int32_t> corner_edges;  // 3 per triangle, indices into keys
};
SortedEdges sorted_edges(const std::int32_t* triangles, int num_triangles);

// A regular patch of a level's triangle: its 12 points in box_spline.h's order, P3, P6, P7 being the triangle's corners
// `rotation`, `rotation` + 1 and `rotation` + 2. Phantoms hold -1: beside a crease edge (P6-P7), P9, P10 and P11; at a
// crease vertex (P3, its crease P2-P3-P4), P0 and P1.
enum class PatchShape : std::uint8_t { Smooth, CreaseEdge, CreaseVertex };
struct Patch {
    std::int32_t points[kBoxSplinePoints];
    int rotation = 0;
    PatchShape shape = PatchShape::Smooth;
};

// The weights of a patch's points (those that are no phantom) at (s, t) of its triangle (s towards the triangle's
// corner 1, t towards corner 2): for the position and its derivatives along s and t. The phantoms' weights go to the
// points they are made of.
struct PatchWeights {
    double position[kBoxSplinePoints], ds[kBoxSplinePoints], dt[kBoxSplinePoints];
};
void patch_weights(const Patch& patch, double s, double t, PatchWeights& out);

class LevelPatches {
public:
    // The last level of a plan: its triangles, the sharp edges its rules see (with their sharpness), the vertices with
    // a sharpness of their own, and the classes of its vertices at the next refinement. The plan must outlive this.
    // triangles: the level's every triangle where the plan left some out (a plan of no levels with holes: the input's
    // triangles, which shape the surface whether or not they have one); they must outlive this too.
    explicit LevelPatches(const Plan& plan, const std::int32_t* triangles = nullptr, int num_triangles = 0);

    // The regular patch of face, or false where the face is none.
    bool find_patch(int face, Patch& out) const;

    const std::int32_t* triangles() const { return triangles_; }
    // Each triangle's edges as the plan's split numbers them (Plan::output_edges), made on the first call; nullptr
    // for a level that is the input's, whose edges are found by their ends.
    const std::int32_t* triangle_edges() const;
    // The faces that have v as a corner (as 3 * face + corner).
    const std::int32_t* corners_begin(int v) const { return corners_.data() + offsets_[std::size_t(v)]; }
    const std::int32_t* corners_end(int v) const { return corners_.data() + offsets_[std::size_t(v) + 1]; }

private:
    float sharpness(int a, int b) const;
    int next_corner(int corner, bool counter_clockwise) const;  // around the corner's vertex; -1: none or several
    bool smooth_corner(int corner, std::int32_t ring[6]) const;
    bool crease_corner(int corner, bool counter_clockwise, std::int32_t fan[4]) const;
    bool crease_vertex(int corner, std::int32_t back[4], std::int32_t on[4]) const;

    const Plan& plan_;
    const std::int32_t* triangles_;
    // triangle_edges(), made where first needed: next to an interior vertex of valence 2, two edges of a refined level
    // join the same two vertices (the edges inside the two faces at the vertex), which their ends cannot tell apart.
    bool has_edges_;
    mutable std::vector<std::int32_t> triangle_edges_;
    // Each vertex's corners; a smooth vertex's put in counter-clockwise order by smooth_corner, once a face asks, with
    // each corner's place among them. Not for two threads at once.
    std::vector<std::int32_t> offsets_;
    mutable std::vector<std::int32_t> corners_;
    mutable std::vector<std::uint8_t> corner_rank_;
    enum class Order : std::uint8_t { NotYet, CounterClockwise, NoDisk };
    mutable std::vector<Order> ordered_;
    std::unordered_map<std::uint64_t, float> sharp_;
    // Vertices whose every rule around them is the smooth one: smooth, six faces, no sharp edge, no sharpness.
    std::vector<bool> smooth_;
    std::vector<bool> has_sharpness_;
    const VertexType* types_;
};

}  // namespace loopsub::detail
