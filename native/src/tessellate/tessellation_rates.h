// A tessellation's rates: each input edge's, checked, with the numbers of its inner points; each input triangle's
// sides; the levels a rate needs.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "base/input_checks.h"
#include "loopsub/tessellation.h"
#include "tessellate/kept_input.h"

namespace loopsub::detail {

// A rate given as an argument (the uniform rate, screen_space_rates' max_rate) in 1..kMaxTessellationRate: a plain
// InputError after `context`, as for the options (the call is at fault, not the mesh's data).
void validate_rate_argument(int rate, const char* name, const char* context);

// The rates' view readable: no negative count, no null array of a positive one (plain InputErrors, as validate_view).
void validate_rates_view(const TessellationRates& rates);

// Each rated edge (TessellationRates::edges and rates, as base/input_checks.h checks a mesh's data): tag(k, e, rate)
// for rated edge k on the input's edge e, report(NotAnEdge) for one that names no edge of the mesh, report
// (RateOutOfRange) for a rate outside 1..kMaxTessellationRate. One pass; a problem is built only where one is found.
template <typename Report, typename Tag>
bool check_rated_edges(const KeptInput& input, const TessellationRates& rates, Report&& report, Tag&& tag) {
    const std::vector<std::uint64_t>& keys = input.edges.keys;
    for (int k = 0; k < rates.num_edges; ++k) {
        const std::int32_t a = rates.edges[2 * k], b = rates.edges[2 * k + 1], rate = rates.rates[k];
        // screen_space_rates gives the edges in this order: then the k-th is the one.
        const int e =
            std::size_t(k) < keys.size() && keys[std::size_t(k)] == edge_key(a, b) ? k : input.find_edge(a, b);
        const bool in_range = rate >= 1 && rate <= kMaxTessellationRate;
        if (e >= 0 && in_range) {
            tag(k, e, rate);
            continue;
        }
        Problem p;
        p.kind = e < 0 ? Kind::NotAnEdge : Kind::RateOutOfRange, p.element = Element::RatedEdge, p.index = k;
        p.refers_to = a, p.other = b;
        if (e >= 0) p.value = float(rate), p.limit = float(kMaxTessellationRate);
        if (!report(p)) return false;
    }
    return true;
}

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
