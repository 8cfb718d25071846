// Generated test meshes: closed, open, with extreme valences, and with seeded random crease / corner tags. One set
// for the native tests (tests/native, through mesh_gen.h) and the benchmark (bench/).
//
// Everything here is deterministic (fixed seeds, std::mt19937 whose sequence the standard fixes) and built
// without the project's code, so that a test's input never depends on the code under test. Public API only
// (tests/lint/check_layers.py): the benchmark is held to it.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "loopsub/loopsub.h"

namespace loopsub::testing {

struct TestMesh : MeshData {
    std::string name;
    // Face-varying UVs: 2 floats per value, 3 value indices per triangle (empty: none).
    std::vector<float> uvs;
    std::vector<std::int32_t> triangle_uvs;
    Boundary boundary = Boundary::EdgesOnly;
    CreaseMethod crease_method = CreaseMethod::Uniform;

    using MeshData::view;
    // view() with the UVs as its one face-varying layer: valid while this mesh lives and is not modified (the layer
    // is kept here, made again at each call).
    MeshView view_with_uvs() const;

private:
    mutable FaceVaryingLayer uv_layer_;
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
// A pillow (two faces on the same three vertices) on an icosahedron's vertex `apex`, which is then a vertex of two
// fans; the pillow's other vertices are v (an interior vertex of valence 2) and v + 1. Every refined level has two
// edges between the same two vertices next to v.
struct PillowOnIcosahedron {
    TestMesh mesh;
    std::int32_t v, apex;
};
PillowOnIcosahedron pillow_on_icosahedron();

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

}  // namespace loopsub::testing
