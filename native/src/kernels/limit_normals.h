// The limit normals' reference arithmetic, shared by every kernel: a tangent is a weighted sum of the offsets of a
// vertex's neighbours from it (tangent masks sum to zero, and the offsets are small numbers, where the positions
// themselves would lose the tangents' low bits at deep levels), and a normal is t1 x t2 made unit in float. Float
// suffices: the tangents' own rounding (offsets of points rounded to floats) moves a normal far more than rounding its
// arithmetic does (docs/benchmark.md, "the normals in float"). Where the squared length of t1 x t2 leaves
// [kLeastSquaredLength, kMostSquaredLength], its products may have overflowed or lost bits as denormals: there both
// tangents are scaled by powers of two to a largest coordinate near one first, which changes no bits elsewhere.
//
// The SIMD kernels compute the normals of the vertices with smooth disk fans themselves, from the loads of their limit
// points (LimitFn, kernels_limit.h), in the same arithmetic per lane (with fused multiply-adds in AVX2); what is left
// to these functions is rare: vertices with tangent weights of their own (semi-sharp features spent past the last
// level) and the sides of creases.
#pragma once

#include <cstddef>

#include "kernels/kernels.h"
#include "tables/limit_tables.h"

namespace loopsub::detail {

constexpr float kLeastSquaredLength = 0x1p-100f, kMostSquaredLength = 0x1p100f;

// The normals of last-level vertices [vertices.begin, vertices.end) from the last level's points `in` (their first
// three channels, an element's channels side by side): a vertex with a smooth disk fan its own, one whose normals are
// its sides' a zero vector (side_normals writes an only side's there), the rings read through `view`. The scalar
// kernel's.
void vertex_normals_reference(const LimitTables& lt, const StencilView& view, ChannelsView<const float> in,
                              float* normals, Range vertices);

// Of those, the vertices with tangent weights of their own (LimitTables::own_vertex_tangents): their normals, written
// over what a SIMD kernel's smooth normals put there.
void own_vertex_normals(const LimitTables& lt, const StencilView& view, ChannelsView<const float> in, float* normals,
                        Range vertices);

// The normals of sides [sides.begin, sides.end) (LimitTables::sides), each at normals + 3 * its row.
void side_normals(const LimitTables& lt, ChannelsView<const float> in, float* normals, Range sides);

}  // namespace loopsub::detail
