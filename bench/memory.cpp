// --memory: peak resident memory of loopsub and OpenSubdiv, each in a process of its own.
#include <opensubdiv/far/topologyRefiner.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <utility>

#include "bench.h"

namespace bench {

using namespace OpenSubdiv;

namespace {

long peak_rss_kib() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss;  // KiB on Linux
}

}  // namespace

int measure_memory(int levels) {
    const Mesh& m = meshes().front();
    // The child prints its own peak: read it back through a pipe.
    auto run = [&](const char* what, auto work) {
        int fds[2];
        if (pipe(fds) != 0) return -1L;
        std::fflush(stdout);
        const pid_t child = fork();
        if (child == 0) {
            close(fds[0]);
            const long before = peak_rss_kib();
            work();
            char line[64];
            const int length = std::snprintf(line, sizeof line, "%ld %ld", before, peak_rss_kib());
            if (write(fds[1], line, std::size_t(length)) != length) _exit(1);
            _exit(0);
        }
        close(fds[1]);
        char line[64] = {0};
        const ssize_t got = read(fds[0], line, sizeof line - 1);
        close(fds[0]);
        int status = 0;
        waitpid(child, &status, 0);
        long before = 0, peak = -1;
        if (got <= 0 || std::sscanf(line, "%ld %ld", &before, &peak) != 2) std::printf("%s: failed\n", what);
        return peak < 0 ? -1L : peak - before;
    };
    const std::size_t triangles = std::size_t(m.num_triangles()) << (2 * levels);
    auto ours = [&](loopsub::LevelTables tables) {
        return [&m, levels, tables] {
            loopsub::Options o = options(loopsub::Kernel::Auto, 1, tables);
            o.levels = levels;
            loopsub::Plan plan(view(m), o);
            std::vector<float> out(std::size_t(plan.num_output_vertices()) * 3);
            plan.evaluate(loopsub::interleaved(m.positions.data(), 3), loopsub::interleaved(out.data(), 3));
            benchmark::DoNotOptimize(out.data());
        };
    };
    const long auto_tables = run("loopsub", ours(loopsub::LevelTables::Auto));
    const long stored_tables = run("loopsub, tables stored", ours(loopsub::LevelTables::Stored));
    const long theirs = run("opensubdiv", [&] {
        const std::unique_ptr<Far::TopologyRefiner> refiner = osd_refiner(view(m), false, levels);
        std::vector<Vertex> all(refiner->GetNumVerticesTotal());
        benchmark::DoNotOptimize(osd_interpolate(*refiner, m, all.data(), levels));
    });
    // A closed mesh: each level adds one vertex per edge, three halves per triangle.
    std::size_t vertices = std::size_t(m.num_vertices());
    for (int l = 0; l < levels; ++l) vertices = vertices + (std::size_t(m.num_triangles()) << (2 * l)) * 3 / 2;
    const double output_mib = double(vertices * 12 + triangles * 12) / (1 << 20);
    std::printf(
        "peak resident memory, %s to level %d: %zu triangles, %zu vertices; output arrays (positions + "
        "triangles) %.1f MiB\n",
        m.name.c_str(), levels, triangles, vertices, output_mib);
    for (const auto& [name, kib] : {std::pair<const char*, long>{"loopsub (tables Auto)", auto_tables},
                                    {"loopsub (tables Stored)", stored_tables},
                                    {"opensubdiv", theirs}}) {
        if (kib < 0) continue;
        const double mib = double(kib) / 1024.0;
        std::printf(
            "  %-24s %8.1f MiB above the process's start = %.2fx the output arrays, %.1f bytes per output "
            "triangle\n",
            name, mib, mib / output_mib, double(kib) * 1024.0 / double(triangles));
    }
    return auto_tables < 0 || stored_tables < 0 || theirs < 0;
}

}  // namespace bench
