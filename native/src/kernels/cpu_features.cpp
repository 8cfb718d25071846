#include "kernels/cpu_features.h"

#if defined(LOOPSUB_X86_SIMD)
#if defined(_MSC_VER)
#include <immintrin.h>
#include <intrin.h>
#else
#include <cpuid.h>
#endif
#include <cstdint>
#endif

namespace loopsub::detail {

#if !defined(LOOPSUB_X86_SIMD)

bool cpu_runs_sse41() { return false; }
bool cpu_runs_avx2_fma() { return false; }

#else

// The CPU is asked directly (cpuid, xgetbv), not through GCC's and Clang's __builtin_cpu_supports: its runtime
// (libgcc's, compiler-rt's __cpu_indicator_init) is one some toolchains only stub. zig 0.17's, which builds the
// add-on's modules for glibc 2.28 (scripts/build_modules.sh), answers false for every feature, which made those
// modules run the scalar kernel on every CPU.
namespace {

enum Register { EAX, EBX, ECX, EDX };

bool cpuid_bit(unsigned leaf, Register register_index, int bit) {
    unsigned registers[4] = {};
#if defined(_MSC_VER)
    int values[4];
    __cpuidex(values, 0, 0);
    if (static_cast<unsigned>(values[0]) < leaf) return false;
    __cpuidex(values, static_cast<int>(leaf), 0);
    for (int i = 0; i < 4; ++i) registers[i] = static_cast<unsigned>(values[i]);
#else
    if (!__get_cpuid_count(leaf, 0, &registers[EAX], &registers[EBX], &registers[ECX], &registers[EDX])) return false;
#endif
    return (registers[register_index] >> bit) & 1;
}

// XCR0: which register states the OS saves on a context switch. Only called when cpuid says OSXSAVE.
std::uint64_t os_saved_states() {
#if defined(_MSC_VER)
    return _xgetbv(0);
#else
    unsigned low, high;
    __asm__ volatile("xgetbv" : "=a"(low), "=d"(high) : "c"(0));
    return (static_cast<std::uint64_t>(high) << 32) | low;
#endif
}

}  // namespace

bool cpu_runs_sse41() { return cpuid_bit(1, ECX, 19); }

bool cpu_runs_avx2_fma() {
    // AVX2 and FMA on the CPU, and the OS saving the YMM registers (OSXSAVE, then XCR0's SSE and AVX bits).
    const bool os_saves_ymm = cpuid_bit(1, ECX, 27) && (os_saved_states() & 0x6) == 0x6;
    return os_saves_ymm && cpuid_bit(7, EBX, 5) && cpuid_bit(1, ECX, 12);
}

#endif

}  // namespace loopsub::detail
