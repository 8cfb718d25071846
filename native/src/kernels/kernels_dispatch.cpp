// Run-time choice of the evaluation kernel: the widest instruction set the CPU has, unless one is forced; and how a
// part of a level is run: by kind where the level reads from its parent's faces, chunk by chunk where it is derived.
#include <algorithm>
#include <vector>

#include "kernels/cpu_features.h"
#include "kernels/kernels.h"
#include "base/parallel.h"

namespace loopsub::detail {

namespace {

// Part `part` of `parts` of [begin, end).
Range share_of(int begin, int end, int part, int parts) {
    const auto [first, last] = part_of(end - begin, part, parts);
    return Range{begin + first, begin + last};
}

// The interior edges [edges.begin, edges.end) of a level that reads them from its parent's faces: whole faces by the
// interior kernel, the edges of a face the range cuts through from a table of their own.
void refine_interior(const Kernels& kernels, const LevelStencils& s, ChannelsView<const float> in,
                     ChannelsView<float> out, Range edges) {
    const LevelStencils::InteriorFaces& interior = *s.interior;
    auto one_by_one = [&](int first, int last) {
        std::int32_t ends[6], c[3], d[3];
        for (int e = first; e < last; ++e) {
            std::int32_t abcd[4];
            interior.edge(e, abcd);
            ends[2 * (e - first)] = abcd[0], ends[2 * (e - first) + 1] = abcd[1], c[e - first] = abcd[2],
                          d[e - first] = abcd[3];
        }
        kernels.refine(s, {nullptr, nullptr, ends, c, d, 0, first}, in, out, {0, 0}, {first, last});
    };
    const int begin = edges.begin - interior.first_edge, end = edges.end - interior.first_edge;  // 3 per face
    const int first_face = (begin + 2) / 3, end_face = end / 3;
    if (first_face > end_face) return one_by_one(edges.begin, edges.end);  // within one face
    one_by_one(edges.begin, interior.first_edge + 3 * first_face);
    kernels.interior(s, in, out, {first_face, end_face});
    one_by_one(interior.first_edge + 3 * end_face, edges.end);
}

}  // namespace

void refine_part(const Kernels& kernels, const LevelStencils& s, ChannelsView<const float> in, ChannelsView<float> out,
                 int part, int parts) {
    auto share = [part, parts](int begin, int end) { return share_of(begin, end, part, parts); };
    if (s.fan_midpoints > 0) {  // each kind shared on its own: they cost differently
        kernels.refine(s, stored_view(s), in, out, share(0, s.fan_first_midpoint), {0, 0});  // old vertices
        kernels.fans(s, in, out, share(0, s.fan_midpoints));
        const int halves = 2 * s.fan_midpoints;
        if (!s.interior) return kernels.refine(s, stored_view(s), in, out, {0, 0}, share(halves, s.num_edges));
        const Range interior_faces = share(0, (s.num_edges - halves) / 3);
        refine_interior(kernels, s, in, out, {halves + 3 * interior_faces.begin, halves + 3 * interior_faces.end});
        return;
    }
    const Range vertices = share(0, s.num_vertices), edges = share(0, s.num_edges);
    const RefineFn refine = kernels.refine;
    if (!s.derived_from) return refine(s, stored_view(s), in, out, vertices, edges);
    // Chunks small enough that their tables stay in the first-level cache while the kernel reads them.
    constexpr int kChunk = 1024;
    const Topology& parent = *s.derived_from;
    std::vector<std::int32_t> offsets(kChunk + 1), ring, ends(2 * kChunk), c(kChunk), d(kChunk);
    for (int first = vertices.begin; first < vertices.end; first += kChunk) {
        const int last = std::min(vertices.end, first + kChunk);
        const Index base = child_ring_offset(parent, first);
        for (int v = first; v <= last; ++v) offsets[v - first] = child_ring_offset(parent, v) - base;
        ring.resize(std::size_t(offsets[last - first]));
        write_child_rings(parent, first, last, ring.data());
        refine(s, {offsets.data(), ring.data(), nullptr, nullptr, nullptr, first, 0}, in, out, {first, last}, {0, 0});
    }
    for (int first = edges.begin; first < edges.end; first += kChunk) {
        const int last = std::min(edges.end, first + kChunk);
        child_edges(parent, first, last, ends.data(), c.data(), d.data());
        refine(s, {nullptr, nullptr, ends.data(), c.data(), d.data(), 0, first}, in, out, {0, 0}, {first, last});
    }
}

void limit_part(const Kernels& kernels, const LimitTables& lt, ChannelsView<const float> in, ChannelsView<float> out,
                float* normals, int part, int parts) {
    auto share = [part, parts](int count) { return share_of(0, count, part, parts); };
    if (!lt.from_grandparent)
        return kernels.limit(lt, stored_view(lt.positions), in, out, normals, share(lt.positions.num_vertices));
    const Grandparent& g = lt.from_grandparent->grandparent;
    kernels.limit(lt, stored_view(lt.positions), in, out, normals, share(g.num_vertices));
    kernels.limit_grandchild(lt, in, out, normals, {share(g.num_edges), share(g.num_faces)});
}

void limit_over_grandchild_rings(LimitFn limit, const LimitTables& lt, ChannelsView<const float> in,
                                 ChannelsView<float> out, float* normals, Range vertices) {
    // Chunks whose rings stay in the first-level cache while the kernel reads them.
    constexpr int kChunk = 256;
    std::int32_t offsets[kChunk + 1], ring[6 * kChunk];
    for (int first = vertices.begin; first < vertices.end; first += kChunk) {
        const int last = std::min(vertices.end, first + kChunk);
        write_ordered_grandchild_rings(lt.from_grandparent->grandparent, first, last, offsets, ring);
        limit(lt, {offsets, ring, nullptr, nullptr, nullptr, first, 0}, in, out, normals, {first, last});
    }
}

void limit_grandchild_scalar(const LimitTables& lt, ChannelsView<const float> in, ChannelsView<float> out,
                             float* normals, GrandchildShare share) {
    Range kinds[3];
    share.vertices(lt.from_grandparent->grandparent, kinds);
    for (const Range& kind : kinds) limit_over_grandchild_rings(limit_scalar, lt, in, out, normals, kind);
}

// A forced kernel the CPU cannot run steps down to the next narrower one rather than crash. The CPU is asked once:
// in a virtual machine each cpuid leaves for the hypervisor (docs/benchmark.md, "Measurements behind the code").
Kernel resolve_kernel(Kernel requested) {
    static const bool avx2 = cpu_runs_avx2_fma();
    static const bool sse41 = cpu_runs_sse41();
    switch (requested) {
        case Kernel::Scalar: return Kernel::Scalar;
        case Kernel::SSE41: return sse41 ? Kernel::SSE41 : Kernel::Scalar;
        default: return avx2 ? Kernel::AVX2 : sse41 ? Kernel::SSE41 : Kernel::Scalar;  // Auto or AVX2
    }
}

Kernels kernel_functions(Kernel resolved) {
#if defined(LOOPSUB_X86_SIMD)
    switch (resolved) {
        case Kernel::AVX2:
            return {refine_avx2, refine_interior_avx2, refine_fans_avx2, limit_avx2, limit_grandchild_avx2, patch_avx2};
        case Kernel::SSE41:
            return {refine_sse41, refine_interior_sse41,  refine_fans_sse41,
                    limit_sse41,  limit_grandchild_sse41, patch_sse41};
        default:
            return {refine_scalar, refine_interior_scalar,  refine_fans_scalar,
                    limit_scalar,  limit_grandchild_scalar, patch_scalar};
    }
#else
    (void)resolved;  // resolve_kernel gives Scalar when the build has no SIMD kernel
    return {refine_scalar, refine_interior_scalar,  refine_fans_scalar,
            limit_scalar,  limit_grandchild_scalar, patch_scalar};
#endif
}

}  // namespace loopsub::detail

namespace loopsub {

const char* kernel_name(Kernel kernel) {
    switch (kernel) {
        case Kernel::Auto: return "auto";
        case Kernel::Scalar: return "scalar";
        case Kernel::SSE41: return "sse4.1";
        case Kernel::AVX2: return "avx2";
    }
    return "unknown";
}

Kernel best_kernel() { return detail::resolve_kernel(Kernel::Auto); }

}  // namespace loopsub
