// A tessellation's rates: the edges' given rates checked and numbered; the levels a rate needs.
#include "tessellate/tessellation_rates.h"

#include "tessellate/tessellation_data.h"

namespace loopsub::detail {

namespace {

// what(): the rate's name, made only for the error.
template <typename Name>
int rate_in_range(int rate, Name what) {
    if (rate < 1 || rate > kMaxTessellationRate)
        tessellation_fail(what() + " must be between 1 and " + std::to_string(kMaxTessellationRate) + ", got " +
                          std::to_string(rate));
    return rate;
}

}  // namespace

EdgeRates edges_with_rates(const KeptInput& input, int num_vertices, const TessellationRates& rates) {
    EdgeRates edges;
    const int uniform = rate_in_range(rates.uniform_rate, [] { return std::string("uniform_rate"); });
    edges.rates.assign(input.edges.keys.size(), uniform);
    if (rates.num_edges < 0) tessellation_fail("num_edges must not be negative");
    for (int k = 0; k < rates.num_edges; ++k) {
        const std::int32_t a = rates.edges[2 * k], b = rates.edges[2 * k + 1];
        // screen_space_rates gives the edges in this order: then the k-th is the one.
        const int e = std::size_t(k) < input.edges.keys.size() && input.edges.keys[std::size_t(k)] == edge_key(a, b)
                          ? k
                          : input.find_edge(a, b);
        auto name = [a, b] { return "edge (" + std::to_string(a) + ", " + std::to_string(b) + ")"; };
        if (e < 0) tessellation_fail("a rate for " + name() + ", which no triangle has");
        edges.rates[std::size_t(e)] = rate_in_range(rates.rates[k], [&] { return "the rate of " + name(); });
    }
    std::vector<std::uint8_t> on_surface(input.surface_everywhere() ? 0 : edges.rates.size(), 0);
    for (std::size_t c = 0; c < std::size_t(3) * input.has_surface.size(); ++c)
        if (input.has_surface[c / 3]) on_surface[std::size_t(input.edges.corner_edges[c])] = 1;
    std::int64_t next = num_vertices;
    for (std::size_t e = 0; e < edges.rates.size(); ++e) {
        edges.first_point.push_back(next);
        if (on_surface.empty() || on_surface[e]) next += edges.rates[e] - 1;
    }
    edges.end_point = next;
    return edges;
}

int two_adic(int rate) {
    int e = 0;
    while (rate % 2 == 0) rate /= 2, ++e;
    return e;
}

}  // namespace loopsub::detail
