#include "kernels/limit_normals.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>

namespace loopsub::detail {

namespace {

// The tangents of the points around `centre` with weights w1 and w2: a multiply, then an add, per coordinate.
struct Tangents {
    float t1[3] = {0.0f, 0.0f, 0.0f}, t2[3] = {0.0f, 0.0f, 0.0f};

    Tangents() = default;
    Tangents(ChannelsView<const float> in, Index centre, const Index* points, int count, const float* w1,
             const float* w2) {
        const float* c = in.data + std::size_t(centre) * in.element_stride;
        for (int i = 0; i < count; ++i) {
            const float* p = in.data + std::size_t(points[i]) * in.element_stride;
            for (int k = 0; k < 3; ++k) {
                const float d = p[k] - c[k];
                t1[k] += w1[i] * d;
                t2[k] += w2[i] * d;
            }
        }
    }
    // A smooth vertex of valence 6: LimitTables::regular_tangents over its ring's points.
    static Tangents regular(ChannelsView<const float> in, const Index* ring, const float abc[3]) {
        const float* p[6];
        for (int i = 0; i < 6; ++i) p[i] = in.data + std::size_t(ring[i]) * in.element_stride;
        Tangents t;
        for (int k = 0; k < 3; ++k) {
            t.t1[k] = abc[0] * (p[0][k] - p[3][k]) + abc[1] * (p[1][k] - p[2][k]) + abc[1] * (p[5][k] - p[4][k]);
            t.t2[k] = abc[2] * (p[1][k] - p[4][k]) + abc[2] * (p[2][k] - p[5][k]);
        }
        return t;
    }
};

// An open side at a corner: along its two sharp edges, the first and the last of its points, in the order that makes
// t1 x t2 point the way its faces do (a side wider than a half turn would turn it over).
Tangents corner_tangents(ChannelsView<const float> in, Index corner, const Index* points, int faces) {
    auto at = [&](Index v) { return in.data + std::size_t(v) * in.element_stride; };
    const float* c = at(corner);
    Tangents t;
    double facing = 0.0, cross[3], sum[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < faces; ++i) {
        const float *p = at(points[i]), *q = at(points[i + 1]);
        const double a[3] = {double(p[0]) - c[0], double(p[1]) - c[1], double(p[2]) - c[2]},
                     b[3] = {double(q[0]) - c[0], double(q[1]) - c[1], double(q[2]) - c[2]};
        sum[0] += a[1] * b[2] - a[2] * b[1], sum[1] += a[2] * b[0] - a[0] * b[2], sum[2] += a[0] * b[1] - a[1] * b[0];
    }
    for (int k = 0; k < 3; ++k) t.t1[k] = at(points[0])[k] - c[k], t.t2[k] = at(points[faces])[k] - c[k];
    cross[0] = double(t.t1[1]) * t.t2[2] - double(t.t1[2]) * t.t2[1];
    cross[1] = double(t.t1[2]) * t.t2[0] - double(t.t1[0]) * t.t2[2];
    cross[2] = double(t.t1[0]) * t.t2[1] - double(t.t1[1]) * t.t2[0];
    for (int k = 0; k < 3; ++k) facing += cross[k] * sum[k];
    if (facing < 0.0) std::swap(t.t1, t.t2);
    return t;
}

// The unit normals of a batch of tangent pairs, zero where the tangents do not span a plane. Over arrays and without
// branches, the compiler takes four square roots and divisions at once, which one at a time cost more than the
// tangents themselves. Float arithmetic, as the SIMD kernels' (limit_normals.h).
struct NormalBatch {
    static constexpr int kSize = 64;
    float x[kSize], y[kSize], z[kSize];

    void put(int i, Tangents t) {
        if (in_range(cross(i, t))) return;
        scale_to_unit(t.t1);
        scale_to_unit(t.t2);
        cross(i, t);
    }
    // Cross product i from t, and its squared length.
    float cross(int i, const Tangents& t) {
        x[i] = t.t1[1] * t.t2[2] - t.t1[2] * t.t2[1];
        y[i] = t.t1[2] * t.t2[0] - t.t1[0] * t.t2[2];
        z[i] = t.t1[0] * t.t2[1] - t.t1[1] * t.t2[0];
        return x[i] * x[i] + y[i] * y[i] + z[i] * z[i];
    }
    static bool in_range(float squared) { return squared >= kLeastSquaredLength && squared <= kMostSquaredLength; }
    // t scaled by the power of two that brings its largest coordinate into [0.5, 1) (into [0.5, 4) near the largest
    // floats, whose reciprocal powers of two are denormal): the scale's exponent bits are 253 minus the largest's.
    static void scale_to_unit(float t[3]) {
        const float largest = std::max({std::abs(t[0]), std::abs(t[1]), std::abs(t[2])});
        std::uint32_t bits;
        std::memcpy(&bits, &largest, sizeof bits);
        const std::uint32_t scale_bits = (253u << 23) - std::min(bits & 0x7f800000u, 252u << 23);
        float scale;
        std::memcpy(&scale, &scale_bits, sizeof scale);
        for (int c = 0; c < 3; ++c) t[c] *= scale;
    }
    // Normal i to normals + 3 * row_of(i).
    template <typename RowOf>
    void store(int count, float* normals, RowOf row_of) {
        for (int i = 0; i < count; ++i) {
            const float squared = x[i] * x[i] + y[i] * y[i] + z[i] * z[i];
            // Where `squared` is zero, so are x, y and z (put scaled the tangents of any smaller product).
            const float reciprocal = 1.0f / std::sqrt(squared);
            const float inverse = squared > 0.0f ? reciprocal : 0.0f;
            float* to = normals + 3 * std::size_t(row_of(i));
            to[0] = x[i] * inverse;
            to[1] = y[i] * inverse;
            to[2] = z[i] * inverse;
        }
    }
};

// Normals of items [begin, end) in batches: tangents_of(i) gives item i's, written at normals + 3 * row_of(i).
template <typename TangentsOf, typename RowOf>
void normals_in_batches(std::size_t begin, std::size_t end, TangentsOf tangents_of, float* normals, RowOf row_of) {
    NormalBatch batch;
    for (std::size_t first = begin; first < end; first += NormalBatch::kSize) {
        const int count = int(std::min<std::size_t>(NormalBatch::kSize, end - first));
        for (int i = 0; i < count; ++i) batch.put(i, tangents_of(first + std::size_t(i)));
        batch.store(count, normals, [&](int i) { return row_of(first + std::size_t(i)); });
    }
}

constexpr auto itself = [](std::size_t v) { return v; };

// The vertices of [vertices) with tangent weights of their own: (vertex, first weight), in vertex order.
std::pair<const std::pair<Index, Index>*, const std::pair<Index, Index>*> own_in(const LimitTables& lt,
                                                                                 Range vertices) {
    const auto& own = lt.own_vertex_tangents;
    const auto lo = std::lower_bound(own.begin(), own.end(), std::pair<Index, Index>(vertices.begin, -1));
    const auto hi = std::lower_bound(lo, own.end(), std::pair<Index, Index>(vertices.end, -1));
    return {own.data() + (lo - own.begin()), own.data() + (hi - own.begin())};
}

Tangents own_vertex_tangents(const LimitTables& lt, const StencilView& view, ChannelsView<const float> in,
                             const std::pair<Index, Index>& own) {
    const Index v = own.first;
    return Tangents(in, v, view.ring + view.ring_first(v), view.valence(v), lt.own_t1.data() + own.second,
                    lt.own_t2.data() + own.second);
}

}  // namespace

void vertex_normals_reference(const LimitTables& lt, const StencilView& view, ChannelsView<const float> in,
                              float* normals, Range vertices) {
    // Not a structured binding: C++17 lambdas cannot capture one (clang refuses).
    const auto own_range = own_in(lt, vertices);
    const std::pair<Index, Index>* own = own_range.first;
    const std::pair<Index, Index>* const own_end = own_range.second;
    normals_in_batches(
        std::size_t(vertices.begin), std::size_t(vertices.end),
        [&](std::size_t v) {
            if (lt.by_side[v]) return Tangents();  // zero: its normals are its sides' (side_normals)
            if (own != own_end && std::size_t(own->first) == v) return own_vertex_tangents(lt, view, in, *own++);
            const Index* ring = view.ring + view.ring_first(int(v));
            const int valence = view.valence(int(v));
            if (valence == 6) return Tangents::regular(in, ring, lt.regular_tangents);
            return Tangents(in, Index(v), ring, valence, lt.smooth_t1[valence].data(), lt.smooth_t2[valence].data());
        },
        normals, itself);
}

void own_vertex_normals(const LimitTables& lt, const StencilView& view, ChannelsView<const float> in, float* normals,
                        Range vertices) {
    const auto [own, own_end] = own_in(lt, vertices);
    for (const auto* it = own; it != own_end; ++it) {  // never a vertex by sides (PlanBuilder::pull_back_spent)
        const std::size_t v = std::size_t(it->first);
        normals_in_batches(
            v, v + 1, [&](std::size_t) { return own_vertex_tangents(lt, view, in, *it); }, normals, itself);
    }
}

void side_normals(const LimitTables& lt, ChannelsView<const float> in, float* normals, Range sides) {
    normals_in_batches(
        std::size_t(sides.begin), std::size_t(sides.end),
        [&](std::size_t i) {
            const LimitTables::Side& side = lt.sides[i];
            const Index* points = lt.side_points.data() + side.first;
            if (side.own >= 0)
                return Tangents(in, side.vertex, points, side.closed ? side.faces : side.faces + 1,
                                lt.own_t1.data() + side.own, lt.own_t2.data() + side.own);
            if (side.closed)
                return Tangents(in, side.vertex, points, side.faces, lt.smooth_t1[side.faces].data(),
                                lt.smooth_t2[side.faces].data());
            if (side.corner) return corner_tangents(in, side.vertex, points, side.faces);
            return Tangents(in, side.vertex, points, side.faces + 1, lt.side_t1[side.faces].data() + 1,
                            lt.side_t2[side.faces].data() + 1);
        },
        normals, [&lt](std::size_t i) { return lt.sides[i].row; });
}

}  // namespace loopsub::detail
