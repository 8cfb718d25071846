// The rows' names and registration, in the order they run, and the speedup tables printed after them.
#include <unistd.h>

#include <cstdio>

#include "bench.h"

namespace bench {

std::string ours_name(const char* what, const Mesh& m, loopsub::Kernel kernel, int threads) {
    return std::string("loopsub_") + what + "/" + m.name + "/" + loopsub::kernel_name(kernel) +
           "/threads:" + std::to_string(threads);
}

void register_all() {
    auto add = [](const std::string& name, auto&& fn, auto... args) {
        benchmark::RegisterBenchmark(name.c_str(), fn, args...)->Unit(benchmark::kMillisecond)->UseRealTime();
    };
    for (const Mesh& m : meshes()) {
        add("opensubdiv_far_full/" + m.name, osd_far_full, &m);
        add("opensubdiv_primvar_refiner/" + m.name, osd_primvar_refiner, &m);
        add("opensubdiv_stencil_table/" + m.name, osd_stencil_table, &m);
        add("opensubdiv_cpu_evaluator/" + m.name, osd_cpu_evaluator, &m);
        add("opensubdiv_omp_evaluator/" + m.name + "/threads:2", osd_omp_evaluator, &m);
        add("opensubdiv_limit/" + m.name, osd_limit, &m);
        add("opensubdiv_face_varying/" + m.name, osd_face_varying, &m);
        add("opensubdiv_far_full_uvs/" + m.name, osd_far_full_uvs, &m);
        for (int rate : kTessellationRates) {
            const std::string suffix = m.name + "/rate:" + std::to_string(rate);
            add("opensubdiv_bfr_tessellate/" + suffix, osd_bfr_tessellate, &m, rate);
            add("loopsub_tessellate/" + suffix + "/threads:1", ours_tessellate, &m, rate, 1);
            add("loopsub_tessellate/" + suffix + "/threads:2", ours_tessellate, &m, rate, 2);
            add("loopsub_tessellation/" + suffix + "/threads:1", ours_tessellation, &m, rate, 1);
        }
        for (int channels : {7, 16})
            add("loopsub_limit_channels/" + m.name + "/channels:" + std::to_string(channels), ours_limit_channels, &m,
                channels);
        for (int threads : {1, 2}) {
            add("loopsub_limit/" + m.name + "/threads:" + std::to_string(threads), ours_limit, &m, threads, false);
            add("loopsub_limit_compact/" + m.name + "/threads:" + std::to_string(threads), ours_limit, &m, threads,
                true);
            add("loopsub_topology_limit/" + m.name + "/threads:" + std::to_string(threads), ours_topology_limit, &m,
                threads);
            add("loopsub_face_varying/" + m.name + "/threads:" + std::to_string(threads), ours_face_varying, &m,
                threads);
            add("loopsub_full_uvs/" + m.name + "/threads:" + std::to_string(threads), ours_full_uvs, &m, threads);
            const std::string suffix = m.name + "/threads:" + std::to_string(threads);
            add("loopsub_topology/" + suffix, ours_topology, &m, threads, loopsub::LevelTables::Auto);
            add("loopsub_topology_derived/" + suffix, ours_topology, &m, threads, loopsub::LevelTables::Derived);
            for (loopsub::Kernel kernel : kKernels) {
                add(ours_name("full", m, kernel, threads), ours_full, &m, kernel, threads, loopsub::LevelTables::Auto);
                add(ours_name("evaluate", m, kernel, threads), ours_evaluate, &m, kernel, threads,
                    loopsub::LevelTables::Auto);
            }
            const loopsub::Kernel best = loopsub::best_kernel();
            add(ours_name("full_derived", m, best, threads), ours_full, &m, best, threads,
                loopsub::LevelTables::Derived);
            add(ours_name("evaluate_derived", m, best, threads), ours_evaluate, &m, best, threads,
                loopsub::LevelTables::Derived);
        }
    }
}

RecordingReporter::RecordingReporter() : ConsoleReporter(isatty(fileno(stdout)) ? OO_ColorTabular : OO_Tabular) {}

void RecordingReporter::ReportRuns(const std::vector<Run>& runs) {
    for (const Run& run : runs) {
        const std::string& name = run.run_name.function_name;
        if (run.run_type == Run::RT_Aggregate && run.aggregate_name == "median")
            median_[name] = run.GetAdjustedRealTime();
        else if (run.run_type == Run::RT_Iteration) single_[name] = run.GetAdjustedRealTime();
    }
    ConsoleReporter::ReportRuns(runs);
}

double RecordingReporter::ms(const std::string& name) const {
    if (const auto found = median_.find(name); found != median_.end()) return found->second;
    if (const auto found = single_.find(name); found != single_.end()) return found->second;
    return -1.0;
}

void print_speedups(const RecordingReporter& r) {
    auto ratio = [](double theirs, double ours) {
        char text[32] = "-";
        if (theirs > 0 && ours > 0) std::snprintf(text, sizeof text, "%.1fx", theirs / ours);
        return std::string(text);
    };
    std::printf(
        "\nSpeedups, OpenSubdiv time / loopsub time (issue 8's targets, one thread: full >= 10x Far, evaluate >= 8x "
        "PrimvarRefiner):\n");
    std::printf("%-10s %-15s %-8s %16s %22s %21s\n", "mesh", "kernel", "threads", "full vs Far", "evaluate vs Primvar",
                "evaluate vs stencils");
    for (const Mesh& m : meshes()) {
        const double far = r.ms("opensubdiv_far_full/" + m.name),
                     primvar = r.ms("opensubdiv_primvar_refiner/" + m.name);
        for (int threads : {1, 2}) {
            // The stencil evaluator with the same thread count: CpuEvaluator for one, OmpEvaluator for two.
            const double stencils = r.ms(threads == 1 ? "opensubdiv_cpu_evaluator/" + m.name
                                                      : "opensubdiv_omp_evaluator/" + m.name + "/threads:2");
            for (const char* tables : {"", "_derived"}) {
                for (loopsub::Kernel kernel : kKernels) {
                    const double full = r.ms(ours_name((std::string("full") + tables).c_str(), m, kernel, threads));
                    const double evaluate =
                        r.ms(ours_name((std::string("evaluate") + tables).c_str(), m, kernel, threads));
                    if (full < 0 && evaluate < 0) continue;
                    const std::string label = std::string(loopsub::kernel_name(kernel)) + (*tables ? " derived" : "");
                    std::printf("%-10s %-15s %-8d %16s %22s %21s\n", m.name.c_str(), label.c_str(), threads,
                                ratio(far, full).c_str(), ratio(primvar, evaluate).c_str(),
                                ratio(stencils, evaluate).c_str());
                }
            }
        }
    }
    std::printf(
        "\nTwo threads against one, loopsub time with 1 / with 2 (issue 8's targets: full >= 1.6x, evaluate >= "
        "1.7x):\n");
    std::printf("%-10s %-15s %10s %10s %10s\n", "mesh", "kernel", "topology", "full", "evaluate");
    for (const Mesh& m : meshes()) {
        for (const char* tables : {"", "_derived"}) {
            for (loopsub::Kernel kernel : kKernels) {
                auto two_vs_one = [&](const std::string& what) {
                    return ratio(r.ms(ours_name((what + tables).c_str(), m, kernel, 1)),
                                 r.ms(ours_name((what + tables).c_str(), m, kernel, 2)));
                };
                const std::string topology =
                    ratio(r.ms("loopsub_topology" + std::string(tables) + "/" + m.name + "/threads:1"),
                          r.ms("loopsub_topology" + std::string(tables) + "/" + m.name + "/threads:2"));
                const std::string full = two_vs_one("full"), evaluate = two_vs_one("evaluate");
                if (full == "-" && evaluate == "-") continue;
                const std::string label = std::string(loopsub::kernel_name(kernel)) + (*tables ? " derived" : "");
                std::printf("%-10s %-15s %10s %10s %10s\n", m.name.c_str(), label.c_str(), topology.c_str(),
                            full.c_str(), evaluate.c_str());
            }
        }
    }
    std::printf(
        "\nLimit surface and face-varying (best kernel), OpenSubdiv time / loopsub time; per frame, and end to end "
        "with a UV layer:\n");
    std::printf("%-10s %-8s %34s %38s %38s\n", "mesh", "threads", "limit+normals vs Interpolate+Limit",
                "UVs vs InterpolateFaceVarying (ms)", "full with UVs vs Far with UVs (ms)");
    auto compared = [&](const std::string& theirs, const std::string& ours) {
        const double a = r.ms(theirs), b = r.ms(ours);
        char text[64] = "-";
        if (a > 0 && b > 0) std::snprintf(text, sizeof text, "%.1fx (%.1f vs %.1f ms)", a / b, b, a);
        return std::string(text);
    };
    for (const Mesh& m : meshes()) {
        for (int threads : {1, 2}) {
            const std::string suffix = m.name + "/threads:" + std::to_string(threads);
            const std::string limit = compared("opensubdiv_limit/" + m.name, "loopsub_limit/" + suffix);
            const std::string uvs = compared("opensubdiv_face_varying/" + m.name, "loopsub_face_varying/" + suffix);
            const std::string full = compared("opensubdiv_far_full_uvs/" + m.name, "loopsub_full_uvs/" + suffix);
            if (limit == "-" && uvs == "-" && full == "-") continue;
            std::printf("%-10s %-8d %34s %38s %38s\n", m.name.c_str(), threads, limit.c_str(), uvs.c_str(),
                        full.c_str());
        }
    }
    std::printf(
        "\nTessellation of the limit surface, Bfr time (one thread) / loopsub time (issue 25's target: >= 5x with "
        "one):\n");
    std::printf("%-10s %-6s %34s %34s %20s\n", "mesh", "rate", "one thread", "two threads", "tessellation (ms)");
    for (const Mesh& m : meshes())
        for (int rate : kTessellationRates) {
            const std::string suffix = m.name + "/rate:" + std::to_string(rate);
            const std::string one =
                compared("opensubdiv_bfr_tessellate/" + suffix, "loopsub_tessellate/" + suffix + "/threads:1");
            const std::string two =
                compared("opensubdiv_bfr_tessellate/" + suffix, "loopsub_tessellate/" + suffix + "/threads:2");
            const double build = r.ms("loopsub_tessellation/" + suffix + "/threads:1");
            if (one == "-" && two == "-" && build < 0) continue;
            std::printf("%-10s %-6d %34s %34s %20.1f\n", m.name.c_str(), rate, one.c_str(), two.c_str(), build);
        }
}

}  // namespace bench
