// The "quads" layout shared by the SIMD kernels: each element's channels contiguous and padded to a multiple of
// four floats (channel_stride 1, element_stride a multiple of 4), so that one 16-byte load fetches four channels of
// a neighbour. This is the seed's advice (slides 36-45: keep a vertex's x, y, z in one load) and the layout the
// plan's scratch levels use: there a smooth edge point costs four loads, against twelve (one per channel and
// neighbour) for planar data, and the loads are what bounds these kernels (docs/benchmark.md).
//
// Everything here has internal linkage: the header is compiled into translation units built for different
// instruction sets, and one shared inline copy (the linker keeps any one) could carry AVX2 code into the SSE4.1 path.
#pragma once

#include <emmintrin.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "loopsub/loopsub.h"
#include "tables/stencils.h"

namespace loopsub::detail {
namespace {

constexpr int kQuad = 4;

// True when every element's channels can be read as whole quads. Lanes past num_channels are read too and go through
// the same arithmetic without being stored: padding inside the element (which should hold zeros: garbage there could
// be a denormal, which slows the arithmetic down), or, for rows of three channels, the next element's first channel;
// such rows (the evaluation's scratch) must be followed by a readable quad.
inline bool reads_as_quads(const ChannelsView<const float>& v) {
    return v.channel_stride == 1 && (v.element_stride % kQuad == 0 || (v.element_stride == 3 && v.num_channels == 3));
}

// The input of a quad pass: quad of element i at in + i * step. Step is a compile-time 4 or 3 in the common cases (up
// to four channels, or positions), which keeps the address arithmetic cheap; 0 means the run-time `step`.
template <std::size_t Step>
struct QuadSource {
    const float* in;
    std::size_t step;

    const float* at(std::size_t element) const { return in + element * (Step ? Step : step); }
};

// Where quad h (channels 4h .. 4h + lanes - 1) of an output goes: channel 4h + j of element i is at
// data + i * element_stride + j * channel_stride. Only those `lanes` channels are written.
struct QuadTarget {
    float* data;
    std::size_t element_stride, channel_stride;
    int lanes;  // 4, or fewer in the last quad when the channel count is not a multiple of 4

    // Quads of four channels, four floats apart: a plan's scratch level (see PackedQuads).
    bool packed() const { return channel_stride == 1 && lanes == kQuad && element_stride == kQuad; }

    // Any layout: contiguous lanes (a user's n x 3 array) with one or two stores, others lane by lane.
    void store(std::size_t element, __m128 v) const {
        float* q = data + element * element_stride;
        if (channel_stride == 1) {
            switch (lanes) {
                case 4: _mm_storeu_ps(q, v); return;
                case 3:
                    _mm_storel_pi(reinterpret_cast<__m64*>(q), v);
                    _mm_store_ss(q + 2, _mm_movehl_ps(v, v));
                    return;
                case 2: _mm_storel_pi(reinterpret_cast<__m64*>(q), v); return;
                default: _mm_store_ss(q, v); return;
            }
        }
        alignas(16) float lane_values[kQuad];
        _mm_store_ps(lane_values, v);
        for (int j = 0; j < lanes; ++j) q[j * channel_stride] = lane_values[j];
    }
};

// A packed QuadTarget, known to be one at compile time: the kernels' passes are templates on their output type,
// so that the common case stores without testing the layout.
struct PackedQuads {
    float* data;

    void store(std::size_t element, __m128 v) const { _mm_storeu_ps(data + element * kQuad, v); }
};

// Three channels, three floats apart: a user's n x 3 array of positions, what the last level usually writes. Known at
// compile time, like PackedQuads, so that each store is two moves rather than a test of the layout first.
struct PackedRows3 {
    float* data;

    void store(std::size_t element, __m128 v) const {
        float* q = data + element * 3;
        _mm_storel_pi(reinterpret_cast<__m64*>(q), v);
        _mm_store_ss(q + 2, _mm_movehl_ps(v, v));
    }
    // Four rows at once (points p0 .. p3, each in a quad whose last lane is unused): three 16-byte stores where
    // one row at a time takes eight (docs/benchmark.md, "rows of three stored four at a time").
    void store_four(std::size_t element, __m128 p0, __m128 p1, __m128 p2, __m128 p3) const {
        float* q = data + element * 3;
        const __m128 z0_x1 = _mm_shuffle_ps(p0, p1, _MM_SHUFFLE(0, 0, 2, 2));      // z0 z0 x1 x1
        _mm_storeu_ps(q, _mm_shuffle_ps(p0, z0_x1, _MM_SHUFFLE(2, 0, 1, 0)));      // x0 y0 z0 x1
        _mm_storeu_ps(q + 4, _mm_shuffle_ps(p1, p2, _MM_SHUFFLE(1, 0, 2, 1)));     // y1 z1 x2 y2
        const __m128 z2_x3 = _mm_shuffle_ps(p2, p3, _MM_SHUFFLE(0, 0, 2, 2));      // z2 z2 x3 x3
        _mm_storeu_ps(q + 8, _mm_shuffle_ps(z2_x3, p3, _MM_SHUFFLE(2, 1, 2, 0)));  // z2 x3 y3 z3
    }
};

inline QuadTarget quad_target(const ChannelsView<float>& out, int quad) {
    const int lanes = out.num_channels - quad * kQuad < kQuad ? out.num_channels - quad * kQuad : kQuad;
    return {out.data + std::size_t(quad) * kQuad * out.channel_stride, out.element_stride, out.channel_stride, lanes};
}

// The tables a run reads, as plain pointers (a StencilView and the smooth weights): vector stores may alias anything,
// so the compiler would otherwise reload the data pointers of LevelStencils' vectors after every output.
struct Tables : StencilView {
    const float *smooth_self, *smooth_ring;
    std::size_t first_edge_point;  // output element of edge point 0

    Tables(const LevelStencils& s, const StencilView& view)
        : StencilView(view),
          smooth_self(s.smooth_self.data()),
          smooth_ring(s.smooth_ring.data()),
          first_edge_point(std::size_t(s.num_vertices)) {}
};

// Two neighbouring indices of a table in one 8-byte load: the kernels are bound by their loads, a quad per
// neighbour and an index per quad, and splitting the pair costs a shift.
inline void load_index_pair(const std::int32_t* at, std::int32_t& first, std::int32_t& second) {
    std::uint64_t pair;
    std::memcpy(&pair, at, sizeof pair);
    first = std::int32_t(std::uint32_t(pair));
    second = std::int32_t(std::uint32_t(pair >> 32));
}

// The ends (a, b) and wings (c, d) of edges e and e + 1 from the tables, read a pair at a time.
struct EdgePairIndices {
    std::int32_t a[2], b[2], c[2], d[2];
};
inline EdgePairIndices next_edges_indices(const StencilView& t, int e) {
    const std::int32_t* ends = t.edge_ends + 2 * (e - t.edge_base);
    EdgePairIndices i;
    load_index_pair(ends, i.a[0], i.b[0]);
    load_index_pair(ends + 2, i.a[1], i.b[1]);
    load_index_pair(t.edge_wing_c + (e - t.edge_base), i.c[0], i.c[1]);
    load_index_pair(t.edge_wing_d + (e - t.edge_base), i.d[0], i.d[1]);
    return i;
}

// Runs an instruction set's smooth pass, smooth(tables, source, target), over every quad of channels, with the
// source and target types that let it compile the common layouts to plain strided loads and stores.
template <typename SmoothPass>
void for_each_quad(const LevelStencils& s, const StencilView& view, ChannelsView<const float> in,
                   ChannelsView<float> out, const SmoothPass& smooth) {
    const Tables tables(s, view);
    for (int quad = 0; quad * kQuad < in.num_channels; ++quad) {
        const float* first_channel = in.data + quad * kQuad;
        const QuadTarget target = quad_target(out, quad);
        const bool rows3 = target.channel_stride == 1 && target.element_stride == 3 && target.lanes == 3;
        if (in.element_stride == kQuad && target.packed())
            smooth(tables, QuadSource<kQuad>{first_channel, kQuad}, PackedQuads{target.data});
        else if (in.element_stride == kQuad) smooth(tables, QuadSource<kQuad>{first_channel, kQuad}, target);
        else if (in.element_stride == 3 && rows3)  // positions, from the evaluation's scratch into an n x 3 array
            smooth(tables, QuadSource<3>{first_channel, 3}, PackedRows3{target.data});
        else if (in.element_stride == 3) smooth(tables, QuadSource<3>{first_channel, 3}, target);
        else smooth(tables, QuadSource<0>{first_channel, in.element_stride}, target);
    }
}

// One quad of the interior edge points of parent faces [faces.begin, faces.end) (LevelStencils::interior): per face,
// its three corners and three midpoints give its three edges. smooth(a, b, c, d) is the instruction set's smooth edge
// mask, the arithmetic of its edge points from tables (the same bits either way).
template <std::size_t Step, typename Out, typename SmoothEdge>
void interior_quad(const LevelStencils& s, const QuadSource<Step> in, const Out out, Range faces, SmoothEdge smooth) {
    const LevelStencils::InteriorFaces& interior = *s.interior;
    const std::int32_t* face_vertices = interior.face_vertices.data();
    const std::int32_t* face_edges = interior.face_edges.data();
    const std::int32_t nv = interior.parent_vertices;
    const std::size_t first_output = std::size_t(s.num_vertices) + std::size_t(interior.first_edge);
    auto face_points = [&](int f, __m128 points[3]) {
        const std::int32_t* v = face_vertices + 3 * std::size_t(f);
        const std::int32_t* fe = face_edges + 3 * std::size_t(f);
        const __m128 m0 = _mm_loadu_ps(in.at(nv + fe[0])), m1 = _mm_loadu_ps(in.at(nv + fe[1])),
                     m2 = _mm_loadu_ps(in.at(nv + fe[2]));
        points[0] = smooth(m0, m1, _mm_loadu_ps(in.at(v[1])), m2);
        points[1] = smooth(m1, m2, _mm_loadu_ps(in.at(v[2])), m0);
        points[2] = smooth(m2, m0, _mm_loadu_ps(in.at(v[0])), m1);
    };
    int f = faces.begin;
    if constexpr (std::is_same_v<Out, PackedRows3>) {
        for (; f + 3 < faces.end; f += 4) {  // twelve points, three PackedRows3::store_four
            __m128 p[12];
            for (int k = 0; k < 4; ++k) face_points(f + k, p + 3 * k);
            const std::size_t first = first_output + 3 * std::size_t(f);
            out.store_four(first, p[0], p[1], p[2], p[3]);
            out.store_four(first + 4, p[4], p[5], p[6], p[7]);
            out.store_four(first + 8, p[8], p[9], p[10], p[11]);
        }
    }
    for (; f < faces.end; ++f) {
        __m128 p[3];
        face_points(f, p);
        for (int k = 0; k < 3; ++k) out.store(first_output + 3 * std::size_t(f) + k, p[k]);
    }
}

// One quad of the smooth points of the fans of parent edges [parent_edges.begin, parent_edges.end) (FanFn): a
// midpoint of two faces (valence 6) with its two halves from its ring's seven points. vertex(self, ring_sum, w_self,
// w_ring) and edge(a, b, c, d) are the instruction set's smooth masks as its table passes weigh them (the ring summed
// from zero in ring order, as theirs), so the bits are the tables'; irregular(h) computes another fan from the tables.
template <std::size_t Step, typename Out, typename Vertex, typename Edge, typename Irregular>
void fan_quad(const Tables& t, const LevelStencils& s, const QuadSource<Step> in, const Out out, Range parent_edges,
              Vertex vertex, Edge edge, Irregular irregular) {
    const int nv = s.fan_first_midpoint;
    const bool any_regular = s.smooth_self.size() > 6;
    const float w_self = any_regular ? s.smooth_self[6] : 0.0f, w_ring = any_regular ? s.smooth_ring[6] : 0.0f;
    auto regular = [&](int h) { return t.valence(nv + h) == 6; };
    auto fan = [&](int h, __m128& midpoint, __m128& half_a, __m128& half_b) {
        const std::int32_t* ring = t.ring + t.ring_first(nv + h);
        std::int32_t a, b, c0, c1, d0, d1;
        load_index_pair(ring, a, b);
        load_index_pair(ring + 2, c0, c1);
        load_index_pair(ring + 4, d0, d1);
        const __m128 pa = _mm_loadu_ps(in.at(a)), pb = _mm_loadu_ps(in.at(b)), pm = _mm_loadu_ps(in.at(nv + h));
        const __m128 pc0 = _mm_loadu_ps(in.at(c0)), pc1 = _mm_loadu_ps(in.at(c1));
        const __m128 pd0 = _mm_loadu_ps(in.at(d0)), pd1 = _mm_loadu_ps(in.at(d1));
        __m128 ring_sum = _mm_add_ps(_mm_setzero_ps(), pa);
        ring_sum = _mm_add_ps(_mm_add_ps(_mm_add_ps(_mm_add_ps(_mm_add_ps(ring_sum, pb), pc0), pc1), pd0), pd1);
        midpoint = vertex(pm, ring_sum, w_self, w_ring);
        half_a = edge(pa, pm, pc0, pd0);  // half 2h = (a, m): wings c[2h], d[2h]
        half_b = edge(pm, pb, pc1, pd1);  // half 2h + 1 = (m, b)
    };
    auto one = [&](int h) {
        if (!regular(h)) return irregular(h);
        __m128 midpoint, half_a, half_b;
        fan(h, midpoint, half_a, half_b);
        out.store(std::size_t(nv + h), midpoint);
        out.store(t.first_edge_point + 2 * std::size_t(h), half_a);
        out.store(t.first_edge_point + 2 * std::size_t(h) + 1, half_b);
    };
    int h = parent_edges.begin;
    if constexpr (std::is_same_v<Out, PackedRows3>) {
        for (; h + 3 < parent_edges.end; h += 4) {  // four midpoints, eight halves: three PackedRows3::store_four
            if (!(regular(h) && regular(h + 1) && regular(h + 2) && regular(h + 3))) {
                for (int k = 0; k < 4; ++k) one(h + k);
                continue;
            }
            __m128 m[4], e[8];
            for (int k = 0; k < 4; ++k) fan(h + k, m[k], e[2 * k], e[2 * k + 1]);
            out.store_four(std::size_t(nv + h), m[0], m[1], m[2], m[3]);
            out.store_four(t.first_edge_point + 2 * std::size_t(h), e[0], e[1], e[2], e[3]);
            out.store_four(t.first_edge_point + 2 * std::size_t(h) + 4, e[4], e[5], e[6], e[7]);
        }
    }
    for (; h < parent_edges.end; ++h) one(h);
}

}  // namespace
}  // namespace loopsub::detail
