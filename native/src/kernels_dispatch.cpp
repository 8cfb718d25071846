// Run-time choice of the evaluation kernel: the widest instruction set the CPU has, unless one is forced.
#include "cpu_features.h"
#include "kernels.h"

namespace loopsub::detail {

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
