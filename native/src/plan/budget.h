// How much memory a plan and its evaluation need, estimated before any is allocated, so that a request far past the
// limit is refused with the bytes it would need instead of failing half-way.
#pragma once

#include <cstdint>
#include <limits>

namespace loopsub::detail {

// Saturating arithmetic: a request for 40 levels must say "too much", not wrap around to a small number.
inline constexpr std::uint64_t kSaturated = std::numeric_limits<std::uint64_t>::max();
inline std::uint64_t add(std::uint64_t a, std::uint64_t b) { return a > kSaturated - b ? kSaturated : a + b; }
inline std::uint64_t mul(std::uint64_t a, std::uint64_t b) { return b != 0 && a > kSaturated / b ? kSaturated : a * b; }

// Counts of one level.
struct LevelCounts {
    std::uint64_t vertices, edges, faces;
    LevelCounts child() const { return {add(vertices, edges), add(mul(2, edges), mul(3, faces)), mul(4, faces)}; }
};

// Bytes a plan of `levels` levels from a level with these counts, and one evaluation of num_channels, hold at most.
std::uint64_t estimate_for_counts(LevelCounts level, int levels, int num_channels);

}  // namespace loopsub::detail
