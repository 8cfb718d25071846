// Which SIMD kernels this build has and this CPU runs: the one place that knows compilers and architectures.
// The SIMD kernels exist on x86-64 only (CMake defines LOOPSUB_X86_SIMD there unless LOOPSUB_NO_SIMD is set);
// everywhere else the scalar reference path is the kernel.
#pragma once

namespace loopsub::detail {

bool cpu_runs_sse41();
bool cpu_runs_avx2_fma();

}  // namespace loopsub::detail
