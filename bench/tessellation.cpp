// Tessellation rows: Bfr's tessellation of the limit surface against loopsub's Tessellation, its frames and its
// construction.
#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/bfr/tessellation.h>

#include "bench.h"
#include "loopsub/tessellation.h"

namespace bench {

using namespace OpenSubdiv;

namespace {

loopsub::TessellationRates uniform_rate(int rate) {
    loopsub::TessellationRates rates;
    rates.uniform_rate = rate;
    return rates;
}

}  // namespace

// Bfr's own way to tessellate the limit surface: a surface per face (kept), its patch points per frame, and
// Surface::Evaluate with both derivatives at each point of the face's Bfr::Tessellation.
void osd_bfr_tessellate(benchmark::State& state, const Mesh* m, int rate) {
    const std::unique_ptr<Far::TopologyRefiner> refiner = osd_refiner(view(*m), false, 0);
    const Bfr::RefinerSurfaceFactory<> factory(*refiner);
    std::vector<Bfr::Surface<float>> surfaces(std::size_t(m->num_triangles()));
    for (int f = 0; f < m->num_triangles(); ++f) factory.InitVertexSurface(f, &surfaces[std::size_t(f)]);
    const Bfr::Tessellation tessellation(surfaces[0].GetParameterization(), rate);
    std::vector<float> coords(2 * std::size_t(tessellation.GetNumCoords()));
    tessellation.GetCoords(coords.data());
    const Bfr::Surface<float>::PointDescriptor point(3);
    std::vector<float> patch_points, out(9 * coords.size() / 2);
    long long points = 0;
    for (auto _ : state) {
        points = 0;
        for (const Bfr::Surface<float>& surface : surfaces) {
            patch_points.resize(3 * std::size_t(surface.GetNumPatchPoints()));
            surface.PreparePatchPoints(m->positions.data(), point, patch_points.data(), point);
            for (std::size_t i = 0; i < coords.size() / 2; ++i) {
                float* p = &out[9 * i];
                surface.Evaluate(&coords[2 * i], patch_points.data(), point, p, p + 3, p + 6);
            }
            points += tessellation.GetNumCoords();
        }
        benchmark::DoNotOptimize(out.data());
    }
    state.counters["points/s"] = benchmark::Counter(double(points), benchmark::Counter::kIsIterationInvariantRate);
}

void ours_tessellate(benchmark::State& state, const Mesh* m, int rate, int threads) {
    const loopsub::Tessellation tessellation(view(*m), options(loopsub::Kernel::Auto, threads), uniform_rate(rate));
    std::vector<float> points(3 * std::size_t(tessellation.num_points())),
        normals(3 * std::size_t(tessellation.num_face_points()));
    for (auto _ : state) {
        tessellation.evaluate(m->positions.data(), points.data(), normals.data());
        benchmark::DoNotOptimize(normals.data());
    }
    state.counters["points/s"] =
        benchmark::Counter(double(tessellation.num_face_points()), benchmark::Counter::kIsIterationInvariantRate);
}

void ours_tessellation(benchmark::State& state, const Mesh* m, int rate, int threads) {
    for (auto _ : state) {
        const loopsub::Tessellation tessellation(view(*m), options(loopsub::Kernel::Auto, threads), uniform_rate(rate));
        benchmark::DoNotOptimize(tessellation.triangles());
    }
}

}  // namespace bench
