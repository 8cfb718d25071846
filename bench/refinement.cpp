// Refinement rows: OpenSubdiv's Far (refiner, PrimvarRefiner, stencil table and evaluators) against loopsub's plans
// and frames.
#include <opensubdiv/osd/cpuEvaluator.h>
#include <opensubdiv/osd/ompEvaluator.h>

#include "bench.h"

namespace bench {

using namespace OpenSubdiv;

namespace {

template <typename Evaluator>
void osd_evaluator(benchmark::State& state, const Mesh* m) {
    const std::unique_ptr<Far::TopologyRefiner> refiner = osd_refiner(view(*m));
    const std::unique_ptr<const Far::StencilTable> table = osd_stencils(*refiner);
    std::vector<float> out(std::size_t(table->GetNumStencils()) * 3);
    const Osd::BufferDescriptor desc(0, 3, 3);
    for (auto _ : state) {
        Evaluator::EvalStencils(m->positions.data(), desc, out.data(), desc, &table->GetSizes()[0],
                                &table->GetOffsets()[0], &table->GetControlIndices()[0], &table->GetWeights()[0], 0,
                                table->GetNumStencils());
        benchmark::DoNotOptimize(out.data());
    }
    set_rate(state, table->GetNumStencils());
}

}  // namespace

void osd_far_full(benchmark::State& state, const Mesh* m) {
    int vertices = 0;
    for (auto _ : state) {
        const std::unique_ptr<Far::TopologyRefiner> refiner = osd_refiner(view(*m));
        const std::unique_ptr<Vertex[]> all(new Vertex[refiner->GetNumVerticesTotal()]);
        benchmark::DoNotOptimize(osd_interpolate(*refiner, *m, all.get()));
        vertices = output_vertices(*refiner);
    }
    set_rate(state, vertices);
}

void osd_primvar_refiner(benchmark::State& state, const Mesh* m) {
    const std::unique_ptr<Far::TopologyRefiner> refiner = osd_refiner(view(*m));
    const std::unique_ptr<Vertex[]> all(new Vertex[refiner->GetNumVerticesTotal()]);
    for (auto _ : state) benchmark::DoNotOptimize(osd_interpolate(*refiner, *m, all.get()));
    set_rate(state, output_vertices(*refiner));
}

void osd_stencil_table(benchmark::State& state, const Mesh* m) {
    const std::unique_ptr<Far::TopologyRefiner> refiner = osd_refiner(view(*m));
    for (auto _ : state) benchmark::DoNotOptimize(osd_stencils(*refiner).get());
    set_rate(state, output_vertices(*refiner));
}

void osd_cpu_evaluator(benchmark::State& state, const Mesh* m) { osd_evaluator<Osd::CpuEvaluator>(state, m); }

void osd_omp_evaluator(benchmark::State& state, const Mesh* m) { osd_evaluator<Osd::OmpEvaluator>(state, m); }

void ours_full(benchmark::State& state, const Mesh* m, loopsub::Kernel kernel, int threads,
               loopsub::LevelTables tables) {
    int vertices = 0;
    for (auto _ : state) {
        loopsub::Plan plan(view(*m), options(kernel, threads, tables));
        vertices = plan.num_output_vertices();
        const std::unique_ptr<float[]> out(new float[std::size_t(vertices) * 3]);
        plan.evaluate(loopsub::interleaved(m->positions.data(), 3), loopsub::interleaved(out.get(), 3));
        benchmark::DoNotOptimize(out.get());
    }
    set_rate(state, vertices);
}

void ours_topology(benchmark::State& state, const Mesh* m, int threads, loopsub::LevelTables tables) {
    int vertices = 0;
    for (auto _ : state) {
        loopsub::Plan plan(view(*m), options(loopsub::Kernel::Auto, threads, tables));
        vertices = plan.num_output_vertices();
        benchmark::DoNotOptimize(plan.output_triangles());
    }
    set_rate(state, vertices);
}

void ours_evaluate(benchmark::State& state, const Mesh* m, loopsub::Kernel kernel, int threads,
                   loopsub::LevelTables tables) {
    loopsub::Plan plan(view(*m), options(kernel, threads, tables));
    std::vector<float> out(std::size_t(plan.num_output_vertices()) * 3);
    for (auto _ : state) {
        plan.evaluate(loopsub::interleaved(m->positions.data(), 3), loopsub::interleaved(out.data(), 3));
        benchmark::DoNotOptimize(out.data());
    }
    set_rate(state, plan.num_output_vertices());
}

}  // namespace bench
