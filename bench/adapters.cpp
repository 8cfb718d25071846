// Both libraries set up the same way for the rows: loopsub's options, and OpenSubdiv's refiner through the tests'
// adapter (support/osd_adapter.h) with the same options, its primvar buffers and stencils.
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/stencilTableFactory.h>

#include <algorithm>

#include "bench.h"
#include "support/osd_adapter.h"

namespace bench {

using namespace OpenSubdiv;

loopsub::Options options(loopsub::Kernel kernel, int threads, loopsub::LevelTables tables) {
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

std::unique_ptr<Far::TopologyRefiner> osd_refiner(const loopsub::MeshView& mesh, bool full_last_level, int levels) {
    std::unique_ptr<Far::TopologyRefiner> refiner =
        loopsub::testing::osd_topology_refiner(mesh, loopsub::testing::sdc_options(options(loopsub::Kernel::Auto, 1)));
    Far::TopologyRefiner::UniformOptions uniform(levels);
    uniform.fullTopologyInLastLevel = full_last_level;  // what Limit needs
    refiner->RefineUniform(uniform);
    return refiner;
}

const Vertex* osd_interpolate(const Far::TopologyRefiner& refiner, const Mesh& m, Vertex* all, int levels) {
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

int output_vertices(const Far::TopologyRefiner& refiner) { return refiner.GetLevel(kLevels).GetNumVertices(); }

std::unique_ptr<const Far::StencilTable> osd_stencils(const Far::TopologyRefiner& refiner) {
    Far::StencilTableFactory::Options options;
    options.generateIntermediateLevels = false;  // control vertices straight to the last level
    options.generateOffsets = true;
    return std::unique_ptr<const Far::StencilTable>(Far::StencilTableFactory::Create(refiner, options));
}

void set_rate(benchmark::State& state, int vertices) {
    state.counters["vertices/s"] = benchmark::Counter(double(vertices), benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace bench
