// libFuzzer target: an OBJ file (with OpenSubdiv's tags) through the reader, then, when it is accepted, through a
// Plan under both rule sets and the per-frame calls, as the CLI runs it. Seeds: the peer shapes.
#include <cstdint>
#include <string>

#include "fuzz_common.h"
#include "obj_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace loopsub;
    obj::ObjMesh mesh;
    try {
        mesh = obj::parse_obj(std::string(reinterpret_cast<const char*>(data), size), "fuzz.obj");
    } catch (const InputError&) { return 0; }
    for (Rules rules : {Rules::Hoppe94, Rules::OpenSubdiv}) {
        Options options;
        options.rules = rules;
        options.levels = 2;
        options.boundary = mesh.boundary.value_or(Boundary::EdgesOnly);
        options.crease_method = mesh.crease_method.value_or(CreaseMethod::Uniform);
        options.memory_limit_bytes = fuzz::kMemoryLimit;
        try {
            Plan plan(mesh.view(), options);
            std::vector<float> corners;
            for (std::int32_t uv : mesh.triangle_uvs)
                corners.insert(corners.end(), {mesh.uvs[2 * uv], mesh.uvs[2 * uv + 1]});
            fuzz::exercise(plan, mesh.positions, corners, mesh.triangle_uvs.empty() ? 0 : 2);
        } catch (const InputError&) {
        } catch (const MemoryLimitError&) {}
    }
    return 0;
}
