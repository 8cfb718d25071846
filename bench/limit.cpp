// Limit surface rows: OpenSubdiv's PrimvarRefiner::Limit against loopsub's limit pass, its normals per corner and
// compact, its plans, and vertex data wider than positions.
#include <opensubdiv/far/primvarRefiner.h>

#include "bench.h"

namespace bench {

using namespace OpenSubdiv;

namespace {

loopsub::Options limit_options(int threads) {
    loopsub::Options o = options(loopsub::Kernel::Auto, threads);
    o.limit_surface = true;
    return o;
}

}  // namespace

void osd_limit(benchmark::State& state, const Mesh* m) {
    const std::unique_ptr<Far::TopologyRefiner> refiner = osd_refiner(view(*m), true);
    const std::unique_ptr<Vertex[]> all(new Vertex[refiner->GetNumVerticesTotal()]);
    const int count = output_vertices(*refiner);
    std::vector<Vertex> limit(count), tangent1(count), tangent2(count);
    const Far::PrimvarRefiner primvar(*refiner);
    for (auto _ : state) {
        const Vertex* last = osd_interpolate(*refiner, *m, all.get());
        primvar.Limit(last, limit, tangent1, tangent2);
        benchmark::DoNotOptimize(limit.data());
    }
    set_rate(state, count);
}

// The limit surface and its normals: per corner, or in compact form (one per vertex and side, Plan::LimitNormals):
// what the add-on reads.
void ours_limit(benchmark::State& state, const Mesh* m, int threads, bool compact) {
    loopsub::Plan plan(view(*m), limit_options(threads));
    std::vector<float> out(std::size_t(plan.num_output_vertices()) * 3),
        normals(compact ? std::size_t(plan.num_limit_normals()) * 3 : std::size_t(plan.num_output_triangles()) * 9);
    for (auto _ : state) {
        if (compact)
            plan.evaluate(loopsub::interleaved(m->positions.data(), 3), loopsub::interleaved(out.data(), 3),
                          loopsub::Plan::LimitNormals{normals.data()});
        else
            plan.evaluate(loopsub::interleaved(m->positions.data(), 3), loopsub::interleaved(out.data(), 3),
                          normals.data());
        benchmark::DoNotOptimize(normals.data());
    }
    set_rate(state, plan.num_output_vertices());
}

void ours_topology_limit(benchmark::State& state, const Mesh* m, int threads) {
    const loopsub::Options o = limit_options(threads);
    int vertices = 0;
    for (auto _ : state) {
        loopsub::Plan plan(view(*m), o);
        vertices = plan.num_output_vertices();
        benchmark::DoNotOptimize(plan.output_triangles());
    }
    set_rate(state, vertices);
}

// Vertex data wider than positions (point attributes, vertex-group weights): `channels` floats per vertex, the first
// three the positions, the rest their sums, on the limit surface as the add-on refines them.
void ours_limit_channels(benchmark::State& state, const Mesh* m, int channels) {
    loopsub::Plan plan(view(*m), limit_options(1));
    std::vector<float> in(std::size_t(m->num_vertices()) * std::size_t(channels));
    for (int v = 0; v < m->num_vertices(); ++v)
        for (int c = 0; c < channels; ++c) {
            const float* p = &m->positions[3 * std::size_t(v)];
            in[std::size_t(v) * std::size_t(channels) + std::size_t(c)] = c < 3 ? p[c] : p[0] + p[1] + p[2];
        }
    std::vector<float> out(std::size_t(plan.num_output_vertices()) * std::size_t(channels));
    for (auto _ : state) {
        plan.evaluate(loopsub::interleaved(in.data(), channels), loopsub::interleaved(out.data(), channels));
        benchmark::DoNotOptimize(out.data());
    }
    set_rate(state, plan.num_output_vertices());
}

}  // namespace bench
