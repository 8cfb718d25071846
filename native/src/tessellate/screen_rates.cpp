// Rates from the screen (loopsub/tessellation.h, screen_space_rates): an edge's length on screen, in segments; and the
// camera of a look-at and a perspective (look_at_camera).
#include <algorithm>
#include <array>
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

Camera look_at_camera(const float eye[3], const float target[3], const float up[3], float fov_degrees, float width,
                      float height) {
    using Vector = std::array<double, 3>;
    auto cross = [](const Vector& a, const Vector& b) {
        return Vector{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    };
    auto unit = [](Vector a) {
        const double length = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        if (!(length > 0.0)) throw InputError("look_at_camera: the eye, the target and up must span a view");
        for (double& c : a) c /= length;
        return a;
    };
    const Vector forward = unit({double(target[0]) - eye[0], double(target[1]) - eye[1], double(target[2]) - eye[2]}),
                 right = unit(cross(forward, {up[0], up[1], up[2]})), above = cross(right, forward);
    const double f = 1.0 / std::tan(0.5 * double(fov_degrees) * 3.14159265358979323846 / 180.0);
    const double aspect = double(width) / height, near = 1e-3, far = 1e6;
    const double* axes[3] = {right.data(), above.data(), forward.data()};
    double view[3][4];  // rows: right, up, -forward (OpenGL looks down -z); translation last
    for (int r = 0; r < 3; ++r) {
        const double sign = r == 2 ? -1.0 : 1.0;
        for (int c = 0; c < 3; ++c) view[r][c] = sign * axes[r][c];
        view[r][3] = -(view[r][0] * eye[0] + view[r][1] * eye[1] + view[r][2] * eye[2]);
    }
    Camera camera;
    const double scale[4] = {f / aspect, f, (far + near) / (near - far), -1.0};
    for (int c = 0; c < 4; ++c) {
        camera.world_to_clip[c] = float(scale[0] * view[0][c]);
        camera.world_to_clip[4 + c] = float(scale[1] * view[1][c]);
        camera.world_to_clip[8 + c] = float(scale[2] * view[2][c] + (c == 3 ? 2.0 * far * near / (near - far) : 0.0));
        camera.world_to_clip[12 + c] = float(scale[3] * view[2][c]);
    }
    camera.viewport_width = width, camera.viewport_height = height;
    return camera;
}

TessellationRates ScreenRates::view() const {
    TessellationRates view;
    view.edges = edges.data(), view.rates = rates.data(), view.num_edges = int(rates.size());
    return view;
}

ScreenRates screen_space_rates(const MeshView& mesh, const float* positions, const Camera& camera, float pixels,
                               int max_rate, DicingMeasure measure, float offscreen_scale) {
    const bool by_deviation = measure == DicingMeasure::Deviation;
    if (!(pixels > 0.0f) || !std::isfinite(pixels))
        fail("pixels must be a positive number, got " + std::to_string(pixels));
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
    const std::vector<std::uint64_t> keys = detail::sorted_edge_keys(mesh.triangles, mesh.num_triangles);

    // The third corners of each edge's first two faces (-1: none), for its bulge.
    std::vector<std::int32_t> opposite(2 * keys.size(), -1);
    if (by_deviation)
        for (std::size_t c = 0; c < 3 * std::size_t(mesh.num_triangles); ++c) {
            const std::size_t face = c - c % 3;
            const std::uint64_t key = detail::edge_key(mesh.triangles[c], mesh.triangles[face + (c + 1) % 3]);
            const std::size_t e = std::size_t(std::lower_bound(keys.begin(), keys.end(), key) - keys.begin());
            std::int32_t* slot = &opposite[2 * e];
            (slot[0] < 0 ? slot[0] : slot[1]) = mesh.triangles[face + (c + 2) % 3];
        }

    ScreenRates out;
    out.edges.reserve(2 * keys.size()), out.rates.reserve(keys.size());
    // Pixels per unit of length at depth 1 (w = 1), perpendicular to the view: the matrix's scale of y (its up row,
    // made of the focal length) times half the viewport's height.
    const float* m = camera.world_to_clip;
    const double pixels_at_depth_one =
        std::sqrt(double(m[4]) * m[4] + double(m[5]) * m[5] + double(m[6]) * m[6]) * 0.5 * camera.viewport_height;
    for (std::size_t e = 0; e < keys.size(); ++e) {
        const std::int32_t a = std::int32_t(keys[e] >> 32), b = std::int32_t(keys[e] & 0xffffffffu);
        const float* pa = positions + 3 * std::size_t(a);
        const float* pb = positions + 3 * std::size_t(b);
        float middle[3], offset[3];  // the edge's midpoint, and what is measured there: the edge or its bulge
        for (int k = 0; k < 3; ++k) middle[k] = 0.5f * (pa[k] + pb[k]), offset[k] = pb[k] - pa[k];
        if (by_deviation) {
            const std::int32_t c = opposite[2 * e], d = opposite[2 * e + 1];
            for (int k = 0; k < 3; ++k)
                offset[k] =
                    c >= 0 && d >= 0
                        ? (positions[3 * std::size_t(c) + k] + positions[3 * std::size_t(d) + k] - pa[k] - pb[k]) / 8.0f
                        : 0.0f;
        }
        const Clip p = to_clip(m, pa), q = to_clip(m, pb), mid = to_clip(m, middle);
        const double length =
            std::sqrt(double(offset[0]) * offset[0] + double(offset[1]) * offset[1] + double(offset[2]) * offset[2]);
        if (!std::isfinite(p.x + p.y + p.w + q.x + q.y + q.w + length))
            fail("the positions of edge (" + std::to_string(a) + ", " + std::to_string(b) + ") are not finite");
        int rate = 1;
        if (p.w > 0.0 || q.w > 0.0) {  // else both ends are behind the camera: unseen, one segment
            // As Cycles measures: the length in pixels it would have at its midpoint's depth, facing the camera; a
            // midpoint out of the view (or behind the camera) coarser by offscreen_scale.
            const double depth = std::max(std::fabs(mid.w), 1e-6);
            double measured = length * pixels_at_depth_one / depth;
            const bool in_view = mid.w > 0.0 && std::fabs(mid.x) <= mid.w && std::fabs(mid.y) <= mid.w;
            double segments = by_deviation ? std::sqrt(measured / pixels) : measured / pixels;
            if (!in_view) segments /= offscreen_scale;
            rate = int(std::clamp(std::ceil(segments), 1.0, double(max_rate)));
        }
        out.edges.push_back(a), out.edges.push_back(b), out.rates.push_back(rate);
    }
    return out;
}

}  // namespace loopsub
