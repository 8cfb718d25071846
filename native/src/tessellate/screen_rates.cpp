// Rates from the screen (loopsub/tessellation.h, screen_space_rates): an edge's length on screen, in segments.
#include <algorithm>
#include <cmath>
#include <string>

#include "loopsub/tessellation.h"
#include "tessellate/level_patches.h"

namespace loopsub {

namespace {

[[noreturn]] void fail(const std::string& message) { throw InputError("screen_space_rates: " + message); }

struct Clip {
    double x, y, w;
};

Clip to_clip(const float m[16], const float* p) {
    auto row = [&](int r) {
        return double(m[4 * r]) * p[0] + double(m[4 * r + 1]) * p[1] + m[4 * r + 2] * double(p[2]) + m[4 * r + 3];
    };
    return {row(0), row(1), row(3)};
}

}  // namespace

TessellationRates ScreenRates::view() const {
    TessellationRates view;
    view.edges = edges.data(), view.rates = rates.data(), view.num_edges = int(rates.size());
    return view;
}

ScreenRates screen_space_rates(const MeshView& mesh, const float* positions, const Camera& camera,
                               float pixels_per_segment, int max_rate, float offscreen_scale) {
    if (!(pixels_per_segment > 0.0f) || !std::isfinite(pixels_per_segment))
        fail("pixels_per_segment must be a positive number, got " + std::to_string(pixels_per_segment));
    if (max_rate < 1 || max_rate > kMaxTessellationRate)
        fail("max_rate must be between 1 and " + std::to_string(kMaxTessellationRate) + ", got " +
             std::to_string(max_rate));
    if (!(offscreen_scale >= 1.0f) || !std::isfinite(offscreen_scale))
        fail("offscreen_scale must be at least 1, got " + std::to_string(offscreen_scale));
    if (!(camera.viewport_width > 0.0f) || !(camera.viewport_height > 0.0f) || !std::isfinite(camera.viewport_width) ||
        !std::isfinite(camera.viewport_height))
        fail("the viewport must have a positive size");
    for (float m : camera.world_to_clip)
        if (!std::isfinite(m)) fail("world_to_clip must be finite");
    if (mesh.num_triangles < 0 || (mesh.num_triangles > 0 && !mesh.triangles)) fail("no triangles");
    for (int c = 0; c < 3 * mesh.num_triangles; ++c)
        if (mesh.triangles[c] < 0 || mesh.triangles[c] >= mesh.num_vertices)
            fail("triangle corner " + std::to_string(c) + " names vertex " + std::to_string(mesh.triangles[c]) +
                 ", not in 0.." + std::to_string(mesh.num_vertices - 1));
    std::vector<std::uint64_t> keys;
    keys.reserve(3 * std::size_t(mesh.num_triangles));
    for (std::size_t c = 0; c < 3 * std::size_t(mesh.num_triangles); ++c)
        keys.push_back(detail::edge_key(mesh.triangles[c], mesh.triangles[c - c % 3 + (c + 1) % 3]));
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());

    ScreenRates out;
    out.edges.reserve(2 * keys.size()), out.rates.reserve(keys.size());
    const double half_width = 0.5 * camera.viewport_width, half_height = 0.5 * camera.viewport_height;
    for (const std::uint64_t key : keys) {
        const std::int32_t a = std::int32_t(key >> 32), b = std::int32_t(key & 0xffffffffu);
        const Clip p = to_clip(camera.world_to_clip, positions + 3 * std::size_t(a)),
                   q = to_clip(camera.world_to_clip, positions + 3 * std::size_t(b));
        if (!std::isfinite(p.x + p.y + p.w + q.x + q.y + q.w))
            fail("the positions of edge (" + std::to_string(a) + ", " + std::to_string(b) + ") are not finite");
        int rate;
        if (p.w <= 0.0 && q.w <= 0.0) {
            rate = 1;
        } else if (p.w <= 0.0 || q.w <= 0.0) {
            rate = max_rate;
        } else {
            const double px = p.x / p.w, py = p.y / p.w, qx = q.x / q.w, qy = q.y / q.w;
            double segments = std::hypot((px - qx) * half_width, (py - qy) * half_height) / pixels_per_segment;
            const bool outside = (px < -1.0 && qx < -1.0) || (px > 1.0 && qx > 1.0) || (py < -1.0 && qy < -1.0) ||
                                 (py > 1.0 && qy > 1.0);
            if (outside) segments /= offscreen_scale;
            rate = int(std::clamp(std::ceil(segments), 1.0, double(max_rate)));
        }
        out.edges.push_back(a), out.edges.push_back(b), out.rates.push_back(rate);
    }
    return out;
}

}  // namespace loopsub
