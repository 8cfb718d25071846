// How one triangle is cut for a tessellation: its points and triangles for a rate per edge and an inner rate. No mesh
// here: the tessellation numbers a face's corners and edge points as the mesh's, so that neighbours share them.
//
// The points of a face, in this order: its 3 corners; then the rate[k] - 1 points of each edge k (from corner k to
// corner k + 1) in that direction; then the inner points, those of the inner rate's lattice with no coordinate zero
// (none below an inner rate of 3), or, where the edge rates differ and the inner rate is below 3, the centre.
// Where every rate is the same the triangles are the lattice's; otherwise the inner points' lattice is joined to each
// edge by a strip (the points of the edge and the ring of inner points along it, zipped in order of their place along
// the edge).
#pragma once

#include <cstdint>
#include <vector>

namespace loopsub::detail {

// A point of a face, in its barycentric coordinates (den - b1 - b2, b1, b2) / den: corner 0 takes the rest.
struct PatternPoint {
    std::int32_t b1, b2, den;
};

struct FacePattern {
    std::vector<PatternPoint> points;
    std::vector<std::int32_t> triangles;  // 3 per triangle, indices into points, counter-clockwise
};

// rates: segments per edge (>= 1); inner_rate >= each of them.
void tessellate_triangle(const int rates[3], int inner_rate, FacePattern& out);

// The index among a face's points of the first point of edge k (rates as above); k = 3: of the first inner point.
inline int first_edge_point(const int rates[3], int k) {
    int first = 3;
    for (int e = 0; e < k; ++e) first += rates[e] - 1;
    return first;
}

// How many triangles tessellate_triangle makes: the inner rate's lattice where every rate is the same; otherwise the
// inner lattice of rate n - 3 and a strip of r + n - 3 triangles along each edge of rate r, or a fan of r triangles
// per edge around the centre below an inner rate of 3.
inline std::int64_t num_pattern_triangles(const int rates[3], int inner_rate) {
    const std::int64_t n = inner_rate;
    if (rates[0] == n && rates[1] == n && rates[2] == n) return n * n;
    if (n < 3) return std::int64_t(rates[0]) + rates[1] + rates[2];
    return (n - 3) * (n - 3) + (std::int64_t(rates[0]) + rates[1] + rates[2]) + 3 * (n - 3);
}

// How many inner points tessellate_triangle makes.
inline std::int64_t num_inner_points(const int rates[3], int inner_rate) {
    const bool uniform = rates[0] == inner_rate && rates[1] == inner_rate && rates[2] == inner_rate;
    if (!uniform && inner_rate < 3) return 1;
    return std::int64_t(inner_rate - 1) * (inner_rate - 2) / 2;
}

}  // namespace loopsub::detail
