// Generated test meshes: closed, open, with extreme valences, and with seeded random crease / corner tags.
//
// Everything here is deterministic (fixed seeds, std::mt19937 whose sequence the standard fixes) and built
// without the project's code, so that a test's input never depends on the code under test.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cctype>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "loopsub/loopsub.h"

namespace loopsub::testing {

// A gtest parameter's name made from its case's `name` (gtest takes letters, digits and '_' only).
template <typename Case>
std::string case_name(const ::testing::TestParamInfo<Case>& info) {
    std::string name = info.param.name;
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return name;
}

struct TestMesh : MeshData {
    std::string name;
    // Face-varying UVs: 2 floats per value, 3 value indices per triangle (empty: none).
    std::vector<float> uvs;
    std::vector<std::int32_t> triangle_uvs;
    Boundary boundary = Boundary::EdgesOnly;
    CreaseMethod crease_method = CreaseMethod::Uniform;
};

// The distinct undirected edges of a triangle list, each as (min, max), sorted.
std::vector<std::array<std::int32_t, 2>> unique_edges(const std::vector<std::int32_t>& triangles);

// Length of the diagonal of the axis-aligned bounding box of 3-float positions.
double bounding_box_diagonal(const std::vector<float>& positions);

// --- Closed meshes -------------------------------------------------------------------------------------------
TestMesh icosahedron();
// The icosahedron split `splits` times by midpoints pushed onto the unit sphere: 20 * 4^splits triangles.
TestMesh icosphere(int splits);
// Closed triangulated cube [-1, 1]^3: 8 vertices (index = x + 2y + 4z of the 0/1 corner), 12 triangles.
TestMesh cube();
// Two cones glued at a ring of n vertices: apexes of valence n (vertices 0 and 1), ring vertices of valence 4.
TestMesh bipyramid(int n);
// Torus with a regular triangulation (every vertex has valence 6): vertex (i, j) is i * nv + j, i around the
// big circle (nu), j around the tube (nv). Each quad (i, j)-(i+1, j+1) is split along that diagonal.
TestMesh torus(int nu, int nv);
inline int torus_vertex(int nv, int i, int j) { return i * nv + j; }

// --- Open meshes ---------------------------------------------------------------------------------------------
// (nx+1) x (ny+1) vertices, vertex (i, j) = j * (nx + 1) + i, each quad split along (i, j)-(i+1, j+1); slightly
// curved (z = 0.1 sin x cos y) so that no rule can pass by symmetry. Interior vertices have valence 6; boundary
// vertices 4, except the corners (valence 2 at (nx, 0) and (0, ny), 3 at (0, 0) and (nx, ny)).
TestMesh grid(int nx, int ny);
inline int grid_vertex(int nx, int i, int j) { return j * (nx + 1) + i; }
// Open tube: n around, rows + 1 rings; every boundary vertex has valence 4 (three faces), the interior 6.
TestMesh open_cylinder(int n, int rows);
// n triangles around an apex (vertex 0, valence n); the rim (vertices 1..n) is boundary, valence 3.
TestMesh open_fan(int n);
// The upper half (triangle centroids with z > -0.05) of icosphere(splits); one boundary loop.
TestMesh hemisphere(int splits);

// --- Non-manifold meshes (OpenSubdiv makes such edges and vertices sharp) -----------------------------------
// grid(3, 3) with a fin: an extra triangle on the interior edge (1,1)-(2,2), which then has three faces.
TestMesh fin_on_grid();
// Two open fans of n triangles touching only at their apex (vertex 0): a non-manifold vertex.
TestMesh bowtie(int n);

// --- Changes applied to a mesh -------------------------------------------------------------------------------
// Moves every vertex by a seeded random offset of up to `amount` per coordinate: breaks the symmetry under which a
// wrong weight could still produce the right point.
void jitter(TestMesh& mesh, unsigned seed, float amount);
// Tags a seeded random `fraction` of the edges as creases. Sharpness: kInfiniteSharpness when semi_sharp is false,
// otherwise drawn from a mix of values below 1, integers, fractional values above 1, and infinite.
void add_random_creases(TestMesh& mesh, unsigned seed, double fraction, bool semi_sharp);
// Tags `count` distinct seeded random vertices as corners (sharpness infinite, or semi-sharp values as above).
void add_random_corners(TestMesh& mesh, unsigned seed, int count, bool semi_sharp);
// UVs from the x, y coordinates; triangles whose centroid has x > 0 get their own copies of their UV values, so
// that a seam (the same vertex with two UVs) runs through the mesh.
void add_uvs_with_seam(TestMesh& mesh);

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
