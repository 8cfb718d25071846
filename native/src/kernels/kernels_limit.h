// The limit stage shared by the SIMD kernels (LimitFn, limit_pass): a last-level vertex's limit point and its two
// tangents from one fan of loads of its ring, and its unit normal from the tangents, four vertices at a time.
//
// A limit point and the tangents read the same points (the limit mask's ring, the tangent masks' offsets from the
// vertex): computing them in one pass halves the loads of a pass each. The limit point is the kernels' smooth vertex
// mask as their table passes weigh it (the ring summed from zero in ring order), so a frame's positions are the same
// bits with the normals as without; the tangents are the reference's sums (limit_normals.cpp) per lane, and the
// normals its arithmetic in float, four or eight at a time across lanes.
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

// The limit point and tangents of a vertex of valence 6 (nearly every one) from its point and its ring's six in order:
// the smooth vertex mask as the table passes weigh it (the ring summed from zero in ring order), and the tangents of
// LimitTables::regular_tangents.
template <typename Vertex, typename MultiplyAdd>
struct RegularLimit {
    __m128 a, b, c;
    float w_self, w_ring;
    Vertex vertex;
    MultiplyAdd multiply_add;

    RegularLimit(const LimitTables& lt, Vertex vertex_mask, MultiplyAdd step)
        : a(_mm_set1_ps(lt.regular_tangents[0])),
          b(_mm_set1_ps(lt.regular_tangents[1])),
          c(_mm_set1_ps(lt.regular_tangents[2])),
          w_self(lt.positions.smooth_self.size() > 6 ? lt.positions.smooth_self[6] : 0.0f),
          w_ring(lt.positions.smooth_self.size() > 6 ? lt.positions.smooth_ring[6] : 0.0f),
          vertex(vertex_mask),
          multiply_add(step) {}

    void operator()(__m128 centre, const __m128 p[6], __m128& position, __m128& t1, __m128& t2) const {
        __m128 ring_sum = _mm_setzero_ps();
        for (int k = 0; k < 6; ++k) ring_sum = _mm_add_ps(ring_sum, p[k]);
        t1 = _mm_mul_ps(a, _mm_sub_ps(p[0], p[3]));
        t1 = multiply_add(b, _mm_sub_ps(p[1], p[2]), t1);
        t1 = multiply_add(b, _mm_sub_ps(p[5], p[4]), t1);
        t2 = multiply_add(c, _mm_sub_ps(p[2], p[5]), _mm_mul_ps(c, _mm_sub_ps(p[1], p[4])));
        position = vertex(centre, ring_sum, w_self, w_ring);
    }
};

// Stores `count` consecutive vertices' limit points from `first` on and, where `normals` is set, their unit normals
// (unit_normals, UnitNormals::kWidth at a time; zero where by_side, if given, says the vertex's normals are its
// sides'). Two tight loops of independent steps (the points, then the normals), where one loop of both kept the square
// roots' latency in every step. A last group of fewer than kWidth repeats its last vertex: every vertex's bits are
// those of its lane alone, wherever a part of a range begins.
template <typename Out, typename UnitNormals>
void store_limit_chunk(const Out out, float* normals, const std::uint8_t* by_side, int first, int count,
                       __m128* position, __m128* t1, __m128* t2, UnitNormals unit_normals) {
    int i = 0;
    if constexpr (std::is_same_v<Out, PackedRows3>)
        for (; i + 4 <= count; i += 4)
            out.store_four(std::size_t(first + i), position[i], position[i + 1], position[i + 2], position[i + 3]);
    for (; i < count; ++i) out.store(std::size_t(first + i), position[i]);
    if (normals == nullptr) return;
    constexpr int kWidth = UnitNormals::kWidth;
    for (int k = count; k % kWidth != 0; ++k) t1[k] = t1[count - 1], t2[k] = t2[count - 1];
    float* rows = normals + 3 * std::size_t(first);
    for (i = 0; i + kWidth <= count; i += kWidth) unit_normals(t1 + i, t2 + i, rows + 3 * i);
    if (i < count) {
        float last[3 * kWidth];
        unit_normals(t1 + i, t2 + i, last);
        std::memcpy(rows + 3 * i, last, sizeof(float) * 3 * std::size_t(count - i));
    }
    if (by_side == nullptr) return;
    for (i = 0; i < count; ++i)
        if (by_side[first + i]) std::memset(rows + 3 * i, 0, 3 * sizeof(float));
}

// The positions quad (the first) of vertices [vertices.begin, vertices.end) with their normals, rows of three at
// `normals`: zero for a vertex whose normals are its sides'. vertex(self, ring_sum, w_self, w_ring) is the
// instruction set's smooth vertex mask, multiply_add(w, d, sum) its step of a tangent's sum, unit_normals(t1, t2,
// normals) its normals of four tangent pairs.
template <std::size_t Step, typename Out, typename Vertex, typename MultiplyAdd, typename UnitNormals>
void limit_quad(const LimitTables& lt, const Tables& t, const QuadSource<Step> in, const Out out, float* normals,
                Range vertices, Vertex vertex, MultiplyAdd multiply_add, UnitNormals unit_normals) {
    const std::vector<float>* smooth_t1 = lt.smooth_t1.data();
    const std::vector<float>* smooth_t2 = lt.smooth_t2.data();
    const RegularLimit<Vertex, MultiplyAdd> regular(lt, vertex, multiply_add);
    auto point = [&](int v, __m128& position, __m128& t1, __m128& t2) {
        const int n = t.valence(v);
        const std::int32_t* ring = t.ring + t.ring_first(v);
        const __m128 centre = _mm_loadu_ps(in.at(v));
        if (n == 6) {  // nearly every vertex
            std::int32_t r[6];
            for (int k = 0; k < 6; k += 2) load_index_pair(ring + k, r[k], r[k + 1]);
            __m128 p[6];
            for (int k = 0; k < 6; ++k) p[k] = _mm_loadu_ps(in.at(r[k]));
            return regular(centre, p, position, t1, t2);
        }
        const float* w1 = smooth_t1[n].data();
        const float* w2 = smooth_t2[n].data();
        __m128 ring_sum = _mm_setzero_ps();
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
    // A chunk at a time: first every vertex's point and tangents, then their normals (store_limit_chunk).
    constexpr int kChunk = 64;
    alignas(16) __m128 position[kChunk], t1[kChunk], t2[kChunk];
    for (int first = vertices.begin; first < vertices.end; first += kChunk) {
        const int count = std::min(kChunk, vertices.end - first);
        for (int i = 0; i < count; ++i) point(first + i, position[i], t1[i], t2[i]);
        store_limit_chunk(out, normals, lt.by_side.data(), first, count, position, t1, t2, unit_normals);
    }
}

// Limit outputs of one kind, consecutive from `first`, gathered a chunk at a time for store_limit_chunk.
struct LimitChunk {
    static constexpr int kSize = 64;  // a multiple of 2 and 3 plus one: whole units fill it to 63 or 64
    // 32: the AVX2 kernel stores a pair of halves (from an even slot) 32 bytes at a time, within one cache line.
    alignas(32) __m128 position[kSize], t1[kSize], t2[kSize];
    Index first = 0;
    int count = 0;
};

// RegularLimit for two vertices, into consecutive slots of a chunk: here one after the other; the AVX2 kernel has
// its own that works on both at once, a register half each (the same bits).
template <typename Regular>
struct OneAfterOther {
    Regular regular;

    void operator()(__m128 centre_a, const __m128 ring_a[6], __m128 centre_b, const __m128 ring_b[6], LimitChunk& c,
                    int slot) const {
        regular(centre_a, ring_a, c.position[slot], c.t1[slot], c.t2[slot]);
        regular(centre_b, ring_b, c.position[slot + 1], c.t1[slot + 1], c.t2[slot + 1]);
    }
};

// The limit points, and where `normals` is set the normals, of a share of the vertices made by the splits after the
// grandparent (LimitTables::from_grandparent; kernels.h, GrandchildShare), by kind, each ring's points loaded once for
// the vertices that share them: the rings are write_ordered_grandchild_rings', in its order, their indices worked out
// in registers, and the arithmetic RegularLimit's (two vertices at a time by Two<RegularLimit>), so that the bits are
// those of limit_quad over those rings. A grandparent edge's child midpoint and its halves' midpoints read 13 points
// for the three, a grandparent face's three interior edges' midpoints 12 (21 each from rings).
template <template <typename> class Two, std::size_t Step, typename Out, typename Vertex, typename MultiplyAdd,
          typename UnitNormals>
void grandchild_limit_quad(const LimitTables& lt, const QuadSource<Step> in, const Out out, float* normals,
                           GrandchildShare share, Vertex vertex, MultiplyAdd multiply_add, UnitNormals unit_normals) {
    const Grandparent& g = lt.from_grandparent->grandparent;
    using Regular = RegularLimit<Vertex, MultiplyAdd>;
    const Regular regular(lt, vertex, multiply_add);
    const Two<Regular> two{regular};
    const Index nv = g.num_vertices, child_vertices = nv + g.num_edges, halves_end = child_vertices + 2 * g.num_edges;
    Range kinds[3];  // the share's outputs, a range of last-level vertices per kind
    share.vertices(g, kinds);
    const Index* corner_halves = g.corner_halves;
    auto load = [&](Index v) { return _mm_loadu_ps(in.at(std::size_t(v))); };
    auto next_corner = [](int k) { return k == 2 ? 0 : k + 1; };  // a triangle's corners, counter-clockwise
    auto prev_corner = [](int k) { return k == 0 ? 2 : k - 1; };

    auto flush = [&](LimitChunk& c) {
        if (c.count > 0)
            store_limit_chunk(out, normals, nullptr, c.first, c.count, c.position, c.t1, c.t2, unit_normals);
        c.first += c.count, c.count = 0;
    };
    // The first of `n` slots for one unit's outputs, after storing the chunk if they do not fit.
    auto slots = [&](LimitChunk& c, int n) {
        if (c.count + n > LimitChunk::kSize) flush(c);
        c.count += n;
        return c.count - n;
    };
    // Grandparent edge h gives its child's midpoint R = nv + h and the midpoints of its halves 2h = (a, R) and
    // 2h + 1 = (R, b); R's ring (2h, G's interior edges j and j - 1, 2h + 1, F's k and k - 1) is among the halves'
    // points, so one fan of loads serves the three. F runs along h from its first end (h its edge k), G the other way
    // (h its edge j): h's sides (Grandparent::edge_sides). A boundary edge has F only: its vertices are by sides, and
    // their limits are LimitFn's (`redone`), so F stands in for G there, only to keep the loads in place.
    LimitChunk midpoints, halves;
    midpoints.first = kinds[0].begin, halves.first = kinds[1].begin;
    for (Index h = share.edges.begin; h < share.edges.end; ++h) {
        const Index* f_side = g.edge_sides + 2 * kEdgeSideSize * std::size_t(h);
        const Index* g_side = f_side[kEdgeSideSize] < 0 ? f_side : f_side + kEdgeSideSize;
        const __m128 r = load(nv + h), half_a = load(child_vertices + 2 * h), half_b = load(child_vertices + 2 * h + 1);
        const __m128 g_interior = load(g_side[kInterior]), f_interior = load(f_side[kInterior]);
        const __m128 g_interior_before = load(g_side[kInteriorBefore]);
        const __m128 f_interior_before = load(f_side[kInteriorBefore]);
        const __m128 at_r[6] = {half_a, g_interior, g_interior_before, half_b, f_interior, f_interior_before};
        const __m128 at_a[6] = {
            load(g.edge_vertices[2 * h]), load(g_side[kHalfAfter]), g_interior, r, f_interior_before,
            load(f_side[kHalfBefore])};
        const __m128 at_b[6] = {r,
                                g_interior_before,
                                load(g_side[kHalfBefore]),
                                load(g.edge_vertices[2 * h + 1]),
                                load(f_side[kHalfAfter]),
                                f_interior};
        const int m = slots(midpoints, 1);
        regular(r, at_r, midpoints.position[m], midpoints.t1[m], midpoints.t2[m]);
        two(half_a, at_a, half_b, at_b, halves, slots(halves, 2));
    }
    flush(midpoints);
    flush(halves);
    // The midpoints of face f's interior edges k, from m_k to m_k+1: its ring m_k, the half of edge k at its end,
    // that of edge k + 1 at its start, m_k+1, interior edges k + 1 and k - 1.
    LimitChunk interiors;
    interiors.first = kinds[2].begin;
    for (Index f = share.faces.begin; f < share.faces.end; ++f) {
        const Index* face_halves = &corner_halves[3 * std::size_t(f)];
        __m128 m[3], start[3], end[3], edge[3];
        for (int k = 0; k < 3; ++k) {
            m[k] = load(nv + (face_halves[k] >> 1));
            start[k] = load(child_vertices + face_halves[k]);
            end[k] = load(child_vertices + (face_halves[k] ^ 1));
            edge[k] = load(halves_end + 3 * f + k);
        }
        __m128 p[3][6];
        for (int k = 0; k < 3; ++k) {
            const int next = next_corner(k), before = prev_corner(k);
            const __m128 ring[6] = {m[k], end[k], start[next], m[next], edge[next], edge[before]};
            std::copy(ring, ring + 6, p[k]);
        }
        const int i = slots(interiors, 3);
        two(edge[0], p[0], edge[1], p[1], interiors, i);
        regular(edge[2], p[2], interiors.position[i + 2], interiors.t1[i + 2], interiors.t2[i + 2]);
    }
    flush(interiors);
}

// A SIMD kernel's LimitFn (kernels.h) from its arithmetic: the positions' quad with the normals (limit_quad), the other
// quads by smooth_quad(tables, source, target, vertices) as a refinement's vertex pass, then the specials; other
// layouts run the scalar reference.
template <typename Vertex, typename MultiplyAdd, typename UnitNormals, typename SmoothQuad>
void limit_pass(const LimitTables& lt, const StencilView& view, ChannelsView<const float> in, ChannelsView<float> out,
                float* normals, Range vertices, Vertex vertex, MultiplyAdd multiply_add, UnitNormals unit_normals,
                SmoothQuad smooth_quad) {
    if (!reads_as_quads(in)) return limit_scalar(lt, view, in, out, normals, vertices);
    const LevelStencils& s = lt.positions;
    for_each_quad(s, view, in, out, [&](const Tables& t, auto source, auto target) {
        if (normals != nullptr && source.in == in.data)  // the positions: the normals from the same loads
            return limit_quad(lt, t, source, target, normals, vertices, vertex, multiply_add, unit_normals);
        smooth_quad(t, source, target, vertices);
    });
    apply_specials(s, view, in, out, vertices, {0, 0});
    if (normals != nullptr) own_vertex_normals(lt, view, in, normals, vertices);
}

// A SIMD kernel's GrandchildLimitFn (kernels.h) from its arithmetic: every quad by grandchild_limit_quad, the
// positions' with the normals; then the vertices next to tags (LimitTables::FromGrandparent::redone) again by its
// LimitFn, `limit`, over their rings, runs of consecutive ones at a time; other layouts run the scalar reference.
template <template <typename> class Two, typename Vertex, typename MultiplyAdd, typename UnitNormals>
void grandchild_limit_pass(const LimitTables& lt, ChannelsView<const float> in, ChannelsView<float> out, float* normals,
                           GrandchildShare share, Vertex vertex, MultiplyAdd multiply_add, UnitNormals unit_normals,
                           LimitFn limit) {
    if (!reads_as_quads(in)) return limit_grandchild_scalar(lt, in, out, normals, share);
    const LevelStencils& s = lt.positions;
    for_each_quad(s, stored_view(s), in, out, [&](const Tables&, auto source, auto target) {
        grandchild_limit_quad<Two>(lt, source, target, source.in == in.data ? normals : nullptr, share, vertex,
                                   multiply_add, unit_normals);
    });
    const std::vector<Index>& redone = lt.from_grandparent->redone;
    if (redone.empty()) return;
    Range kinds[3];
    share.vertices(lt.from_grandparent->grandparent, kinds);
    for (const Range& kind : kinds) {
        auto next = std::lower_bound(redone.begin(), redone.end(), kind.begin);
        while (next != redone.end() && *next < kind.end) {
            const Index first = *next;
            Index last = first + 1;
            while (++next != redone.end() && *next == last && last < kind.end) ++last;
            limit_over_grandchild_rings(limit, lt, in, out, normals, {first, last});
        }
    }
}

}  // namespace
}  // namespace loopsub::detail
