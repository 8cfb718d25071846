#include "cpu_features.h"

#if defined(LOOPSUB_X86_SIMD) && defined(_MSC_VER)
#include <immintrin.h>
#include <intrin.h>
#endif

namespace loopsub::detail {

#if !defined(LOOPSUB_X86_SIMD)

bool cpu_runs_sse41() { return false; }
bool cpu_runs_avx2_fma() { return false; }

#elif defined(_MSC_VER)

namespace {

bool cpuid_bit(int leaf, int register_index, int bit) {
    int registers[4];
    __cpuidex(registers, leaf, 0);
    return (registers[register_index] >> bit) & 1;
}

}  // namespace

bool cpu_runs_sse41() { return cpuid_bit(1, 2, 19); }  // ECX.SSE4_1
bool cpu_runs_avx2_fma() {
    // AVX2 and FMA on the CPU, and the OS saving the YMM registers (OSXSAVE, then XCR0 bits 1 and 2).
    const bool os_saves_ymm = cpuid_bit(1, 2, 27) && (_xgetbv(0) & 0x6) == 0x6;
    return os_saves_ymm && cpuid_bit(7, 1, 5) && cpuid_bit(1, 2, 12);  // EBX.AVX2, ECX.FMA
}

#else  // GCC and Clang

bool cpu_runs_sse41() { return __builtin_cpu_supports("sse4.1"); }
bool cpu_runs_avx2_fma() { return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"); }

#endif

}  // namespace loopsub::detail
