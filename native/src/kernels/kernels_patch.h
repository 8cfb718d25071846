// The body of the patch kernels (kernels.h, PatchFn) for the SIMD instruction sets: the samples of a block a vector at
// a time, each file supplying its arithmetic as a traits type:
//   V::Vec, V::kWidth              the vector type and how many floats it holds
//   V::load(p), V::broadcast(x)    a vector from kWidth floats, from one float
//   V::multiply_add(a, b, c)       a * b + c
//   V::multiply(a, b), V::subtract(a, b)
//   V::unit_factor(x)              1 / sqrt(x) where x > 0, else 0
//   V::max_magnitude(a, b, c)      the largest of |a|, |b|, |c|
//   V::reciprocal_or_zero(x)       1 / x where x > 0, else 0
//   V::store(p, v)
//   V::store_rows(rows, x, y, z)   kWidth rows of three floats from the lanes of x, y and z
// Reading a block's stride of weights (the block's samples padded with zeros to a multiple of 8), the kernel computes
// whole vectors and writes only the block's samples: whole vectors as rows, the last part of one lane by lane.
#pragma once

#include "kernels/kernels.h"

namespace loopsub::detail {

template <typename V>
void patch_pass(const float points[kPatchPoints][4], const float* weights, int count, int stride, float* positions,
                float* normals) {
    using Vec = typename V::Vec;
    constexpr int W = V::kWidth;
    for (int first = 0; first < count; first += W) {
        Vec sum[3][3];  // position, d/ds, d/dt; x, y, z
        for (auto& kind : sum)
            for (Vec& c : kind) c = V::broadcast(0.0f);
        for (int i = 0; i < kPatchPoints; ++i) {
            const Vec x = V::broadcast(points[i][0]), y = V::broadcast(points[i][1]), z = V::broadcast(points[i][2]);
            for (int k = 0; k < 3; ++k) {
                const Vec w = V::load(weights + std::size_t(kPatchPoints * k + i) * std::size_t(stride) + first);
                sum[k][0] = V::multiply_add(w, x, sum[k][0]);
                sum[k][1] = V::multiply_add(w, y, sum[k][1]);
                sum[k][2] = V::multiply_add(w, z, sum[k][2]);
            }
        }
        // The derivatives scaled to a largest coordinate of one before their cross product, which would overflow
        // (or underflow) a float where they are large (or small); the normal's direction is theirs.
        Vec s[3], t[3];
        const Vec s_unit = V::reciprocal_or_zero(V::max_magnitude(sum[1][0], sum[1][1], sum[1][2])),
                  t_unit = V::reciprocal_or_zero(V::max_magnitude(sum[2][0], sum[2][1], sum[2][2]));
        for (int c = 0; c < 3; ++c) s[c] = V::multiply(sum[1][c], s_unit), t[c] = V::multiply(sum[2][c], t_unit);
        const Vec n[3] = {V::subtract(V::multiply(s[1], t[2]), V::multiply(s[2], t[1])),
                          V::subtract(V::multiply(s[2], t[0]), V::multiply(s[0], t[2])),
                          V::subtract(V::multiply(s[0], t[1]), V::multiply(s[1], t[0]))};
        const Vec unit =
            V::unit_factor(V::multiply_add(n[0], n[0], V::multiply_add(n[1], n[1], V::multiply(n[2], n[2]))));
        const Vec normal[3] = {V::multiply(n[0], unit), V::multiply(n[1], unit), V::multiply(n[2], unit)};
        const int lanes = count - first < W ? count - first : W;
        if (lanes == W) {
            V::store_rows(positions + 3 * std::size_t(first), sum[0][0], sum[0][1], sum[0][2]);
            V::store_rows(normals + 3 * std::size_t(first), normal[0], normal[1], normal[2]);
            continue;
        }
        alignas(32) float out[6][W];
        for (int c = 0; c < 3; ++c) V::store(out[c], sum[0][c]), V::store(out[3 + c], normal[c]);
        for (int l = 0; l < lanes; ++l)
            for (int c = 0; c < 3; ++c) {
                positions[3 * std::size_t(first + l) + std::size_t(c)] = out[c][l];
                normals[3 * std::size_t(first + l) + std::size_t(c)] = out[3 + c][l];
            }
    }
}

}  // namespace loopsub::detail
