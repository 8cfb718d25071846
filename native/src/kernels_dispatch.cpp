// Run-time choice of the evaluation kernel: the widest instruction set the CPU has, unless one is forced.
#include "kernels.h"

namespace loopsub::detail {

Kernel resolve_kernel(Kernel requested) {
    if (requested != Kernel::Auto) return requested == Kernel::AVX2 && !__builtin_cpu_supports("avx2") ? Kernel::SSE41 : requested;
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return Kernel::AVX2;
    if (__builtin_cpu_supports("sse4.1")) return Kernel::SSE41;
    return Kernel::Scalar;
}

RefineFn refine_function(Kernel resolved) {
    switch (resolved) {
        case Kernel::AVX2: return refine_avx2;
        case Kernel::SSE41: return refine_sse41;
        default: return refine_scalar;
    }
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
