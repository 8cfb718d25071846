// A tessellation's rates: the edges' given rates checked and numbered; the levels a rate needs.
#include "tessellate/tessellation_rates.h"

#include "tessellate/tessellation_data.h"

namespace loopsub::detail {

void validate_rate_argument(int rate, const char* name, const char* context) {
    if (rate < 1 || rate > kMaxTessellationRate)
        throw InputError(std::string(context) + name + " must be between 1 and " +
                         std::to_string(kMaxTessellationRate) + ", got " + std::to_string(rate));
}

void validate_rates_view(const TessellationRates& rates) {
    if (rates.num_edges < 0) tessellation_fail("num_edges must not be negative");
    if (rates.num_edges > 0 && (rates.edges == nullptr || rates.rates == nullptr))
        tessellation_fail("edges or rates are missing (null) but num_edges is " + std::to_string(rates.num_edges));
}

EdgeRates edges_with_rates(const KeptInput& input, int num_vertices, const TessellationRates& rates) {
    validate_rate_argument(rates.uniform_rate, "uniform_rate", "tessellation: ");
    validate_rates_view(rates);
    EdgeRates edges;
    edges.rates.assign(input.edges.keys.size(), rates.uniform_rate);
    check_rated_edges(input, rates, ThrowFirst{"tessellation: "},
                      [&edges](int, int e, int rate) { edges.rates[std::size_t(e)] = rate; });
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
