// A tessellation's rates: each input edge's, checked, with the numbers of its inner points; each input triangle's
// sides; the levels a rate needs.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "loopsub/tessellation.h"
#include "tessellate/kept_input.h"

namespace loopsub::detail {

// The input's edges' rates (in KeptInput::edges' order), and the number of each one's first inner point (an edge of
// no triangle with a surface has none), and the number after the last.
struct EdgeRates {
    std::vector<int> rates;
    std::vector<std::int64_t> first_point;
    std::int64_t end_point = 0;
};

EdgeRates edges_with_rates(const KeptInput& input, int num_vertices, const TessellationRates& rates);

// One input triangle's sides: their edges' rates and first points, and whether each runs along its edge.
struct Sides {
    int rates[3];
    std::int64_t first_point[3];
    bool along[3];
    int inner_rate() const { return std::max({rates[0], rates[1], rates[2]}); }
};

int two_adic(int rate);  // the exponent of the largest power of two dividing rate

}  // namespace loopsub::detail
