// Run-time choice of the evaluation kernel: the widest instruction set the CPU has, unless one is forced; and the
// runs over a level derived from its parent, chunk by chunk.
#include <algorithm>
#include <vector>

#include "cpu_features.h"
#include "kernels.h"

namespace loopsub::detail {

void refine_ranges(RefineFn refine, const LevelStencils& s, ChannelsView<const float> in, ChannelsView<float> out,
                   Range vertices, Range edges) {
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

// A forced kernel the CPU cannot run steps down to the next narrower one rather than crash.
Kernel resolve_kernel(Kernel requested) {
    const bool avx2 = cpu_runs_avx2_fma();
    const bool sse41 = cpu_runs_sse41();
    switch (requested) {
        case Kernel::Scalar: return Kernel::Scalar;
        case Kernel::SSE41: return sse41 ? Kernel::SSE41 : Kernel::Scalar;
        default: return avx2 ? Kernel::AVX2 : sse41 ? Kernel::SSE41 : Kernel::Scalar;  // Auto or AVX2
    }
}

RefineFn refine_function(Kernel resolved) {
#if defined(LOOPSUB_X86_SIMD)
    switch (resolved) {
        case Kernel::AVX2: return refine_avx2;
        case Kernel::SSE41: return refine_sse41;
        default: return refine_scalar;
    }
#else
    (void)resolved;  // resolve_kernel gives Scalar when the build has no SIMD kernel
    return refine_scalar;
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
