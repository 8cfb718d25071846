// loopsub_bfr_job IN.obj RATE: OpenSubdiv's Bfr tessellating the limit surface as a one-shot job, the counterpart of
// `loopsub IN.obj OUT.obj --tessellate RATE` for timing whole processes (scripts/bench_fresh.py): the OBJ's triangles
// (v and f lines, the first three corners of each face) read, then Bfr with its default options: the refiner's base
// level (the tests' adapter, support/osd_adapter.h: the rules of Rules::OpenSubdiv, boundary edges only), the factory,
// per face its surface, its patch points and Surface::Evaluate (position and both derivatives, whence a unit normal) at
// every point of its uniform Bfr::Tessellation, into one array of points and normals per face point (a tessellation's
// result, nothing written out). Prints "factory_ms=... evaluate_ms=... points=..." (evaluate_ms: the surfaces, their
// patch points and the evaluation).
#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/bfr/tessellation.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/meshes.h"
#include "support/osd_adapter.h"

using namespace OpenSubdiv;

namespace {

loopsub::testing::TestMesh read_triangles(const char* path) {
    loopsub::testing::TestMesh mesh;
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream words(line);
        std::string kind;
        words >> kind;
        if (kind == "v") {
            float x, y, z;
            words >> x >> y >> z;
            mesh.positions.insert(mesh.positions.end(), {x, y, z});
        } else if (kind == "f") {
            for (int k = 0; k < 3; ++k) {
                std::string corner;
                words >> corner;
                mesh.triangles.push_back(std::atoi(corner.c_str()) - 1);
            }
        }
    }
    return mesh;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: loopsub_bfr_job IN.obj RATE\n");
        return 2;
    }
    const loopsub::testing::TestMesh mesh = read_triangles(argv[1]);
    const int rate = std::atoi(argv[2]);
    using Clock = std::chrono::steady_clock;
    const auto started = Clock::now();
    loopsub::Options options;
    options.rules = loopsub::Rules::OpenSubdiv;
    const std::unique_ptr<Far::TopologyRefiner> refiner =
        loopsub::testing::osd_topology_refiner(mesh.view(), loopsub::testing::sdc_options(options));
    const Bfr::RefinerSurfaceFactory<> factory(*refiner);
    const auto made = Clock::now();
    std::vector<float> coords, patch_points, points, normals;
    const Bfr::Surface<float>::PointDescriptor point(3);
    Bfr::Surface<float> surface;
    for (int f = 0; f < mesh.num_triangles(); ++f) {
        if (!factory.InitVertexSurface(f, &surface)) continue;
        const Bfr::Tessellation tessellation(surface.GetParameterization(), rate);
        coords.resize(2 * std::size_t(tessellation.GetNumCoords()));
        tessellation.GetCoords(coords.data());
        patch_points.resize(3 * std::size_t(surface.GetNumPatchPoints()));
        surface.PreparePatchPoints(mesh.positions.data(), point, patch_points.data(), point);
        const std::size_t first = points.size();
        points.resize(first + 3 * std::size_t(tessellation.GetNumCoords()));
        normals.resize(points.size());
        for (int i = 0; i < tessellation.GetNumCoords(); ++i) {
            float* p = &points[first + 3 * std::size_t(i)];
            float du[3], dv[3];
            surface.Evaluate(&coords[2 * std::size_t(i)], patch_points.data(), point, p, du, dv);
            float* n = &normals[first + 3 * std::size_t(i)];
            n[0] = du[1] * dv[2] - du[2] * dv[1], n[1] = du[2] * dv[0] - du[0] * dv[2],
            n[2] = du[0] * dv[1] - du[1] * dv[0];
            const float length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            if (length > 0.0f) n[0] /= length, n[1] /= length, n[2] /= length;
        }
    }
    const auto evaluated = Clock::now();
    using ms = std::chrono::duration<double, std::milli>;
    std::printf("factory_ms=%.3f evaluate_ms=%.3f points=%zu\n", ms(made - started).count(),
                ms(evaluated - made).count(), points.size() / 3);
    return 0;
}
