// What every fuzz target checks once the core has accepted an input: it runs every per-frame call, and nothing it
// writes may be other than finite. Refusals (InputError, MemoryLimitError) are fine; anything else ends the run.
#pragma once

#include <cmath>
#include <cstdlib>
#include <vector>

#include "loopsub/loopsub.h"

namespace loopsub::fuzz {

// Small enough that a fuzzer never waits on a big refinement; the refusal path is exercised instead.
inline constexpr std::uint64_t kMemoryLimit = std::uint64_t(64) << 20;

inline void require_finite(const std::vector<float>& values) {
    for (float value : values)
        if (!std::isfinite(value)) std::abort();  // finite input must never give a non-finite output
}

// Evaluates the plan with the given positions (3 per vertex) and face-varying values (channels per corner).
inline void exercise(Plan& plan, const std::vector<float>& positions, const std::vector<float>& corners, int corner_channels) {
    std::vector<float> out(std::size_t(plan.num_output_vertices()) * 3);
    try {
        plan.evaluate(interleaved(positions.data(), 3), interleaved(out.data(), 3));
        require_finite(out);
    } catch (const InputError&) {
    }
    if (corner_channels > 0) {
        std::vector<float> refined(std::size_t(plan.num_output_triangles()) * 3 * corner_channels);
        try {
            plan.evaluate_face_varying(corners.data(), refined.data(), corner_channels);
            require_finite(refined);
        } catch (const InputError&) {
        }
    }
}

}  // namespace loopsub::fuzz
