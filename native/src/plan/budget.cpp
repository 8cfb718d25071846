#include "plan/budget.h"

#include <algorithm>
#include <cstdio>

#include "loopsub/loopsub.h"

namespace loopsub::detail {

std::uint64_t estimate_for_counts(LevelCounts level, int levels, int num_channels) {
    // Bytes per element, summed over the arrays that hold them.
    // Kept with any level: the input triangles' edges (12 per face), which name the output edges' input edges.
    std::uint64_t kept = levels > 0 ? mul(12, level.faces) : 0, largest_transient = 0;
    LevelCounts previous = level;
    for (int l = 0; l < levels; ++l) {
        // Kept per level: stencils (rings 8, edge points 16, offsets 4), the level's edges (8), vertex types (1).
        kept = add(kept, add(mul(32, level.edges), mul(5, level.vertices)));
        // Held while refining it: connectivity (faces and face edges 24 + edge faces 12 per face-edge pair,
        // vertex edges 12) and sharpness (8 per edge and vertex).
        const std::uint64_t transient = add(mul(36, level.faces), add(mul(20, level.edges), mul(12, level.vertices)));
        largest_transient = std::max(largest_transient, transient);
        previous = level;
        level = level.child();
    }
    // The last level's triangles and parents (16), the output, and the two scratch levels of evaluation (four
    // channels, or fewer padded to four: an evaluation runs a quad of channels at a time).
    const std::uint64_t padded = 4;
    kept = add(kept, add(mul(16, level.faces), add(mul(mul(4, std::uint64_t(num_channels)), level.vertices),
                                                   mul(mul(4, padded), mul(2, previous.vertices)))));
    return add(kept, mul(2, largest_transient));  // a child level is built while its parent still lives
}

}  // namespace loopsub::detail

namespace loopsub {

std::string describe_bytes(std::uint64_t bytes) {
    char text[64];
    const bool gib = bytes >= (std::uint64_t(1) << 30);
    std::snprintf(text, sizeof text, "%.2f %s (%llu bytes)",
                  double(bytes) / double(std::uint64_t(1) << (gib ? 30 : 20)), gib ? "GiB" : "MiB",
                  (unsigned long long)bytes);
    return text;
}

}  // namespace loopsub
