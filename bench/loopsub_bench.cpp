// loopsub against OpenSubdiv, in one run, on the same meshes and the same rules (Rules::OpenSubdiv, boundary edges
// only, uniform creasing), to level 4:
//   icosphere  - an icosphere of 5,120 triangles (2,562 vertices), smooth everywhere;
//   creased    - the same icosphere with an infinitely sharp crease loop, a semi-sharp loop (sharpness 2.5) and
//                four corners (two infinitely sharp, two of sharpness 1.5).
// Output: 655,362 vertices and 1,310,720 triangles each. Positions are n x 3 interleaved floats on both sides.
//
// OpenSubdiv:
//   opensubdiv_far_full           TopologyRefinerFactory + RefineUniform(4) + PrimvarRefiner::Interpolate, levels 1-4
//   opensubdiv_primvar_refiner    PrimvarRefiner::Interpolate, levels 1-4 (per frame; refiner built once)
//   opensubdiv_stencil_table      StencilTableFactory::Create from the refined refiner (last level only, offsets)
//   opensubdiv_cpu_evaluator      Osd::CpuEvaluator::EvalStencils over that table (per frame)
//   opensubdiv_omp_evaluator      Osd::OmpEvaluator::EvalStencils with 2 OpenMP threads (per frame)
//   opensubdiv_limit              Interpolate, levels 1-4, then Limit with both tangents (per frame)
//   opensubdiv_face_varying       InterpolateFaceVarying of a UV layer with a seam, levels 1-4, linear at corners
//                                 only (FVAR_LINEAR_CORNERS_ONLY; per frame)
//   opensubdiv_far_full_uvs       the full pipeline with that layer: TopologyRefinerFactory with its channel +
//                                 RefineUniform(4) + Interpolate + InterpolateFaceVarying, levels 1-4
//   opensubdiv_bfr_tessellate     Bfr: per face, PreparePatchPoints and Surface::Evaluate (position and both
//                                 derivatives) at every point of its uniform Bfr::Tessellation of rate 16 or 12 (per
//                                 frame; the faces' surfaces made once and kept, the tessellation's coordinates too)
// loopsub (kernel: scalar, sse4.1, avx2; threads: Options::threads):
//   loopsub_full                  Plan construction + evaluate
//   loopsub_topology              Plan construction
//   loopsub_evaluate              Plan::evaluate (per frame)
//   loopsub_*_derived             the same with Options::level_tables = Derived (best kernel only); the rows above
//                                 use Auto, which stores the tables at this size
//   loopsub_limit                 Plan::evaluate with the limit surface and its normals per corner (per frame)
//   loopsub_limit_compact         the same with the normals in compact form (Plan::LimitNormals)
//   loopsub_topology_limit        Plan construction with the limit surface
//   loopsub_face_varying          Plan::evaluate_face_varying of the same layer, corners only (per frame)
//   loopsub_full_uvs              Plan construction with that layer + evaluate + evaluate_face_varying (what the
//                                 add-on and the CLI do with a mesh that has UVs)
//   loopsub_tessellate            Tessellation::evaluate at the same rate: its points and normals (per frame)
//   loopsub_tessellation          Tessellation construction at that rate
// Each reports output vertices per second. At the end, the speedups (OpenSubdiv time / loopsub time, medians when
// --benchmark_repetitions > 1). Usage and numbers: docs/benchmark.md. The code: this file runs the rows or one of the
// measurements below; bench.h lists the files, one a topic; the meshes and the OpenSubdiv adapter are the tests'
// (tests/support/).
//
// --memory [LEVELS] instead measures peak resident memory, each side in a process of its own: the icosphere to
// level 6 (21M triangles) by default, Plan + evaluate (tables Auto, then Stored) against TopologyRefiner +
// PrimvarRefiner, beside the bytes of the output arrays (positions and triangles).
//
// --thread-scaling [ROUNDS] instead times one thread against two in pairs close in time (40 rounds by default): the
// ratios issue 8 sets targets for, less at the mercy of this shared machine's drifts than rows of separate benchmarks;
// and the ratio of the fastest run of each side, what two threads give when the machine leaves them both cores. The
// rows with "+uv" plan the mesh's UV layer too, "uv frame" evaluates it; "plan+limit" plans the limit surface,
// "limit frame" evaluates it with its compact normals; --thread-scaling ROUNDS WHAT runs only the rows whose name
// contains WHAT ("uv": the three with the layer, "limit": the two with the limit surface).
//
// --screen-error instead measures what camera-driven rates buy (issue 25): a ground of gentle hills 240 units wide
// (24 x 24 quads) and a sphere of radius 1.5 standing on it, seen from a low camera (1920 x 1080, 50 degrees); the
// tessellation at the camera's rates (screen_space_rates, by length 1 to 32 pixels per segment and by deviation 0.004
// to 1 pixel, at most 64) and at uniform rates 2^L, each with its triangle count and its screen-space error: the
// distance, in pixels, between a triangle's centroid and the limit surface at the centroid's parameters
// (Bfr::Surface::Evaluate, the reference), over the triangles in view, at the 99th percentile and at most; then, per
// dicing rate, the first uniform rate whose error (99th percentile) is no larger.
//
// --malloc-keeps-memory (first argument) makes glibc's malloc keep freed memory for reuse (mmap threshold 32 MiB,
// no trimming): OpenSubdiv then reuses its arrays from one run to the next as loopsub's plans reuse theirs (its
// block pool), instead of paying the kernel for fresh pages each time (docs/benchmark.md).
#include <benchmark/benchmark.h>

#include <opensubdiv/osd/ompEvaluator.h>

#include <malloc.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "bench.h"

int main(int argc, char** argv) {
    if (argc >= 2 && std::string(argv[1]) == "--malloc-keeps-memory") {
        mallopt(M_MMAP_THRESHOLD, 32 << 20);
        mallopt(M_TRIM_THRESHOLD, 1 << 30);
        std::printf("malloc keeps freed memory (mmap threshold 32 MiB, trim threshold 1 GiB)\n");
        for (int i = 1; i + 1 < argc; ++i) argv[i] = argv[i + 1];
        --argc;
    }
    if (argc >= 2 && std::string(argv[1]) == "--memory")
        return bench::measure_memory(argc >= 3 ? std::atoi(argv[2]) : 6);
    if (argc >= 2 && std::string(argv[1]) == "--screen-error") return bench::measure_screen_error();
    if (argc >= 2 && std::string(argv[1]) == "--thread-scaling")
        return bench::measure_thread_scaling(argc >= 3 ? std::atoi(argv[2]) : 40, argc >= 4 ? argv[3] : "");
    OpenSubdiv::Osd::OmpEvaluator::SetNumThreads(2);
    bench::register_all();
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    bench::RecordingReporter reporter;
    benchmark::RunSpecifiedBenchmarks(&reporter);
    bench::print_speedups(reporter);
    benchmark::Shutdown();
    return 0;
}
