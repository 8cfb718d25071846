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
// --benchmark_repetitions > 1). Usage and numbers: docs/benchmark.md.
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

#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/bfr/tessellation.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <opensubdiv/osd/cpuEvaluator.h>
#include <opensubdiv/osd/ompEvaluator.h>

#include <malloc.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "loopsub/loopsub.h"
#include "loopsub/tessellation.h"

namespace {

using namespace OpenSubdiv;

constexpr int kLevels = 4;

// ---- Meshes ------------------------------------------------------------------------------------------------------

struct Mesh {
    std::string name;
    std::vector<float> positions;   // 3 per vertex
    std::vector<int> triangles;     // 3 per triangle
    std::vector<int> crease_edges;  // pairs
    std::vector<float> crease_sharpness;
    std::vector<int> corners;
    std::vector<float> corner_sharpness;
    // A UV layer with a seam: the triangles with x > 0 take their own copies of their values.
    std::vector<float> uvs;       // 2 per value
    std::vector<int> uv_indices;  // 3 per triangle

    int num_vertices() const { return int(positions.size() / 3); }
    int num_triangles() const { return int(triangles.size() / 3); }
};

// An icosahedron split `splits` times (each edge halved, points pushed onto the unit sphere).
Mesh icosphere(int splits) {
    const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
    Mesh m;
    m.positions = {-1, t,  0,  1, t, 0,  -1, -t, 0,  1, -t, 0, 0,  -1, t,  0,  1, t,
                   0,  -1, -t, 0, 1, -t, t,  0,  -1, t, 0,  1, -t, 0,  -1, -t, 0, 1};
    m.triangles = {0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4,  11, 10, 2,  10, 7, 6, 7, 1, 8,
                   3, 9,  4, 3, 4, 2, 3, 2, 6, 3, 6, 8,  3, 8,  9,  4, 9, 5, 2, 4,  11, 6,  2,  10, 8,  6, 7, 9, 8, 1};
    for (int s = 0; s < splits; ++s) {
        std::map<std::pair<int, int>, int> midpoint;
        auto split = [&](int a, int b) {
            const auto key = std::minmax(a, b);
            const auto found = midpoint.find(key);
            if (found != midpoint.end()) return found->second;
            const int v = m.num_vertices();
            for (int c = 0; c < 3; ++c) m.positions.push_back(0.5f * (m.positions[3 * a + c] + m.positions[3 * b + c]));
            midpoint.emplace(key, v);
            return v;
        };
        std::vector<int> children;
        for (int f = 0; f < m.num_triangles(); ++f) {
            const int a = m.triangles[3 * f], b = m.triangles[3 * f + 1], c = m.triangles[3 * f + 2];
            const int ab = split(a, b), bc = split(b, c), ca = split(c, a);
            children.insert(children.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        m.triangles = std::move(children);
    }
    for (int v = 0; v < m.num_vertices(); ++v) {
        float* p = &m.positions[3 * v];
        const float length = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        for (int c = 0; c < 3; ++c) p[c] /= length;
    }
    return m;
}

// Tags the edges between the triangles whose centroid lies above z = height and the others: a closed loop.
void tag_loop(Mesh& m, float height, float sharpness) {
    std::map<std::pair<int, int>, int> above;  // per edge: triangles above minus triangles below
    for (int f = 0; f < m.num_triangles(); ++f) {
        const int* v = &m.triangles[3 * f];
        const float z = (m.positions[3 * v[0] + 2] + m.positions[3 * v[1] + 2] + m.positions[3 * v[2] + 2]) / 3.0f;
        for (int k = 0; k < 3; ++k) above[std::minmax(v[k], v[(k + 1) % 3])] += z > height ? 1 : -1;
    }
    for (const auto& [edge, balance] : above) {
        if (balance != 0) continue;
        m.crease_edges.insert(m.crease_edges.end(), {edge.first, edge.second});
        m.crease_sharpness.push_back(sharpness);
    }
}

Mesh creased_icosphere() {
    Mesh m = icosphere(4);
    m.name = "creased";
    tag_loop(m, 0.3f, 10.0f);
    tag_loop(m, -0.4f, 2.5f);
    m.corners = {0, 3, 6, 9};  // icosahedron vertices (valence 5), away from and on both sides of the loops
    m.corner_sharpness = {10.0f, 10.0f, 1.5f, 1.5f};
    return m;
}

void add_uv_seam(Mesh& m) {
    const int n = m.num_vertices();
    for (int copy = 0; copy < 2; ++copy)
        for (int v = 0; v < n; ++v) m.uvs.insert(m.uvs.end(), {m.positions[3 * v] + copy, m.positions[3 * v + 1]});
    for (int f = 0; f < m.num_triangles(); ++f) {
        const int* v = &m.triangles[3 * f];
        const bool east = m.positions[3 * v[0]] + m.positions[3 * v[1]] + m.positions[3 * v[2]] > 0;
        for (int k = 0; k < 3; ++k) m.uv_indices.push_back(v[k] + (east ? n : 0));
    }
}

const std::vector<Mesh>& meshes() {
    static const std::vector<Mesh> all = [] {
        Mesh smooth = icosphere(4);
        smooth.name = "icosphere";
        std::vector<Mesh> both{smooth, creased_icosphere()};
        for (Mesh& m : both) add_uv_seam(m);
        return both;
    }();
    return all;
}

// ---- OpenSubdiv --------------------------------------------------------------------------------------------------

struct Vertex {  // PrimvarRefiner's interface
    float p[3];
    void Clear(void* = nullptr) { p[0] = p[1] = p[2] = 0.0f; }
    void AddWithWeight(const Vertex& src, float weight) {
        p[0] += weight * src.p[0];
        p[1] += weight * src.p[1];
        p[2] += weight * src.p[2];
    }
};

// The UV layer only where face-varying data is timed: it costs topology work on both sides.
std::unique_ptr<Far::TopologyRefiner> osd_refiner(const Mesh& m, bool full_last_level = false, bool with_uvs = false,
                                                  int levels = kLevels) {
    Sdc::Options sdc;
    sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    sdc.SetCreasingMethod(Sdc::Options::CREASE_UNIFORM);
    sdc.SetFVarLinearInterpolation(Sdc::Options::FVAR_LINEAR_CORNERS_ONLY);
    Far::TopologyDescriptor::FVarChannel uv_channel;
    uv_channel.numValues = int(m.uvs.size() / 2);
    uv_channel.valueIndices = m.uv_indices.data();
    const std::vector<int> three(m.num_triangles(), 3);
    Far::TopologyDescriptor d;
    d.numVertices = m.num_vertices();
    d.numFaces = m.num_triangles();
    d.numVertsPerFace = three.data();
    d.vertIndicesPerFace = m.triangles.data();
    d.numCreases = int(m.crease_sharpness.size());
    d.creaseVertexIndexPairs = m.crease_edges.data();
    d.creaseWeights = m.crease_sharpness.data();
    d.numCorners = int(m.corners.size());
    d.cornerVertexIndices = m.corners.data();
    d.cornerWeights = m.corner_sharpness.data();
    d.numFVarChannels = with_uvs ? 1 : 0;
    d.fvarChannels = with_uvs ? &uv_channel : nullptr;
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    std::unique_ptr<Far::TopologyRefiner> refiner(Factory::Create(d, Factory::Options(Sdc::SCHEME_LOOP, sdc)));
    Far::TopologyRefiner::UniformOptions uniform(levels);
    uniform.fullTopologyInLastLevel = full_last_level;  // what Limit needs
    refiner->RefineUniform(uniform);
    return refiner;
}

// All levels into one buffer, level after level (OpenSubdiv's tutorial layout); returns the last level.
const Vertex* osd_interpolate(const Far::TopologyRefiner& refiner, const Mesh& m, Vertex* all, int levels = kLevels) {
    std::copy(m.positions.begin(), m.positions.end(), &all[0].p[0]);
    const Far::PrimvarRefiner primvar(refiner);
    Vertex* src = all;
    for (int level = 1; level <= levels; ++level) {
        Vertex* dst = src + refiner.GetLevel(level - 1).GetNumVertices();
        primvar.Interpolate(level, src, dst);
        src = dst;
    }
    return src;
}

int output_vertices(const Far::TopologyRefiner& refiner) { return refiner.GetLevel(kLevels).GetNumVertices(); }

void set_rate(benchmark::State& state, int vertices) {
    state.counters["vertices/s"] = benchmark::Counter(double(vertices), benchmark::Counter::kIsIterationInvariantRate);
}

void osd_far_full(benchmark::State& state, const Mesh* m) {
    int vertices = 0;
    for (auto _ : state) {
        const std::unique_ptr<Far::TopologyRefiner> refiner = osd_refiner(*m);
        const std::unique_ptr<Vertex[]> all(new Vertex[refiner->GetNumVerticesTotal()]);
        benchmark::DoNotOptimize(osd_interpolate(*refiner, *m, all.get()));
        vertices = output_vertices(*refiner);
    }
    set_rate(state, vertices);
}

void osd_primvar_refiner(benchmark::State& state, const Mesh* m) {
    const std::unique_ptr<Far::TopologyRefiner> refiner = osd_refiner(*m);
    const std::unique_ptr<Vertex[]> all(new Vertex[refiner->GetNumVerticesTotal()]);
    for (auto _ : state) benchmark::DoNotOptimize(osd_interpolate(*refiner, *m, all.get()));
    set_rate(state, output_vertices(*refiner));
}

void osd_limit(benchmark::State& state, const Mesh* m) {
    const std::unique_ptr<Far::TopologyRefiner> refiner = osd_refiner(*m, true);
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

// Bfr's own way to tessellate the limit surface: a surface per face (kept), its patch points per frame, and
// Surface::Evaluate with both derivatives at each point of the face's Bfr::Tessellation.
void osd_bfr_tessellate(benchmark::State& state, const Mesh* m, int rate) {
    const std::unique_ptr<Far::TopologyRefiner> refiner = osd_refiner(*m, false, false, 0);
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

struct UV {  // PrimvarRefiner's interface, two floats
    float p[2];
    void Clear(void* = nullptr) { p[0] = p[1] = 0.0f; }
    void AddWithWeight(const UV& src, float weight) {
        p[0] += weight * src.p[0];
        p[1] += weight * src.p[1];
    }
};

// The UV layer's values of all levels into one buffer, as osd_interpolate the vertices'; returns the last level's.
const UV* osd_interpolate_uvs(const Far::TopologyRefiner& refiner, const Mesh& m, UV* all) {
    std::copy(m.uvs.begin(), m.uvs.end(), &all[0].p[0]);
    const Far::PrimvarRefiner primvar(refiner);
    UV* src = all;
    for (int level = 1; level <= kLevels; ++level) {
        UV* dst = src + refiner.GetLevel(level - 1).GetNumFVarValues(0);
        primvar.InterpolateFaceVarying(level, src, dst, 0);
        src = dst;
    }
    return src;
}

void osd_face_varying(benchmark::State& state, const Mesh* m) {
    const std::unique_ptr<Far::TopologyRefiner> refiner = osd_refiner(*m, false, true);
    const std::unique_ptr<UV[]> all(new UV[refiner->GetNumFVarValuesTotal(0)]);
    for (auto _ : state) benchmark::DoNotOptimize(osd_interpolate_uvs(*refiner, *m, all.get()));
    set_rate(state, refiner->GetLevel(kLevels).GetNumFVarValues(0));
}

// The full pipeline with a UV layer: topology with its face-varying channel, then vertices and UVs.
void osd_far_full_uvs(benchmark::State& state, const Mesh* m) {
    int vertices = 0;
    for (auto _ : state) {
        const std::unique_ptr<Far::TopologyRefiner> refiner = osd_refiner(*m, false, true);
        const std::unique_ptr<Vertex[]> all(new Vertex[refiner->GetNumVerticesTotal()]);
        benchmark::DoNotOptimize(osd_interpolate(*refiner, *m, all.get()));
        const std::unique_ptr<UV[]> uvs(new UV[refiner->GetNumFVarValuesTotal(0)]);
        benchmark::DoNotOptimize(osd_interpolate_uvs(*refiner, *m, uvs.get()));
        vertices = output_vertices(*refiner);
    }
    set_rate(state, vertices);
}

std::unique_ptr<const Far::StencilTable> osd_stencils(const Far::TopologyRefiner& refiner) {
    Far::StencilTableFactory::Options options;
    options.generateIntermediateLevels = false;  // control vertices straight to the last level
    options.generateOffsets = true;
    return std::unique_ptr<const Far::StencilTable>(Far::StencilTableFactory::Create(refiner, options));
}

void osd_stencil_table(benchmark::State& state, const Mesh* m) {
    const std::unique_ptr<Far::TopologyRefiner> refiner = osd_refiner(*m);
    for (auto _ : state) benchmark::DoNotOptimize(osd_stencils(*refiner).get());
    set_rate(state, output_vertices(*refiner));
}

template <typename Evaluator>
void osd_evaluator(benchmark::State& state, const Mesh* m) {
    const std::unique_ptr<Far::TopologyRefiner> refiner = osd_refiner(*m);
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

// ---- loopsub -----------------------------------------------------------------------------------------------------

loopsub::MeshView view(const Mesh& m, bool with_uvs = false) {
    loopsub::MeshView v;
    v.num_vertices = m.num_vertices();
    v.triangles = m.triangles.data();
    v.num_triangles = m.num_triangles();
    v.crease_edges = m.crease_edges.data();
    v.crease_sharpness = m.crease_sharpness.data();
    v.num_crease_edges = int(m.crease_sharpness.size());
    v.corner_vertices = m.corners.data();
    v.corner_sharpness = m.corner_sharpness.data();
    v.num_corners = int(m.corners.size());
    if (with_uvs) {
        static thread_local loopsub::FaceVaryingLayer layer;
        layer = {m.uv_indices.data(), int(m.uvs.size() / 2)};
        v.face_varying = &layer;
        v.num_face_varying = 1;
    }
    return v;
}

loopsub::Options options(loopsub::Kernel kernel, int threads,
                         loopsub::LevelTables tables = loopsub::LevelTables::Auto) {
    loopsub::Options o;
    o.level_tables = tables;
    o.rules = loopsub::Rules::OpenSubdiv;
    o.levels = kLevels;
    o.boundary = loopsub::Boundary::EdgesOnly;
    o.crease_method = loopsub::CreaseMethod::Uniform;
    o.kernel = kernel;
    o.threads = threads;
    return o;
}

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

void ours_limit(benchmark::State& state, const Mesh* m, int threads) {
    loopsub::Options o = options(loopsub::Kernel::Auto, threads);
    o.limit_surface = true;
    loopsub::Plan plan(view(*m), o);
    std::vector<float> out(std::size_t(plan.num_output_vertices()) * 3),
        normals(std::size_t(plan.num_output_triangles()) * 9);
    for (auto _ : state) {
        plan.evaluate(loopsub::interleaved(m->positions.data(), 3), loopsub::interleaved(out.data(), 3),
                      normals.data());
        benchmark::DoNotOptimize(normals.data());
    }
    set_rate(state, plan.num_output_vertices());
}

// The same with the normals in compact form (one per vertex and side, Plan::LimitNormals): what the add-on reads.
void ours_limit_compact(benchmark::State& state, const Mesh* m, int threads) {
    loopsub::Options o = options(loopsub::Kernel::Auto, threads);
    o.limit_surface = true;
    loopsub::Plan plan(view(*m), o);
    std::vector<float> out(std::size_t(plan.num_output_vertices()) * 3),
        normals(std::size_t(plan.num_limit_normals()) * 3);
    for (auto _ : state) {
        plan.evaluate(loopsub::interleaved(m->positions.data(), 3), loopsub::interleaved(out.data(), 3),
                      loopsub::Plan::LimitNormals{normals.data()});
        benchmark::DoNotOptimize(normals.data());
    }
    set_rate(state, plan.num_output_vertices());
}

void ours_topology_limit(benchmark::State& state, const Mesh* m, int threads) {
    loopsub::Options o = options(loopsub::Kernel::Auto, threads);
    o.limit_surface = true;
    int vertices = 0;
    for (auto _ : state) {
        loopsub::Plan plan(view(*m), o);
        vertices = plan.num_output_vertices();
        benchmark::DoNotOptimize(plan.output_triangles());
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

// Vertex data wider than positions (point attributes, vertex-group weights): `channels` floats per vertex, the first
// three the positions, the rest their sums, on the limit surface as the add-on refines them.
void ours_limit_channels(benchmark::State& state, const Mesh* m, int channels) {
    loopsub::Options o = options(loopsub::Kernel::Auto, 1);
    o.limit_surface = true;
    loopsub::Plan plan(view(*m), o);
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

loopsub::TessellationRates uniform_rate(int rate) {
    loopsub::TessellationRates rates;
    rates.uniform_rate = rate;
    return rates;
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

// ---- Registration and the speedup table --------------------------------------------------------------------------

// 16: the points of level 4; 12: a rate between levels, where the points lie inside the level's triangles.
constexpr int kTessellationRates[] = {16, 12};

constexpr loopsub::Kernel kKernels[] = {loopsub::Kernel::Scalar, loopsub::Kernel::SSE41, loopsub::Kernel::AVX2};

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
        add("opensubdiv_cpu_evaluator/" + m.name, osd_evaluator<Osd::CpuEvaluator>, &m);
        add("opensubdiv_omp_evaluator/" + m.name + "/threads:2", osd_evaluator<Osd::OmpEvaluator>, &m);
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
            add("loopsub_limit/" + m.name + "/threads:" + std::to_string(threads), ours_limit, &m, threads);
            add("loopsub_limit_compact/" + m.name + "/threads:" + std::to_string(threads), ours_limit_compact, &m,
                threads);
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

// Keeps each benchmark's time (ms): the median aggregate when there are repetitions, else the single run.
// Console output as usual (colours only on a terminal); --benchmark_out=FILE writes JSON/CSV alongside.
class RecordingReporter : public benchmark::ConsoleReporter {
public:
    RecordingReporter() : ConsoleReporter(isatty(fileno(stdout)) ? OO_ColorTabular : OO_Tabular) {}

    void ReportRuns(const std::vector<Run>& runs) override {
        for (const Run& run : runs) {
            const std::string& name = run.run_name.function_name;
            if (run.run_type == Run::RT_Aggregate && run.aggregate_name == "median")
                median_[name] = run.GetAdjustedRealTime();
            else if (run.run_type == Run::RT_Iteration) single_[name] = run.GetAdjustedRealTime();
        }
        ConsoleReporter::ReportRuns(runs);
    }

    // Time of a benchmark, or a negative number when it did not run (filtered out).
    double ms(const std::string& name) const {
        if (const auto found = median_.find(name); found != median_.end()) return found->second;
        if (const auto found = single_.find(name); found != single_.end()) return found->second;
        return -1.0;
    }

private:
    std::map<std::string, double> median_, single_;
};

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

// ---- Peak memory -------------------------------------------------------------------------------------------------

long peak_rss_kib() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return usage.ru_maxrss;  // KiB on Linux
}

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
        const std::unique_ptr<Far::TopologyRefiner> refiner = osd_refiner(m, false, false, levels);
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

}  // namespace

// ---- Screen-space error of camera-driven rates ------------------------------------------------------------------

struct Scene {
    loopsub::MeshData mesh;
    loopsub::Camera camera;
};

Scene screen_scene() {
    Scene scene;
    std::vector<float>& p = scene.mesh.positions;
    std::vector<std::int32_t>& t = scene.mesh.triangles;
    const int n = 24;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const float x = 10.0f * (float(i) - n / 2.0f), z = 10.0f * (float(j) - n / 2.0f);
            p.insert(p.end(), {x, 0.8f * std::sin(0.15f * x) * std::cos(0.1f * z) - 0.5f, z});
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
            t.insert(t.end(), {a, c, d, a, d, b});
        }
    const Mesh sphere = icosphere(2);
    const int first = scene.mesh.num_vertices();
    for (int v = 0; v < sphere.num_vertices(); ++v)
        p.insert(p.end(), {1.5f * sphere.positions[3 * v], 1.5f * sphere.positions[3 * v + 1] + 1.6f,
                           1.5f * sphere.positions[3 * v + 2]});
    for (int c : sphere.triangles) t.push_back(first + c);
    // A camera at (0, 2, 9) looking at (0, 1, 0), y up, 50 degrees.
    const float eye[3] = {0, 2, 9}, target[3] = {0, 1, 0}, up[3] = {0, 1, 0};
    scene.camera = loopsub::look_at_camera(eye, target, up, 50.0f, 1920.0f, 1080.0f);
    return scene;
}

// Where a point lands on screen, in pixels; false behind the camera.
bool to_pixels(const loopsub::Camera& c, const double p[3], double out[2]) {
    const float* m = c.world_to_clip;
    auto row = [&](int r) { return m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3]; };
    const double w = row(3);
    if (!(w > 0)) return false;
    out[0] = (row(0) / w + 1) * 0.5 * c.viewport_width, out[1] = (row(1) / w + 1) * 0.5 * c.viewport_height;
    return true;
}

// The tessellation's screen-space error: over its triangles whose centroid is in view, the distance in pixels between
// the centroid and the limit surface at the centroid's parameters (Bfr, at its finest). Its 99th percentile over the
// triangles, and over the picture (each triangle weighted by its area on screen: a uniform tessellation's many far
// triangles, each a fraction of a pixel, count for what they cover), and its largest.
struct ScreenError {
    double p99, picture_p99, max;  // pixels
};
ScreenError screen_error(const Scene& scene, const loopsub::Tessellation& t) {
    std::vector<float> points(3 * std::size_t(t.num_points()));
    t.evaluate(scene.mesh.positions.data(), points.data(), nullptr);
    const loopsub::MeshData& m = scene.mesh;
    Mesh as_bench;
    as_bench.positions = m.positions, as_bench.triangles = m.triangles;
    const std::unique_ptr<Far::TopologyRefiner> refiner = osd_refiner(as_bench, false, false, 0);
    Bfr::SurfaceFactory::Options options;
    options.SetApproxLevelSmooth(10).SetApproxLevelSharp(10);
    const Bfr::RefinerSurfaceFactory<> factory(*refiner, options);
    const Bfr::Surface<double>::PointDescriptor point(3);
    std::vector<double> control(m.positions.begin(), m.positions.end()), patch_points;
    Bfr::Surface<double> surface;
    int face = -1;
    std::vector<double> errors;
    std::vector<std::pair<double, double>> covered;  // (error, area on screen)
    const float* uv = t.face_point_parameters();
    for (int tri = 0; tri < t.num_triangles(); ++tri) {
        const int f = t.parent_triangles()[tri];
        if (f != face) {
            face = f;
            factory.InitVertexSurface(f, &surface);
            patch_points.resize(3 * std::size_t(surface.GetNumPatchPoints()));
            surface.PreparePatchPoints(control.data(), point, patch_points.data(), point);
        }
        double flat[3] = {0, 0, 0}, at[2] = {0, 0};
        for (int c = 0; c < 3; ++c) {
            const std::int32_t fp = t.corner_face_points()[3 * tri + c], v = t.triangles()[3 * tri + c];
            at[0] += uv[2 * fp] / 3.0, at[1] += uv[2 * fp + 1] / 3.0;
            for (int k = 0; k < 3; ++k) flat[k] += points[3 * std::size_t(v) + k] / 3.0;
        }
        double limit[3], a[2], b[2];
        surface.Evaluate(at, patch_points.data(), point, limit);
        if (!to_pixels(scene.camera, flat, a) || !to_pixels(scene.camera, limit, b)) continue;
        if (a[0] < 0 || a[0] > scene.camera.viewport_width || a[1] < 0 || a[1] > scene.camera.viewport_height) continue;
        errors.push_back(std::hypot(a[0] - b[0], a[1] - b[1]));
        double corner[3][2], area = 0.0;
        bool seen = true;
        for (int c = 0; c < 3; ++c) {
            const std::size_t v = std::size_t(t.triangles()[3 * tri + c]);
            const double p[3] = {points[3 * v], points[3 * v + 1], points[3 * v + 2]};
            seen = seen && to_pixels(scene.camera, p, corner[c]);
        }
        if (seen)
            area = 0.5 * std::fabs((corner[1][0] - corner[0][0]) * (corner[2][1] - corner[0][1]) -
                                   (corner[2][0] - corner[0][0]) * (corner[1][1] - corner[0][1]));
        covered.push_back({errors.back(), area});
    }
    if (errors.empty()) return {0.0, 0.0, 0.0};
    std::sort(errors.begin(), errors.end());
    std::sort(covered.begin(), covered.end());
    double total = 0.0, running = 0.0, picture_p99 = covered.back().first;
    for (const auto& [error, area] : covered) total += area;
    for (const auto& [error, area] : covered)
        if ((running += area) >= 0.99 * total) {
            picture_p99 = error;
            break;
        }
    return {errors[std::size_t(0.99 * double(errors.size() - 1))], picture_p99, errors.back()};
}

int measure_screen_error() {
    const Scene scene = screen_scene();
    loopsub::Options options;
    options.rules = loopsub::Rules::OpenSubdiv;
    std::printf("scene: %d triangles (ground of 24 x 24 quads 240 units wide, sphere of 320), camera 1920 x 1080\n",
                scene.mesh.num_triangles());
    std::printf("%-34s %12s %14s %14s %14s\n", "rates", "triangles", "p99 (pixels)", "picture p99", "max (pixels)");
    struct Row {
        int triangles;
        ScreenError error;
    };
    std::vector<Row> uniform;
    for (int level = 0; level <= 6; ++level) {
        loopsub::TessellationRates rates;
        rates.uniform_rate = 1 << level;
        const loopsub::Tessellation t(scene.mesh.view(), options, rates);
        uniform.push_back({t.num_triangles(), screen_error(scene, t)});
        std::printf("%-34s %12d %14.3f %14.3f %14.3f\n", ("uniform " + std::to_string(1 << level)).c_str(),
                    uniform.back().triangles, uniform.back().error.p99, uniform.back().error.picture_p99,
                    uniform.back().error.max);
    }
    for (const auto measure : {loopsub::DicingMeasure::Length, loopsub::DicingMeasure::Deviation}) {
        const bool length = measure == loopsub::DicingMeasure::Length;
        for (float pixels :
             length ? std::vector<float>{1, 2, 4, 8, 16, 32} : std::vector<float>{0.004f, 0.016f, 0.06f, 0.25f, 1.0f}) {
            const loopsub::ScreenRates rates = loopsub::screen_space_rates(
                scene.mesh.view(), scene.mesh.positions.data(), scene.camera, pixels, 64, measure);
            const loopsub::Tessellation t(scene.mesh.view(), options, rates.view());
            const ScreenError error = screen_error(scene, t);
            char name[64];
            std::snprintf(name, sizeof name, "camera, %s %g px", length ? "length" : "deviation", double(pixels));
            std::printf("%-34s %12d %14.3f %14.3f %14.3f\n", name, t.num_triangles(), error.p99, error.picture_p99,
                        error.max);
            // Against the uniform rows: the first power of two as good, and a uniform rate between the two around
            // (log triangles linear in log error: at rate r, triangles grow as r^2 and the error falls as 1 / r^2).
            for (const bool picture : {false, true}) {
                auto of = [picture](const ScreenError& e) { return picture ? e.picture_p99 : e.p99; };
                const auto as_good = std::find_if(uniform.begin(), uniform.end(),
                                                  [&](const Row& row) { return of(row.error) <= of(error); });
                std::printf("%36s by the %s: ", "", picture ? "picture's p99  " : "triangles' p99");
                if (as_good == uniform.end() || as_good == uniform.begin()) {
                    std::printf("no uniform rate from 2 to 64 as good\n");
                    continue;
                }
                const Row &finer = *as_good, &coarser = *(as_good - 1);
                const double slope = std::log(double(finer.triangles) / coarser.triangles) /
                                     std::log(of(finer.error) / of(coarser.error));
                const double same = coarser.triangles * std::pow(of(error) / of(coarser.error), slope);
                std::printf("uniform %d as good, %.1fx the triangles; a uniform rate between, %.1fx\n",
                            1 << int(as_good - uniform.begin()), double(as_good->triangles) / t.num_triangles(),
                            same / t.num_triangles());
            }
        }
    }
    std::printf("(issue 25's target: the first uniform rate as good has >= 5x the triangles)\n");
    return 0;
}

int main(int argc, char** argv) {
    if (argc >= 2 && std::string(argv[1]) == "--malloc-keeps-memory") {
        mallopt(M_MMAP_THRESHOLD, 32 << 20);
        mallopt(M_TRIM_THRESHOLD, 1 << 30);
        std::printf("malloc keeps freed memory (mmap threshold 32 MiB, trim threshold 1 GiB)\n");
        for (int i = 1; i + 1 < argc; ++i) argv[i] = argv[i + 1];
        --argc;
    }
    if (argc >= 2 && std::string(argv[1]) == "--memory") return measure_memory(argc >= 3 ? std::atoi(argv[2]) : 6);
    if (argc >= 2 && std::string(argv[1]) == "--screen-error") return measure_screen_error();
    if (argc >= 2 && std::string(argv[1]) == "--thread-scaling")
        return measure_thread_scaling(argc >= 3 ? std::atoi(argv[2]) : 40, argc >= 4 ? argv[3] : "");
    Osd::OmpEvaluator::SetNumThreads(2);
    register_all();
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    RecordingReporter reporter;
    benchmark::RunSpecifiedBenchmarks(&reporter);
    print_speedups(reporter);
    benchmark::Shutdown();
    return 0;
}
