// --screen-error: what camera-driven rates buy, against uniform rates, in pixels on screen (Bfr the reference).
#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "bench.h"
#include "loopsub/tessellation.h"

namespace bench {

using namespace OpenSubdiv;

namespace {

struct Scene {
    loopsub::MeshData mesh;
    loopsub::Camera camera;
};

Scene screen_scene() {
    Scene scene;
    std::vector<float>& p = scene.mesh.positions;
    std::vector<std::int32_t>& t = scene.mesh.triangles;
    const int n = 24;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const float x = 10.0f * (float(i) - n / 2.0f), z = 10.0f * (float(j) - n / 2.0f);
            p.insert(p.end(), {x, 0.8f * std::sin(0.15f * x) * std::cos(0.1f * z) - 0.5f, z});
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            t.insert(t.end(), {a, c, d, a, d, b});
        }
    const Mesh sphere = loopsub::testing::icosphere(2);
    const int first = scene.mesh.num_vertices();
    for (int v = 0; v < sphere.num_vertices(); ++v)
        p.insert(p.end(), {1.5f * sphere.positions[3 * v], 1.5f * sphere.positions[3 * v + 1] + 1.6f,
                           1.5f * sphere.positions[3 * v + 2]});
    for (int c : sphere.triangles) t.push_back(first + c);
    // A camera at (0, 2, 9) looking at (0, 1, 0), y up, 50 degrees.
    const float eye[3] = {0, 2, 9}, target[3] = {0, 1, 0}, up[3] = {0, 1, 0};
    scene.camera = loopsub::look_at_camera(eye, target, up, 50.0f, 1920.0f, 1080.0f);
    return scene;
}

// Where a point lands on screen, in pixels; false behind the camera.
bool to_pixels(const loopsub::Camera& c, const double p[3], double out[2]) {
    const float* m = c.world_to_clip;
    auto row = [&](int r) { return m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3]; };
    const double w = row(3);
    if (!(w > 0)) return false;
    out[0] = (row(0) / w + 1) * 0.5 * c.viewport_width, out[1] = (row(1) / w + 1) * 0.5 * c.viewport_height;
    return true;
}

// The tessellation's screen-space error: over its triangles whose centroid is in view, the distance in pixels between
// the centroid and the limit surface at the centroid's parameters (Bfr, at its finest). Its 99th percentile over the
// triangles, and over the picture (each triangle weighted by its area on screen: a uniform tessellation's many far
// triangles, each a fraction of a pixel, count for what they cover), and its largest.
struct ScreenError {
    double p99, picture_p99, max;  // pixels
};
ScreenError screen_error(const Scene& scene, const loopsub::Tessellation& t) {
    std::vector<float> points(3 * std::size_t(t.num_points()));
    t.evaluate(scene.mesh.positions.data(), points.data(), nullptr);
    const loopsub::MeshData& m = scene.mesh;
    const std::unique_ptr<Far::TopologyRefiner> refiner = osd_refiner(m.view(), false, 0);
    Bfr::SurfaceFactory::Options options;
    options.SetApproxLevelSmooth(10).SetApproxLevelSharp(10);
    const Bfr::RefinerSurfaceFactory<> factory(*refiner, options);
    const Bfr::Surface<double>::PointDescriptor point(3);
    std::vector<double> control(m.positions.begin(), m.positions.end()), patch_points;
    Bfr::Surface<double> surface;
    int face = -1;
    std::vector<double> errors;
    std::vector<std::pair<double, double>> covered;  // (error, area on screen)
    const float* uv = t.face_point_parameters();
    for (int tri = 0; tri < t.num_triangles(); ++tri) {
        const int f = t.parent_triangles()[tri];
        if (f != face) {
            face = f;
            factory.InitVertexSurface(f, &surface);
            patch_points.resize(3 * std::size_t(surface.GetNumPatchPoints()));
            surface.PreparePatchPoints(control.data(), point, patch_points.data(), point);
        }
        double flat[3] = {0, 0, 0}, at[2] = {0, 0};
        for (int c = 0; c < 3; ++c) {
            const std::int32_t fp = t.corner_face_points()[3 * tri + c], v = t.triangles()[3 * tri + c];
            at[0] += uv[2 * fp] / 3.0, at[1] += uv[2 * fp + 1] / 3.0;
            for (int k = 0; k < 3; ++k) flat[k] += points[3 * std::size_t(v) + k] / 3.0;
        }
        double limit[3], a[2], b[2];
        surface.Evaluate(at, patch_points.data(), point, limit);
        if (!to_pixels(scene.camera, flat, a) || !to_pixels(scene.camera, limit, b)) continue;
        if (a[0] < 0 || a[0] > scene.camera.viewport_width || a[1] < 0 || a[1] > scene.camera.viewport_height) continue;
        errors.push_back(std::hypot(a[0] - b[0], a[1] - b[1]));
        double corner[3][2], area = 0.0;
        bool seen = true;
        for (int c = 0; c < 3; ++c) {
            const std::size_t v = std::size_t(t.triangles()[3 * tri + c]);
            const double p[3] = {points[3 * v], points[3 * v + 1], points[3 * v + 2]};
            seen = seen && to_pixels(scene.camera, p, corner[c]);
        }
        if (seen)
            area = 0.5 * std::fabs((corner[1][0] - corner[0][0]) * (corner[2][1] - corner[0][1]) -
                                   (corner[2][0] - corner[0][0]) * (corner[1][1] - corner[0][1]));
        covered.push_back({errors.back(), area});
    }
    if (errors.empty()) return {0.0, 0.0, 0.0};
    std::sort(errors.begin(), errors.end());
    std::sort(covered.begin(), covered.end());
    double total = 0.0, running = 0.0, picture_p99 = covered.back().first;
    for (const auto& [error, area] : covered) total += area;
    for (const auto& [error, area] : covered)
        if ((running += area) >= 0.99 * total) {
            picture_p99 = error;
            break;
        }
    return {errors[std::size_t(0.99 * double(errors.size() - 1))], picture_p99, errors.back()};
}

}  // namespace

int measure_screen_error() {
    const Scene scene = screen_scene();
    loopsub::Options options;
    options.rules = loopsub::Rules::OpenSubdiv;
    std::printf("scene: %d triangles (ground of 24 x 24 quads 240 units wide, sphere of 320), camera 1920 x 1080\n",
                scene.mesh.num_triangles());
    std::printf("%-34s %12s %14s %14s %14s\n", "rates", "triangles", "p99 (pixels)", "picture p99", "max (pixels)");
    struct Row {
        int triangles;
        ScreenError error;
    };
    std::vector<Row> uniform;
    for (int level = 0; level <= 6; ++level) {
        loopsub::TessellationRates rates;
        rates.uniform_rate = 1 << level;
        const loopsub::Tessellation t(scene.mesh.view(), options, rates);
        uniform.push_back({t.num_triangles(), screen_error(scene, t)});
        std::printf("%-34s %12d %14.3f %14.3f %14.3f\n", ("uniform " + std::to_string(1 << level)).c_str(),
                    uniform.back().triangles, uniform.back().error.p99, uniform.back().error.picture_p99,
                    uniform.back().error.max);
    }
    for (const auto measure : {loopsub::DicingMeasure::Length, loopsub::DicingMeasure::Deviation}) {
        const bool length = measure == loopsub::DicingMeasure::Length;
        for (float pixels :
             length ? std::vector<float>{1, 2, 4, 8, 16, 32} : std::vector<float>{0.004f, 0.016f, 0.06f, 0.25f, 1.0f}) {
            const loopsub::ScreenRates rates = loopsub::screen_space_rates(
                scene.mesh.view(), scene.mesh.positions.data(), scene.camera, pixels, 64, measure);
            const loopsub::Tessellation t(scene.mesh.view(), options, rates.view());
            const ScreenError error = screen_error(scene, t);
            char name[64];
            std::snprintf(name, sizeof name, "camera, %s %g px", length ? "length" : "deviation", double(pixels));
            std::printf("%-34s %12d %14.3f %14.3f %14.3f\n", name, t.num_triangles(), error.p99, error.picture_p99,
                        error.max);
            // Against the uniform rows: the first power of two as good, and a uniform rate between the two around
            // (log triangles linear in log error: at rate r, triangles grow as r^2 and the error falls as 1 / r^2).
            for (const bool picture : {false, true}) {
                auto of = [picture](const ScreenError& e) { return picture ? e.picture_p99 : e.p99; };
                const auto as_good = std::find_if(uniform.begin(), uniform.end(),
                                                  [&](const Row& row) { return of(row.error) <= of(error); });
                std::printf("%36s by the %s: ", "", picture ? "picture's p99  " : "triangles' p99");
                if (as_good == uniform.end() || as_good == uniform.begin()) {
                    std::printf("no uniform rate from 2 to 64 as good\n");
                    continue;
                }
                const Row &finer = *as_good, &coarser = *(as_good - 1);
                const double slope = std::log(double(finer.triangles) / coarser.triangles) /
                                     std::log(of(finer.error) / of(coarser.error));
                const double same = coarser.triangles * std::pow(of(error) / of(coarser.error), slope);
                std::printf("uniform %d as good, %.1fx the triangles; a uniform rate between, %.1fx\n",
                            1 << int(as_good - uniform.begin()), double(as_good->triangles) / t.num_triangles(),
                            same / t.num_triangles());
            }
        }
    }
    std::printf("(issue 25's target: the first uniform rate as good has >= 5x the triangles)\n");
    return 0;
}

}  // namespace bench
