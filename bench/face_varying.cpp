// Face-varying rows, the meshes' UV layer: OpenSubdiv's InterpolateFaceVarying and its full pipeline with the
// layer against loopsub's evaluate_face_varying and plans with the layer.
#include "bench.h"

namespace bench {

using namespace OpenSubdiv;

void osd_face_varying(benchmark::State& state, const Mesh* m) {
    const std::unique_ptr<Far::TopologyRefiner> refiner = osd_refiner(view(*m, true));
    const std::unique_ptr<UV[]> all(new UV[refiner->GetNumFVarValuesTotal(0)]);
    for (auto _ : state) benchmark::DoNotOptimize(osd_interpolate_uvs(*refiner, *m, all.get()));
    set_rate(state, refiner->GetLevel(kLevels).GetNumFVarValues(0));
}

// The full pipeline with a UV layer: topology with its face-varying channel, then vertices and UVs.
void osd_far_full_uvs(benchmark::State& state, const Mesh* m) {
    int vertices = 0;
    for (auto _ : state) {
        const std::unique_ptr<Far::TopologyRefiner> refiner = osd_refiner(view(*m, true));
        const std::unique_ptr<Vertex[]> all(new Vertex[refiner->GetNumVerticesTotal()]);
        benchmark::DoNotOptimize(osd_interpolate(*refiner, *m, all.get()));
        const std::unique_ptr<UV[]> uvs(new UV[refiner->GetNumFVarValuesTotal(0)]);
        benchmark::DoNotOptimize(osd_interpolate_uvs(*refiner, *m, uvs.get()));
        vertices = output_vertices(*refiner);
    }
    set_rate(state, vertices);
}

void ours_face_varying(benchmark::State& state, const Mesh* m, int threads) {
    loopsub::Plan plan(view(*m, true), options(loopsub::Kernel::Auto, threads));
    std::vector<float> out(std::size_t(plan.num_output_face_varying_values(0)) * 2);
    for (auto _ : state) {
        plan.evaluate_face_varying(0, loopsub::interleaved(m->uvs.data(), 2), loopsub::interleaved(out.data(), 2));
        benchmark::DoNotOptimize(out.data());
    }
    set_rate(state, plan.num_output_face_varying_values(0));
}

void ours_full_uvs(benchmark::State& state, const Mesh* m, int threads) {
    int vertices = 0;
    for (auto _ : state) {
        loopsub::Plan plan(view(*m, true), options(loopsub::Kernel::Auto, threads));
        vertices = plan.num_output_vertices();
        const std::unique_ptr<float[]> out(new float[std::size_t(vertices) * 3]);
        plan.evaluate(loopsub::interleaved(m->positions.data(), 3), loopsub::interleaved(out.get(), 3));
        const std::unique_ptr<float[]> uvs(new float[std::size_t(plan.num_output_face_varying_values(0)) * 2]);
        plan.evaluate_face_varying(0, loopsub::interleaved(m->uvs.data(), 2), loopsub::interleaved(uvs.get(), 2));
        benchmark::DoNotOptimize(uvs.get());
    }
    set_rate(state, vertices);
}

}  // namespace bench
