// What the benchmark's files share (loopsub_bench.cpp describes the rows): the meshes, both libraries set up the same
// way (the rules of Rules::OpenSubdiv, boundary edges only, uniform creasing, to level 4), the rows by topic, their
// registration and the speedup table, and the measurements run instead of the rows.
#pragma once

#include <benchmark/benchmark.h>

#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/topologyRefiner.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "loopsub/loopsub.h"
#include "support/meshes.h"

namespace bench {

constexpr int kLevels = 4;

// ---- Meshes (meshes.cpp) -----------------------------------------------------------------------------------------

// A mesh of the tests' generators (support/meshes.h), named as its rows are, with a UV layer with a seam.
using Mesh = loopsub::testing::TestMesh;

// The two meshes of the rows: "icosphere" and "creased".
const std::vector<Mesh>& meshes();

// ---- Both libraries set up (adapters.cpp) ------------------------------------------------------------------------

// The mesh as loopsub and OpenSubdiv read it; the UV layer only where face-varying data is timed: it costs topology
// work on both sides.
inline loopsub::MeshView view(const Mesh& m, bool with_uvs = false) { return with_uvs ? m.view_with_uvs() : m.view(); }

// loopsub's options of the rows; OpenSubdiv's are the same (support/osd_adapter.h).
loopsub::Options options(loopsub::Kernel kernel, int threads, loopsub::LevelTables tables = loopsub::LevelTables::Auto);

struct Vertex {  // PrimvarRefiner's interface
    float p[3];
    void Clear(void* = nullptr) { p[0] = p[1] = p[2] = 0.0f; }
    void AddWithWeight(const Vertex& src, float weight) {
        p[0] += weight * src.p[0];
        p[1] += weight * src.p[1];
        p[2] += weight * src.p[2];
    }
};

struct UV {  // PrimvarRefiner's interface, two floats
    float p[2];
    void Clear(void* = nullptr) { p[0] = p[1] = 0.0f; }
    void AddWithWeight(const UV& src, float weight) {
        p[0] += weight * src.p[0];
        p[1] += weight * src.p[1];
    }
};

// OpenSubdiv's refiner of the mesh with the rows' options, refined uniformly to `levels`; full_last_level: what Limit
// needs.
std::unique_ptr<OpenSubdiv::Far::TopologyRefiner> osd_refiner(const loopsub::MeshView& mesh,
                                                              bool full_last_level = false, int levels = kLevels);
// All levels into one buffer, level after level (OpenSubdiv's tutorial layout); returns the last level.
const Vertex* osd_interpolate(const OpenSubdiv::Far::TopologyRefiner& refiner, const Mesh& m, Vertex* all,
                              int levels = kLevels);
// The UV layer's values of all levels into one buffer, as osd_interpolate the vertices'; returns the last level's.
const UV* osd_interpolate_uvs(const OpenSubdiv::Far::TopologyRefiner& refiner, const Mesh& m, UV* all);
int output_vertices(const OpenSubdiv::Far::TopologyRefiner& refiner);
// The stencils of the last level, from the control vertices straight.
std::unique_ptr<const OpenSubdiv::Far::StencilTable> osd_stencils(const OpenSubdiv::Far::TopologyRefiner& refiner);

// The rows' counter: output vertices per second.
void set_rate(benchmark::State& state, int vertices);

// ---- The rows, by topic ------------------------------------------------------------------------------------------

// Refinement (refinement.cpp): plans and refiners, frames and stencils.
void osd_far_full(benchmark::State& state, const Mesh* m);
void osd_primvar_refiner(benchmark::State& state, const Mesh* m);
void osd_stencil_table(benchmark::State& state, const Mesh* m);
void osd_cpu_evaluator(benchmark::State& state, const Mesh* m);
void osd_omp_evaluator(benchmark::State& state, const Mesh* m);
void ours_full(benchmark::State& state, const Mesh* m, loopsub::Kernel kernel, int threads,
               loopsub::LevelTables tables);
void ours_topology(benchmark::State& state, const Mesh* m, int threads, loopsub::LevelTables tables);
void ours_evaluate(benchmark::State& state, const Mesh* m, loopsub::Kernel kernel, int threads,
                   loopsub::LevelTables tables);

// The limit surface (limit.cpp).
void osd_limit(benchmark::State& state, const Mesh* m);
void ours_limit(benchmark::State& state, const Mesh* m, int threads, bool compact);
void ours_topology_limit(benchmark::State& state, const Mesh* m, int threads);
void ours_limit_channels(benchmark::State& state, const Mesh* m, int channels);

// Face-varying data, the UV layer (face_varying.cpp).
void osd_face_varying(benchmark::State& state, const Mesh* m);
void osd_far_full_uvs(benchmark::State& state, const Mesh* m);
void ours_face_varying(benchmark::State& state, const Mesh* m, int threads);
void ours_full_uvs(benchmark::State& state, const Mesh* m, int threads);

// Tessellation of the limit surface (tessellation.cpp).
void osd_bfr_tessellate(benchmark::State& state, const Mesh* m, int rate);
void ours_tessellate(benchmark::State& state, const Mesh* m, int rate, int threads);
void ours_tessellation(benchmark::State& state, const Mesh* m, int rate, int threads);

// ---- Registration and the speedup table (rows.cpp) ---------------------------------------------------------------

// 16: the points of level 4; 12: a rate between levels, where the points lie inside the level's triangles.
constexpr int kTessellationRates[] = {16, 12};

constexpr loopsub::Kernel kKernels[] = {loopsub::Kernel::Scalar, loopsub::Kernel::SSE41, loopsub::Kernel::AVX2};

std::string ours_name(const char* what, const Mesh& m, loopsub::Kernel kernel, int threads);

void register_all();

// Keeps each benchmark's time (ms): the median aggregate when there are repetitions, else the single run.
// Console output as usual (colours only on a terminal); --benchmark_out=FILE writes JSON/CSV alongside.
class RecordingReporter : public benchmark::ConsoleReporter {
public:
    RecordingReporter();
    void ReportRuns(const std::vector<Run>& runs) override;
    // Time of a benchmark, or a negative number when it did not run (filtered out).
    double ms(const std::string& name) const;

private:
    std::map<std::string, double> median_, single_;
};

void print_speedups(const RecordingReporter& r);

// ---- Measurements instead of the rows ----------------------------------------------------------------------------

int measure_memory(int levels);                                   // --memory (memory.cpp)
int measure_thread_scaling(int rounds, const std::string& only);  // --thread-scaling (thread_scaling.cpp)
int measure_screen_error();                                       // --screen-error (screen_error.cpp)

}  // namespace bench
