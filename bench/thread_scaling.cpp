// --thread-scaling: two threads against one, in pairs close in time.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <utility>

#include "bench.h"

namespace bench {

// Two threads against one, measured in pairs close in time: this machine's speed drifts over seconds (a shared host),
// more than Google Benchmark's interleaved repetitions (each half a second or more) can even out for a ratio. Each
// round times `batch` plans, plans + evaluations, and evaluations with one thread and with two, back to back (the
// order swapped every round), and takes the ratio of the two medians; the median of the rounds' ratios is printed,
// with the spread of the middle half and the medians' times.
int measure_thread_scaling(int rounds, const std::string& only) {
    constexpr int batch = 15;
    std::printf(
        "two threads against one, %d rounds of %d runs each side, pairs measured back to back (AVX2 or the "
        "best kernel, tables Auto)\n",
        rounds, batch);
    std::printf("%-10s %-9s %24s %10s %10s %16s\n", "mesh", "what", "ratio median (middle half)", "1 thread",
                "2 threads", "fastest runs");
    auto median = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v[v.size() / 2];
    };
    for (const Mesh& m : meshes()) {
        // "+uv": with the mesh's UV layer; "uv frame": evaluate_face_varying of that layer; "+limit": with the limit
        // surface; "limit frame": evaluate with the compact limit normals.
        for (const char* what :
             {"plan", "full", "evaluate", "plan+uv", "full+uv", "uv frame", "plan+limit", "limit frame"}) {
            const std::string kind = what;
            if (kind.find(only) == std::string::npos) continue;
            const bool uvs = kind.find("uv") != std::string::npos;
            const bool limit = kind.find("limit") != std::string::npos;
            const bool frame = kind == "evaluate" || kind == "uv frame" || kind == "limit frame";
            auto time_batch = [&](int threads) {
                loopsub::Options o = options(loopsub::Kernel::Auto, threads);
                o.limit_surface = limit;
                std::unique_ptr<loopsub::Plan> kept;
                std::vector<float> out, uv_out, normals;
                if (frame) {
                    kept = std::make_unique<loopsub::Plan>(view(m, uvs), o);
                    out.resize(std::size_t(kept->num_output_vertices()) * 3);
                    if (uvs) uv_out.resize(std::size_t(kept->num_output_face_varying_values(0)) * 2);
                    if (limit) normals.resize(std::size_t(kept->num_limit_normals()) * 3);
                }
                std::vector<double> ms;
                ms.reserve(batch);
                for (int i = 0; i < batch; ++i) {
                    const auto start = std::chrono::steady_clock::now();
                    if (kind == "evaluate") {
                        kept->evaluate(loopsub::interleaved(m.positions.data(), 3),
                                       loopsub::interleaved(out.data(), 3));
                    } else if (kind == "limit frame") {
                        kept->evaluate(loopsub::interleaved(m.positions.data(), 3), loopsub::interleaved(out.data(), 3),
                                       loopsub::Plan::LimitNormals{normals.data()});
                        benchmark::DoNotOptimize(normals.data());
                    } else if (kind == "uv frame") {
                        kept->evaluate_face_varying(0, loopsub::interleaved(m.uvs.data(), 2),
                                                    loopsub::interleaved(uv_out.data(), 2));
                        benchmark::DoNotOptimize(uv_out.data());
                    } else {
                        loopsub::Plan plan(view(m, uvs), o);
                        if (kind == "full" || kind == "full+uv") {
                            const std::unique_ptr<float[]> result(
                                new float[std::size_t(plan.num_output_vertices()) * 3]);
                            plan.evaluate(loopsub::interleaved(m.positions.data(), 3),
                                          loopsub::interleaved(result.get(), 3));
                            benchmark::DoNotOptimize(result.get());
                        }
                        if (kind == "full+uv") {
                            const std::unique_ptr<float[]> result(
                                new float[std::size_t(plan.num_output_face_varying_values(0)) * 2]);
                            plan.evaluate_face_varying(0, loopsub::interleaved(m.uvs.data(), 2),
                                                       loopsub::interleaved(result.get(), 2));
                            benchmark::DoNotOptimize(result.get());
                        }
                        benchmark::DoNotOptimize(plan.output_triangles());
                    }
                    ms.push_back(
                        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
                }
                return std::pair<double, double>(median(ms), *std::min_element(ms.begin(), ms.end()));
            };
            std::vector<double> ratios, one, two;
            double fastest_one = 1e30, fastest_two = 1e30;  // what each does when the machine leaves it both cores
            for (int round = 0; round < rounds; ++round) {
                const auto first = time_batch(round % 2 ? 2 : 1), second = time_batch(round % 2 ? 1 : 2);
                const auto& with_one = round % 2 ? second : first;
                const auto& with_two = round % 2 ? first : second;
                one.push_back(with_one.first);
                two.push_back(with_two.first);
                ratios.push_back(one.back() / two.back());
                fastest_one = std::min(fastest_one, with_one.second);
                fastest_two = std::min(fastest_two, with_two.second);
            }
            std::vector<double> sorted = ratios;
            std::sort(sorted.begin(), sorted.end());
            std::printf("%-10s %-9s %9.2fx (%.2f-%.2fx) %7.2f ms %7.2f ms %6.2fx (%.2f ms)\n", m.name.c_str(), what,
                        median(ratios), sorted[sorted.size() / 4], sorted[sorted.size() * 3 / 4], median(one),
                        median(two), fastest_one / fastest_two, fastest_two);
        }
    }
    return 0;
}

}  // namespace bench
