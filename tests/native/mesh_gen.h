// The native tests' side of the test meshes: the generated meshes (support/meshes.h, shared with the benchmark), and
// what only the tests need: gtest parameter names, OpenSubdiv's regression shapes read with the project's OBJ reader,
// and the evaluation of a plan on a mesh.
#pragma once

#include <gtest/gtest.h>

#include <cctype>
#include <stdexcept>
#include <string>
#include <vector>

#include "loopsub/loopsub.h"
#include "support/meshes.h"

namespace loopsub::testing {

// A gtest parameter's name made from its case's `name` (gtest takes letters, digits and '_' only).
template <typename Case>
std::string case_name(const ::testing::TestParamInfo<Case>& info) {
    std::string name = info.param.name;
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return name;
}

// One of OpenSubdiv's Loop regression shapes (file name in LOOPSUB_PEER_SHAPES), with its tags (boundary mode
// and crease method as tagged, else edges only / uniform) and UVs. OpenSubdiv accepts faces that repeat a vertex
// (loop_nonman_edges has four); the project refuses them as bad input, so drop_degenerate_faces removes those
// `f` lines before parsing, to compare the rest of the shape.
TestMesh peer_shape(const std::string& file_name, bool drop_degenerate_faces = false);

// In a clone that does not sit beside the team's shared folder, OpenSubdiv's shapes are missing: peer_shape throws
// this, and the tests that read them skip with its message (ctest's "Not Run"), never fail or pass.
struct PeerShapesMissing : std::runtime_error {
    using std::runtime_error::runtime_error;
};
// Throws PeerShapesMissing, naming the folder, when it is not there.
void require_peer_shapes();
// The reason to skip a test that reads the shapes (nullptr when they are there), and the macro that does it.
const char* peer_shapes_missing();
#define SKIP_WITHOUT_PEER_SHAPES() \
    if (const char* missing = ::loopsub::testing::peer_shapes_missing()) GTEST_SKIP() << missing

// Refines the mesh's positions with a plan built for it: 3 floats per output vertex.
std::vector<float> evaluate_positions(Plan& plan, const TestMesh& mesh);
// The same with a plan built with the limit surface: the limit positions, and the normals of every output corner
// (9 floats per output triangle).
struct LimitEvaluation {
    std::vector<float> positions, normals;
};
LimitEvaluation evaluate_limit(Plan& plan, const TestMesh& mesh);

}  // namespace loopsub::testing
