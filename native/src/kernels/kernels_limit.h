// The limit stage shared by the SIMD kernels (LimitFn, limit_pass): a last-level vertex's limit point and its two
// tangents from one fan of loads of its ring, and its unit normal from the tangents, four vertices at a time.
//
// A limit point and the tangents read the same points (the limit mask's ring, the tangent masks' offsets from the
// vertex): computing them in one pass halves the loads of a pass each. The limit point is the kernels' smooth vertex
// mask as their table passes weigh it (the ring summed from zero in ring order), so a frame's positions are the same
// bits with the normals as without; the tangents are the reference's sums (limit_normals.cpp) per lane, and the
// normals its arithmetic in double, four at a time.
//
// Internal linkage, as in kernels_quads.h: each instruction set's translation unit keeps its own copy.
#pragma once

#include <xmmintrin.h>

#include <algorithm>
#include <cstring>
#include <type_traits>

#include "kernels/kernels_quads.h"
#include "kernels/kernels_specials.h"
#include "kernels/limit_normals.h"
#include "tables/limit_tables.h"

namespace loopsub::detail {
namespace {

// The positions quad (the first) of vertices [vertices.begin, vertices.end) with their normals, rows of three at
// `normals`: zero for a vertex whose normals are its sides'. vertex(self, ring_sum, w_self, w_ring) is the
// instruction set's smooth vertex mask, multiply_add(w, d, sum) its step of a tangent's sum, unit_normals(t1, t2,
// normals) its normals of four tangent pairs.
template <std::size_t Step, typename Out, typename Vertex, typename MultiplyAdd, typename UnitNormals>
void limit_quad(const LimitTables& lt, const Tables& t, const QuadSource<Step> in, const Out out, float* normals,
                Range vertices, Vertex vertex, MultiplyAdd multiply_add, UnitNormals unit_normals) {
    const std::vector<float>* smooth_t1 = lt.smooth_t1.data();
    const std::vector<float>* smooth_t2 = lt.smooth_t2.data();
    const std::uint8_t* by_side = lt.by_side.data();
    const PackedRows3 normal_rows{normals};
    const __m128 a = _mm_set1_ps(lt.regular_tangents[0]), b = _mm_set1_ps(lt.regular_tangents[1]),
                 c = _mm_set1_ps(lt.regular_tangents[2]);
    const bool any_regular = lt.positions.smooth_self.size() > 6;
    const float w_self6 = any_regular ? t.smooth_self[6] : 0.0f, w_ring6 = any_regular ? t.smooth_ring[6] : 0.0f;
    auto point = [&](int v, __m128& position, __m128& t1, __m128& t2) {
        const int n = t.valence(v);
        const std::int32_t* ring = t.ring + t.ring_first(v);
        const __m128 centre = _mm_loadu_ps(in.at(v));
        __m128 ring_sum = _mm_setzero_ps();
        if (n == 6) {  // nearly every vertex: LimitTables::regular_tangents
            std::int32_t r[6];
            for (int k = 0; k < 6; k += 2) load_index_pair(ring + k, r[k], r[k + 1]);
            __m128 p[6];
            for (int k = 0; k < 6; ++k) {
                p[k] = _mm_loadu_ps(in.at(r[k]));
                ring_sum = _mm_add_ps(ring_sum, p[k]);
            }
            t1 = _mm_mul_ps(a, _mm_sub_ps(p[0], p[3]));
            t1 = multiply_add(b, _mm_sub_ps(p[1], p[2]), t1);
            t1 = multiply_add(b, _mm_sub_ps(p[5], p[4]), t1);
            t2 = multiply_add(c, _mm_sub_ps(p[2], p[5]), _mm_mul_ps(c, _mm_sub_ps(p[1], p[4])));
            position = vertex(centre, ring_sum, w_self6, w_ring6);
            return;
        }
        const float* w1 = smooth_t1[n].data();
        const float* w2 = smooth_t2[n].data();
        t1 = t2 = _mm_setzero_ps();
        for (int k = 0; k < n; ++k) {
            const __m128 p = _mm_loadu_ps(in.at(ring[k]));
            ring_sum = _mm_add_ps(ring_sum, p);
            const __m128 d = _mm_sub_ps(p, centre);
            t1 = multiply_add(_mm_set1_ps(w1[k]), d, t1);
            t2 = multiply_add(_mm_set1_ps(w2[k]), d, t2);
        }
        position = vertex(centre, ring_sum, t.smooth_self[n], t.smooth_ring[n]);
    };
    // A chunk at a time: first every vertex's point and tangents, then their normals four at a time. Two tight loops
    // of independent steps, where one loop of both kept the square roots' latency in every step.
    constexpr int kChunk = 64;
    alignas(16) __m128 position[kChunk], t1[kChunk], t2[kChunk];
    for (int first = vertices.begin; first < vertices.end; first += kChunk) {
        const int count = std::min(kChunk, vertices.end - first);
        for (int i = 0; i < count; ++i) point(first + i, position[i], t1[i], t2[i]);
        // A last group of fewer than four repeats its last vertex: every vertex's bits are those of its lane alone,
        // wherever a part of the range begins.
        for (int i = count; i % 4 != 0; ++i) t1[i] = t1[count - 1], t2[i] = t2[count - 1];
        for (int i = 0; i < count; i += 4) {
            __m128 normal[4];
            unit_normals(t1 + i, t2 + i, normal);
            const int v = first + i;
            std::uint32_t sides = 1;  // four vertices' by_side bytes at once: nearly always none
            if (i + 4 <= count) std::memcpy(&sides, by_side + v, sizeof sides);
            if (sides != 0)
                for (int k = 0; k < 4 && i + k < count; ++k)
                    if (by_side[v + k]) normal[k] = _mm_setzero_ps();
            if constexpr (std::is_same_v<Out, PackedRows3>) {
                if (i + 4 <= count) {
                    out.store_four(std::size_t(v), position[i], position[i + 1], position[i + 2], position[i + 3]);
                    normal_rows.store_four(std::size_t(v), normal[0], normal[1], normal[2], normal[3]);
                    continue;
                }
            }
            for (int k = 0; k < 4 && i + k < count; ++k) {
                out.store(std::size_t(v + k), position[i + k]);
                normal_rows.store(std::size_t(v + k), normal[k]);
            }
        }
    }
}

// A SIMD kernel's LimitFn (kernels.h) from its arithmetic: the positions' quad with the normals (limit_quad), the other
// quads by smooth_quad(tables, source, target, vertices) as a refinement's vertex pass, then the specials; other
// layouts run the scalar reference.
template <typename Vertex, typename MultiplyAdd, typename UnitNormals, typename SmoothQuad>
void limit_pass(const LimitTables& lt, ChannelsView<const float> in, ChannelsView<float> out, float* normals,
                Range vertices, Vertex vertex, MultiplyAdd multiply_add, UnitNormals unit_normals,
                SmoothQuad smooth_quad) {
    if (!reads_as_quads(in)) return limit_scalar(lt, in, out, normals, vertices);
    const LevelStencils& s = lt.positions;
    for_each_quad(s, stored_view(s), in, out, [&](const Tables& t, auto source, auto target) {
        if (normals != nullptr && source.in == in.data)  // the positions: the normals from the same loads
            return limit_quad(lt, t, source, target, normals, vertices, vertex, multiply_add, unit_normals);
        smooth_quad(t, source, target, vertices);
    });
    apply_specials(s, stored_view(s), in, out, vertices, {0, 0});
    if (normals != nullptr) own_vertex_normals(lt, in, normals, vertices);
}

}  // namespace
}  // namespace loopsub::detail
