// Rules::OpenSubdiv against OpenSubdiv itself (Far::TopologyRefiner + PrimvarRefiner from Debian's libosd-dev):
// every output vertex within 1e-5 of the bounding-box diagonal of OpenSubdiv's vertex at the same place in the
// topology, the same faces with the same winding and level-0 parents, and face-varying UVs equal to OpenSubdiv's
// FVAR_LINEAR_ALL interpolation. One test case per mesh and level, so that a failure names its case.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "loopsub/loopsub.h"
#include "mesh_gen.h"
#include "obj_io.h"
#include "osd_reference.h"

namespace loopsub::testing {
namespace {

// The peer's twelve shapes, listed so that a missing or unreadable file fails instead of shrinking the suite.
const char* const kPeerShapes[] = {
    "loop_chaikin0.obj",          "loop_cube.obj",        "loop_cube_creases0.obj",       "loop_fvar_bound0.obj",
    "loop_icos_semisharp.obj",    "loop_icosahedron.obj", "loop_nonman_edges.obj",        "loop_pole8.obj",
    "loop_saddle_edgecorner.obj", "loop_tetrahedron.obj", "loop_triangle_edgecorner.obj", "loop_xord_interior.obj",
};

struct ExactCase {
    std::string name;
    std::function<TestMesh()> make;
    int level;
};
// gtest prints a parameter with this (instead of its bytes) when a case fails.
void PrintTo(const ExactCase& c, std::ostream* os) { *os << c.name; }

bool is_semi(float sharpness) { return sharpness > 0.0f && sharpness < kInfiniteSharpness; }

std::string level_suffix(int level) { return "_L" + std::to_string(level); }

// Our per-corner UVs (2 per corner of each output triangle) against OpenSubdiv's for the same oriented face, corner by
// corner; "" when all are within 1e-5.
std::string compare_face_uvs(const Plan& plan, const MappedReference& mapped, const std::vector<float>& ours,
                             const std::vector<double>& expected_uvs,
                             const std::vector<std::uint8_t>* skipped_vertices = nullptr) {
    std::map<std::array<std::int32_t, 3>, int> osd_face;
    for (std::size_t f = 0; 3 * f < mapped.triangles.size(); ++f) {
        const std::int32_t* t = &mapped.triangles[3 * f];
        osd_face.emplace(canonical_triangle(t[0], t[1], t[2]), int(f));
    }
    const std::int32_t* tris = plan.output_triangles();
    int bad = 0;
    std::ostringstream report;
    for (int f = 0; f < plan.num_output_triangles(); ++f) {
        const std::int32_t* t = &tris[3 * f];
        auto it = osd_face.find(canonical_triangle(t[0], t[1], t[2]));
        if (it == osd_face.end()) continue;  // reported by compare_triangles
        const int g = it->second;
        const int ours_rotation = canonical_rotation(t[0], t[1], t[2]);
        const std::int32_t* u = &mapped.triangles[3 * g];
        const int theirs_rotation = canonical_rotation(u[0], u[1], u[2]);
        for (int k = 0; k < 3; ++k) {
            const int our_corner = (k + ours_rotation) % 3, their_corner = (k + theirs_rotation) % 3;
            if (skipped_vertices && (*skipped_vertices)[t[our_corner]]) continue;
            for (int c = 0; c < 2; ++c) {
                const double got = ours[6 * f + 2 * our_corner + c];
                const double expected = expected_uvs[6 * g + 2 * their_corner + c];
                if (!(std::abs(got - expected) <= 1e-5) && bad++ < 5)
                    report << "  triangle " << f << " corner " << our_corner << " (vertex " << t[our_corner]
                           << ") channel " << c << ": expected " << expected << ", got " << got << "\n";
            }
        }
    }
    if (bad > 5) report << "  ... " << bad << " in all\n";
    return report.str();
}

// A face-varying layer refined by the plan, spread to the output's corners (2 floats per corner of each triangle).
std::vector<float> layer_per_corner(Plan& plan, const std::vector<float>& uvs) {
    std::vector<float> values(2 * std::size_t(plan.num_output_face_varying_values(0)));
    plan.evaluate_face_varying(0, interleaved(uvs.data(), 2), interleaved(values.data(), 2));
    const std::int32_t* indices = plan.output_face_varying_indices(0);
    std::vector<float> per_corner(6 * std::size_t(plan.num_output_triangles()));
    for (std::size_t c = 0; c < per_corner.size() / 2; ++c)
        for (int k = 0; k < 2; ++k) per_corner[2 * c + k] = values[2 * std::size_t(indices[c]) + k];
    return per_corner;
}

// Checks one refinement against OpenSubdiv; every expectation names the mesh and level.
void expect_matches_opensubdiv(const TestMesh& mesh, int levels) {
    Options options;
    options.rules = Rules::OpenSubdiv;
    options.levels = levels;
    options.boundary = mesh.boundary;
    options.crease_method = mesh.crease_method;
    Plan plan(mesh.view(), options);
    const std::vector<float> ours = evaluate_positions(plan, mesh);

    ReferenceUVs uvs;
    if (!mesh.triangle_uvs.empty()) {
        uvs.triangle_uvs = mesh.triangle_uvs.data();
        uvs.uvs = mesh.uvs.data();
        uvs.num_uvs = int(mesh.uvs.size() / 2);
    }
    OsdReference reference(mesh.view(), mesh.positions.data(), {mesh.boundary, mesh.crease_method, levels}, uvs);

    ASSERT_EQ(plan.num_output_vertices(), reference.num_vertices(levels)) << "vertex count";
    const MappedReference mapped = reference.map(plan);
    ASSERT_TRUE(mapped.errors.empty()) << mapped.errors.front();
    ASSERT_EQ(std::size_t(plan.num_output_triangles()), mapped.triangles.size() / 3) << "face count (holes left out)";
    if (mesh.hole_triangles.empty() && mesh.boundary != Boundary::None) {
        ASSERT_EQ(plan.num_output_triangles(), reference.num_faces(levels)) << "face count";
    }

    const double tolerance = 1e-5 * bounding_box_diagonal(mesh.positions);
    const std::string position_report = compare_positions(reference, plan, mapped, levels, ours, tolerance);
    EXPECT_TRUE(position_report.empty()) << position_report;
    const std::string triangle_report = compare_triangles(plan, mapped);
    EXPECT_TRUE(triangle_report.empty()) << triangle_report;
    // The output's tags are what OpenSubdiv carries to its last level, so that feeding the output back in continues
    // the same surface.
    const std::string tag_report = compare_crease_tags(plan, mapped);
    EXPECT_TRUE(tag_report.empty()) << tag_report;
    // Every edge the rules treat as sharp on the last level, boundaries and non-manifold edges included: what
    // OpenSubdiv's last level holds as sharp.
    {
        std::map<std::pair<std::int32_t, std::int32_t>, float> theirs, ours;
        for (const MappedReference::EdgeTag& tag : mapped.edge_tags)
            if (tag.sharpness > 0.0f) theirs[std::minmax(tag.a, tag.b)] = tag.sharpness;
        const std::vector<std::int32_t>& sharp = plan.output_sharp_edges();
        for (std::size_t k = 0; k < plan.output_sharp_edge_sharpness().size(); ++k)
            ours[std::minmax(sharp[2 * k], sharp[2 * k + 1])] = plan.output_sharp_edge_sharpness()[k];
        EXPECT_EQ(ours.size(), theirs.size()) << "sharp edges of the output";
        int differing = 0;
        for (const auto& [edge, sharpness] : theirs) {
            const auto found = ours.find(edge);
            if ((found == ours.end() || std::abs(found->second - sharpness) > 1e-5f) && differing++ < 5)
                ADD_FAILURE() << "sharp edge " << edge.first << "-" << edge.second << ": OpenSubdiv " << sharpness
                              << ", ours " << (found == ours.end() ? 0.0f : found->second);
        }
    }

    // The limit surface: positions against Far::PrimvarRefiner::Limit, and at OpenSubdiv's smooth vertices (one
    // normal per vertex) every corner's normal against tan1 x tan2 of its limit tangents. Limit takes semi-sharp
    // features left on the last level for infinitely sharp ones, where the limit surface refines on until they are
    // spent (issue 23), and a dart (one infinitely sharp edge) for a smooth vertex, whose limit it is not (issue 25):
    // those vertices are left to test_limit_bfr.cpp, against the true limit.
    std::vector<std::uint8_t> semi_sharp(mapped.vertex_tags.size(), 0);
    std::vector<int> infinitely_sharp_edges(mapped.vertex_tags.size(), 0);
    for (std::size_t v = 0; v < semi_sharp.size(); ++v) semi_sharp[v] = is_semi(mapped.vertex_tags[v].sharpness);
    for (const MappedReference::EdgeTag& tag : mapped.edge_tags) {
        if (is_semi(tag.sharpness)) semi_sharp[tag.a] = semi_sharp[tag.b] = 1;
        if (tag.sharpness >= kInfiniteSharpness) ++infinitely_sharp_edges[tag.a], ++infinitely_sharp_edges[tag.b];
    }
    for (std::size_t v = 0; v < semi_sharp.size(); ++v)
        if (infinitely_sharp_edges[v] == 1 && mapped.vertex_tags[v].sharpness == 0.0f) semi_sharp[v] = 1;
    {
        Options limit_options = options;
        limit_options.limit_surface = true;
        Plan limit_plan(mesh.view(), limit_options);
        const auto [limit, normals] = evaluate_limit(limit_plan, mesh);
        int bad_positions = 0, bad_normals = 0, smooth_corners = 0;
        std::ostringstream limit_report;
        for (int v = 0; v < limit_plan.num_output_vertices(); ++v) {
            if (semi_sharp[v]) continue;
            double distance = 0.0;
            for (int k = 0; k < 3; ++k)
                distance = std::max(distance, std::abs(limit[3 * v + k] - mapped.limit_positions[3 * v + k]));
            if (!(distance <= tolerance) && bad_positions++ < 5)
                limit_report << "  limit position of vertex " << v << " off by " << distance << "\n";
        }
        const std::int32_t* tris = limit_plan.output_triangles();
        for (int c = 0; c < 3 * limit_plan.num_output_triangles(); ++c) {
            const int v = tris[c];
            if (!mapped.limit_smooth[v] || semi_sharp[v]) continue;
            ++smooth_corners;
            double distance = 0.0;
            for (int k = 0; k < 3; ++k)
                distance = std::max(distance, std::abs(normals[3 * c + k] - mapped.limit_normals[3 * v + k]));
            if (!(distance <= 1e-5) && bad_normals++ < 5)
                limit_report << "  normal at corner " << c << " (vertex " << v << ") off by " << distance << "\n";
        }
        EXPECT_EQ(bad_positions, 0) << "limit positions differ from OpenSubdiv's Limit:\n" << limit_report.str();
        EXPECT_EQ(bad_normals, 0) << "limit normals differ from OpenSubdiv's tangents:\n" << limit_report.str();
        EXPECT_GT(smooth_corners, 0);
    }

    if (mesh.triangle_uvs.empty()) return;
    // Per-corner face-varying values, linear within each face: OpenSubdiv's FVAR_LINEAR_ALL.
    std::vector<float> corner_uvs(6 * std::size_t(mesh.num_triangles()));
    for (std::size_t c = 0; c < mesh.triangle_uvs.size(); ++c)
        for (int k = 0; k < 2; ++k) corner_uvs[2 * c + k] = mesh.uvs[2 * mesh.triangle_uvs[c] + k];
    std::vector<float> out_uvs(6 * std::size_t(plan.num_output_triangles()));
    plan.evaluate_face_varying(corner_uvs.data(), out_uvs.data(), 2);
    const std::string linear_report = compare_face_uvs(plan, mapped, out_uvs, mapped.face_uvs);
    EXPECT_TRUE(linear_report.empty()) << "per-corner face-varying values differ from OpenSubdiv's FVAR_LINEAR_ALL:\n"
                                       << linear_report;

    // A face-varying layer in every interpolation mode, refined and at the limit.
    const FaceVaryingLayer layer{mesh.triangle_uvs.data(), int(mesh.uvs.size() / 2)};
    MeshView with_layer = mesh.view();
    with_layer.face_varying = &layer;
    with_layer.num_face_varying = 1;
    for (int m = 0; m <= int(FaceVaryingInterpolation::All); ++m) {
        const auto mode = FaceVaryingInterpolation(m);
        OsdReference mode_reference(mesh.view(), mesh.positions.data(),
                                    {mesh.boundary, mesh.crease_method, levels, mode}, uvs);
        for (bool limit : {false, true}) {
            Options layer_options = options;
            layer_options.face_varying = mode;
            layer_options.limit_surface = limit;
            Plan layer_plan(with_layer, layer_options);
            const MappedReference mode_mapped = mode_reference.map(layer_plan);
            ASSERT_TRUE(mode_mapped.errors.empty()) << mode_mapped.errors.front();
            const std::vector<float> per_corner = layer_per_corner(layer_plan, mesh.uvs);
            // LimitFaceVarying stops short at semi-sharp vertices as Limit does; the values there go where the vertex
            // goes.
            const std::string report =
                limit ? compare_face_uvs(layer_plan, mode_mapped, per_corner, mode_mapped.face_uvs_limit, &semi_sharp)
                      : compare_face_uvs(layer_plan, mode_mapped, per_corner, mode_mapped.face_uvs);
            EXPECT_TRUE(report.empty()) << "face-varying mode " << m << (limit ? " at the limit" : "")
                                        << " differs from OpenSubdiv:\n"
                                        << report;
        }
    }
}

// A case built from OpenSubdiv's shapes skips (GTEST_SKIP returns from here, ending the test) when they are missing.
void expect_case_matches_opensubdiv(const ExactCase& exact_case) {
    TestMesh mesh;
    try {
        mesh = exact_case.make();
    } catch (const PeerShapesMissing& missing) { GTEST_SKIP() << missing.what(); }
    expect_matches_opensubdiv(mesh, exact_case.level);
}

std::vector<ExactCase> peer_cases() {
    std::vector<ExactCase> cases;
    for (const char* file : kPeerShapes) {
        std::string name(file);
        name = name.substr(0, name.rfind('.'));
        for (int level = 1; level <= 3; ++level)
            cases.push_back({name + level_suffix(level), [file] { return peer_shape(file, true); }, level});
    }
    return cases;
}

// Adds a case per level in [1, max_level].
void add(std::vector<ExactCase>& cases, const std::string& name, std::function<TestMesh()> make, int max_level = 3) {
    for (int level = 1; level <= max_level; ++level) cases.push_back({name + level_suffix(level), make, level});
}

TestMesh with_boundary(TestMesh mesh, Boundary boundary) {
    mesh.boundary = boundary;
    return mesh;
}

std::vector<ExactCase> generated_cases() {
    std::vector<ExactCase> cases;
    // Smooth closed meshes; the jitter keeps a wrong weight from hiding behind symmetry.
    add(cases, "icosahedron", [] {
        TestMesh m = icosahedron();
        jitter(m, 1, 0.05f);
        return m;
    });
    for (int splits : {1, 2, 3, 4}) {
        add(
            cases, "icosphere" + std::to_string(20 << (2 * splits)),
            [splits] {
                TestMesh m = icosphere(splits);
                jitter(m, 2 + splits, 0.01f);
                return m;
            },
            splits == 4 ? 2 : 3);
    }
    // Valences 3 to 64 at the two apexes of a bipyramid (and 4 on its ring).
    for (int n : {3, 4, 5, 6, 7, 8, 9, 12, 16, 24, 32, 48, 64}) {
        add(cases, "bipyramid" + std::to_string(n), [n] {
            TestMesh m = bipyramid(n);
            jitter(m, 100 + n, 0.01f);
            return m;
        });
    }
    // Infinitely sharp random creases and corners.
    for (unsigned seed : {11u, 12u}) {
        add(cases, "icosphere320_sharp_seed" + std::to_string(seed), [seed] {
            TestMesh m = icosphere(2);
            jitter(m, seed, 0.01f);
            add_random_creases(m, seed, 0.15, false);
            add_random_corners(m, seed + 1000, 4, false);
            return m;
        });
    }
    // Semi-sharp creases and corners, both crease methods, three seeds; a dense set (many vertices where three or
    // more semi-sharp edges meet) and a sparse one.
    for (CreaseMethod method : {CreaseMethod::Uniform, CreaseMethod::Chaikin}) {
        const std::string method_name = method == CreaseMethod::Chaikin ? "chaikin" : "uniform";
        for (unsigned seed : {21u, 22u, 23u}) {
            add(cases, "icosphere320_semisharp_" + method_name + "_seed" + std::to_string(seed), [seed, method] {
                TestMesh m = icosphere(2);
                jitter(m, seed, 0.01f);
                add_random_creases(m, seed, 0.2, true);
                add_random_corners(m, seed + 1000, 6, true);
                m.crease_method = method;
                return m;
            });
        }
        add(cases, "icosphere80_dense_semisharp_" + method_name, [method] {
            TestMesh m = icosphere(1);
            jitter(m, 31, 0.01f);
            add_random_creases(m, 31, 0.45, true);
            m.crease_method = method;
            return m;
        });
        add(cases, "cube_all_edges_2.5_" + method_name, [method] {
            TestMesh m = cube();
            // The cube's 12 edges (not the face diagonals) at sharpness 2.5: sharp, sharp, then the blend.
            for (const auto& e : unique_edges(m.triangles)) {
                const int differing_bits = __builtin_popcount(unsigned(e[0] ^ e[1]));
                if (differing_bits == 1) m.add_crease(e[0], e[1], 2.5f);
            }
            m.crease_method = method;
            return m;
        });
    }
    add(cases, "cube_all_edges_sharp", [] {
        TestMesh m = cube();
        for (const auto& e : unique_edges(m.triangles))
            if (__builtin_popcount(unsigned(e[0] ^ e[1])) == 1) m.add_crease(e[0], e[1], kInfiniteSharpness);
        return m;
    });
    // Open meshes in both boundary modes: a grid (corners of valence 2 and 3), a hemisphere (irregular boundary
    // valences), fans (boundary valence 3), an open tube (boundary valence 4).
    for (Boundary boundary : {Boundary::EdgesOnly, Boundary::EdgesAndCorners}) {
        const std::string mode = boundary == Boundary::EdgesOnly ? "_edges" : "_edges_and_corners";
        add(cases, "grid6x5" + mode, [boundary] {
            TestMesh m = with_boundary(grid(6, 5), boundary);
            jitter(m, 41, 0.01f);
            return m;
        });
        add(cases, "grid6x5_semisharp" + mode, [boundary] {
            TestMesh m = with_boundary(grid(6, 5), boundary);
            jitter(m, 42, 0.01f);
            add_random_creases(m, 42, 0.25, true);
            add_random_corners(m, 43, 3, true);
            return m;
        });
        add(cases, "grid6x5_semisharp_chaikin" + mode, [boundary] {
            TestMesh m = with_boundary(grid(6, 5), boundary);
            jitter(m, 44, 0.01f);
            add_random_creases(m, 44, 0.3, true);
            m.crease_method = CreaseMethod::Chaikin;
            return m;
        });
        add(cases, "hemisphere" + mode, [boundary] {
            TestMesh m = with_boundary(hemisphere(2), boundary);
            jitter(m, 45, 0.01f);
            add_random_creases(m, 45, 0.1, true);
            return m;
        });
        add(cases, "open_cylinder8x3" + mode, [boundary] { return with_boundary(open_cylinder(8, 3), boundary); });
        for (int n : {3, 5, 12, 64}) {
            add(cases, "open_fan" + std::to_string(n) + mode, [boundary, n] {
                TestMesh m = with_boundary(open_fan(n), boundary);
                jitter(m, 50 + n, 0.01f);
                return m;
            });
        }
        add(cases, "fin_on_grid" + mode, [boundary] { return with_boundary(fin_on_grid(), boundary); });
        add(cases, "bowtie4" + mode, [boundary] { return with_boundary(bowtie(4), boundary); });
    }
    // Boundary "none": the faces around the boundary become holes (refined, not written), and tagged holes.
    add(cases, "grid6x5_boundary_none", [] {
        TestMesh m = with_boundary(grid(6, 5), Boundary::None);
        jitter(m, 81, 0.01f);
        return m;
    });
    add(cases, "hemisphere_boundary_none_sharp_rim_part", [] {
        TestMesh m = with_boundary(hemisphere(2), Boundary::None);
        jitter(m, 82, 0.01f);
        // Boundary edges tagged infinitely sharp keep their faces.
        std::map<std::array<std::int32_t, 2>, int> faces;
        for (int t = 0; t < m.num_triangles(); ++t)
            for (int k = 0; k < 3; ++k) {
                const std::int32_t a = m.triangles[3 * t + k], b = m.triangles[3 * t + (k + 1) % 3];
                ++faces[{std::min(a, b), std::max(a, b)}];
            }
        int tagged = 0;
        for (const auto& [edge, count] : faces)
            if (count == 1 && tagged++ % 2 == 0) m.add_crease(edge[0], edge[1]);
        return m;
    });
    add(cases, "icosphere320_holes_semisharp_uv_seam", [] {
        TestMesh m = icosphere(2);
        jitter(m, 83, 0.01f);
        add_random_creases(m, 83, 0.2, true);
        add_uvs_with_seam(m);
        m.hole_triangles = {0, 17, 18, 200, 319};
        return m;
    });
    // Harder tag sets. Level 4 lets sharpness up to 3.7 decay all the way (and Chaikin average it along the way).
    for (CreaseMethod method : {CreaseMethod::Uniform, CreaseMethod::Chaikin}) {
        const std::string method_name = method == CreaseMethod::Chaikin ? "chaikin" : "uniform";
        cases.push_back({"icosphere80_semisharp_" + method_name + "_L4",
                         [method] {
                             TestMesh m = icosphere(1);
                             jitter(m, 71, 0.01f);
                             add_random_creases(m, 71, 0.3, true);
                             add_random_corners(m, 72, 5, true);
                             m.crease_method = method;
                             return m;
                         },
                         4});
        // Every edge tagged: vertices where many semi-sharp edges meet, and no smooth edge at all.
        add(cases, "icosphere80_every_edge_semisharp_" + method_name, [method] {
            TestMesh m = icosphere(1);
            jitter(m, 73, 0.01f);
            add_random_creases(m, 73, 1.0, true);
            m.crease_method = method;
            return m;
        });
        // Valence-64 vertices on semi-sharp creases and with vertex sharpness.
        add(cases, "bipyramid64_apex_creases_" + method_name, [method] {
            TestMesh m = bipyramid(64);
            jitter(m, 74, 0.005f);
            m.add_crease(0, 2, 2.5f);
            m.add_crease(0, 34, 0.7f);
            m.add_crease(1, 10, kInfiniteSharpness);
            m.add_crease(1, 20, 1.5f);
            m.add_crease(1, 40, 3.0f);  // three sharp edges at apex 1
            m.add_corner(0, 0.5f);
            m.crease_method = method;
            return m;
        });
        // The peer's non-manifold shape with random semi-sharp creases, in both boundary modes.
        for (Boundary boundary : {Boundary::EdgesOnly, Boundary::EdgesAndCorners}) {
            add(cases,
                "loop_nonman_edges_semisharp_" + method_name +
                    (boundary == Boundary::EdgesOnly ? "_edges" : "_edges_and_corners"),
                [method, boundary] {
                    TestMesh m = peer_shape("loop_nonman_edges.obj", true);
                    add_random_creases(m, 75, 0.2, true);
                    add_random_corners(m, 76, 4, true);
                    m.crease_method = method;
                    m.boundary = boundary;
                    return m;
                });
        }
    }
    // Two faces on the same three vertices (a triangulated Suzanne has a pair): non-manifold, so their edges are
    // sharp, as OpenSubdiv makes them. The copy runs the same way round or the other way. Level 1 only: from level 2
    // on the two faces' children share pairs of midpoints by two edges each, which the vertex mapping of this
    // harness (edges named by their ends) cannot tell apart.
    for (bool reversed : {false, true}) {
        add(
            cases, std::string("icosphere80_duplicate_triangle") + (reversed ? "_reversed" : "_same_way"),
            [reversed] {
                TestMesh m = icosphere(1);
                jitter(m, 78, 0.01f);
                const std::int32_t a = m.triangles[0], b = m.triangles[1], c = m.triangles[2];
                m.triangles.insert(m.triangles.end(), {a, reversed ? c : b, reversed ? b : c});
                return m;
            },
            1);
    }
    // Crease pairs given end-first (b, a): the tags name an edge, not a direction.
    add(cases, "icosphere320_reversed_crease_pairs", [] {
        TestMesh m = icosphere(2);
        jitter(m, 77, 0.01f);
        add_random_creases(m, 77, 0.2, true);
        for (std::size_t k = 0; k < m.crease_sharpness.size(); ++k)
            std::swap(m.crease_edges[2 * k], m.crease_edges[2 * k + 1]);
        return m;
    });
    // Semi-sharp corners and an interior crease reaching the boundary.
    add(cases, "grid6x5_boundary_corners_and_crease_edges_and_corners", [] {
        TestMesh m = with_boundary(grid(6, 5), Boundary::EdgesAndCorners);
        jitter(m, 78, 0.01f);
        for (int i = 0; i < 6; ++i) m.add_crease(grid_vertex(6, i, 2), grid_vertex(6, i + 1, 2), 1.7f);
        m.add_corner(grid_vertex(6, 3, 0), 2.2f);  // on the boundary
        m.add_corner(grid_vertex(6, 2, 2), 0.4f);  // on the crease
        m.add_corner(grid_vertex(6, 6, 0), 1.0f);  // a boundary corner that the mode already makes sharp
        return m;
    });
    // UVs with a seam on meshes whose shape also exercises creases and boundaries.
    add(cases, "icosphere320_semisharp_uv_seam", [] {
        TestMesh m = icosphere(2);
        jitter(m, 61, 0.01f);
        add_random_creases(m, 61, 0.2, true);
        add_uvs_with_seam(m);
        return m;
    });
    // A semi-sharp crease along the whole UV seam, its sharpness changing from edge to edge (with Chaikin an edge's
    // halves decay differently), and random semi-sharp edges elsewhere, some reaching the seam: the seam values held,
    // then released, level by level as the creases decay.
    for (CreaseMethod method : {CreaseMethod::Uniform, CreaseMethod::Chaikin}) {
        add(cases,
            std::string("icosphere320_semisharp_seam_") + (method == CreaseMethod::Chaikin ? "chaikin" : "uniform"),
            [method] {
                TestMesh m = icosphere(2);
                jitter(m, 64, 0.01f);
                add_uvs_with_seam(m);
                std::map<std::array<std::int32_t, 2>, std::set<std::array<std::int32_t, 2>>> values_at_edge;
                for (std::size_t c = 0; c < m.triangles.size(); ++c) {
                    const std::size_t next = c % 3 == 2 ? c - 2 : c + 1;
                    const bool forward = m.triangles[c] < m.triangles[next];
                    const std::array<std::int32_t, 2> edge{m.triangles[forward ? c : next],
                                                           m.triangles[forward ? next : c]};
                    values_at_edge[edge].insert(
                        {m.triangle_uvs[forward ? c : next], m.triangle_uvs[forward ? next : c]});
                }
                std::mt19937 rng(65);
                std::bernoulli_distribution take(0.3);
                const float kSharpness[] = {0.5f, 1.25f, 2.0f, 2.75f, 0.8f, 3.3f};
                int k = 0;
                for (const auto& [edge, values] : values_at_edge)
                    if (values.size() > 1 || take(rng)) m.add_crease(edge[0], edge[1], kSharpness[k++ % 6]);
                m.crease_method = method;
                return m;
            });
    }
    add(cases, "grid6x5_uv_seam_edges_and_corners", [] {
        TestMesh m = with_boundary(grid(6, 5), Boundary::EdgesAndCorners);
        jitter(m, 62, 0.01f);
        add_uvs_with_seam(m);
        return m;
    });
    return cases;
}

class PeerShapesExact : public ::testing::TestWithParam<ExactCase> {};
class GeneratedExact : public ::testing::TestWithParam<ExactCase> {};

TEST_P(PeerShapesExact, MatchesOpenSubdiv) { expect_case_matches_opensubdiv(GetParam()); }

TEST_P(GeneratedExact, MatchesOpenSubdiv) { expect_case_matches_opensubdiv(GetParam()); }

INSTANTIATE_TEST_SUITE_P(OpenSubdivLoopShapes, PeerShapesExact, ::testing::ValuesIn(peer_cases()),
                         case_name<ExactCase>);
INSTANTIATE_TEST_SUITE_P(Generated, GeneratedExact, ::testing::ValuesIn(generated_cases()), case_name<ExactCase>);

// The peer directory holds exactly the shapes listed above: a shape added there must be added here too.
TEST(PeerShapes, AllShapesAreListed) {
    SKIP_WITHOUT_PEER_SHAPES();
    std::set<std::string> on_disk, listed(std::begin(kPeerShapes), std::end(kPeerShapes));
    for (const auto& entry : std::filesystem::directory_iterator(LOOPSUB_PEER_SHAPES))
        if (entry.path().extension() == ".obj") on_disk.insert(entry.path().filename().string());
    EXPECT_EQ(on_disk, listed);
}

// loop_nonman_edges.obj has four faces that repeat a vertex, which OpenSubdiv accepts. The project refuses them
// (issue 2: a degenerate triangle is bad input, reported with its place), so the exact cases above compare the
// shape without them; the file itself must be refused by name and line, not subdivided into garbage.
TEST(PeerShapes, DegenerateFacesAreRefusedWithTheirLine) {
    SKIP_WITHOUT_PEER_SHAPES();
    // Read, then refused by the core; the CLI's words (loopsub::obj::locate) name the first face's line.
    const obj::ObjMesh file = obj::read_obj(std::string(LOOPSUB_PEER_SHAPES) + "/loop_nonman_edges.obj");
    try {
        Plan plan(file.view(), Options{});
        FAIL() << "loop_nonman_edges.obj was planned although faces 193, 238, 283, 294 repeat a vertex";
    } catch (const InputError& error) {
        ASSERT_NE(error.problem(), nullptr) << error.what();
        const std::string located = obj::locate(file, "loop_nonman_edges.obj", *error.problem());
        EXPECT_NE(located.find("loop_nonman_edges.obj:193"), std::string::npos) << located;
        // Every degenerate triangle is listed, the four of those faces.
        const auto problems = diagnose(file.view());
        EXPECT_EQ(std::count_if(problems.begin(), problems.end(),
                                [](const InputProblem& p) { return p.kind == InputProblem::Kind::DegenerateTriangle; }),
                  4);
    }
    // What remains is still the non-manifold shape the peer meant to test.
    const TestMesh mesh = peer_shape("loop_nonman_edges.obj", true);
    EXPECT_EQ(mesh.num_triangles(), 101 - 4);
    std::map<std::array<std::int32_t, 2>, int> faces_per_edge;
    for (int t = 0; t < mesh.num_triangles(); ++t)
        for (int k = 0; k < 3; ++k) {
            std::int32_t a = mesh.triangles[3 * t + k], b = mesh.triangles[3 * t + (k + 1) % 3];
            ++faces_per_edge[{std::min(a, b), std::max(a, b)}];
        }
    EXPECT_TRUE(std::any_of(faces_per_edge.begin(), faces_per_edge.end(), [](const auto& e) { return e.second > 2; }));
}

// Where the rule sets coincide (a closed mesh with no tags: both are Loop's smooth scheme) Hoppe 94's face-varying
// layers are OpenSubdiv's in every mode: seams follow the same rules in both.
TEST(HoppeFaceVarying, EqualsOpenSubdivOnSmoothClosedMeshes) {
    TestMesh mesh = icosphere(2);
    jitter(mesh, 63, 0.01f);
    add_uvs_with_seam(mesh);
    const FaceVaryingLayer layer{mesh.triangle_uvs.data(), int(mesh.uvs.size() / 2)};
    MeshView view = mesh.view();
    view.face_varying = &layer;
    view.num_face_varying = 1;
    const ReferenceUVs uvs{mesh.triangle_uvs.data(), mesh.uvs.data(), int(mesh.uvs.size() / 2)};
    for (int m = 0; m <= int(FaceVaryingInterpolation::All); ++m) {
        Options options;
        options.rules = Rules::Hoppe94;
        options.levels = 2;
        options.face_varying = FaceVaryingInterpolation(m);
        Plan plan(view, options);
        OsdReference reference(mesh.view(), mesh.positions.data(),
                               {Boundary::EdgesOnly, CreaseMethod::Uniform, 2, options.face_varying}, uvs);
        const MappedReference mapped = reference.map(plan);
        ASSERT_TRUE(mapped.errors.empty()) << mapped.errors.front();
        const std::string report = compare_face_uvs(plan, mapped, layer_per_corner(plan, mesh.uvs), mapped.face_uvs);
        EXPECT_TRUE(report.empty()) << "mode " << m << ":\n" << report;
    }
}

// A layer without seams whose values are an affine function of the positions refines as the positions do, whatever
// the rules and tags: each value takes its vertex's masks (Hoppe 94's {5, 3} irregular crease edges included, which
// run their edge's way), so the refined values are that function of the refined positions, at the limit too. Sharp
// creases (irregular crease vertices under Hoppe 94) and semi-sharp ones with Chaikin, both rule sets, every mode
// but linear, levels 1-3 (the last level's parent is not built from 2 on).
TEST(FaceVaryingWithoutSeams, RefinesAsThePositions) {
    auto uv_of = [](const float* p, int k) { return k == 0 ? p[0] + 0.3f * p[2] + 0.1f : p[1] - 0.2f * p[2]; };
    for (bool semi_sharp : {false, true}) {
        TestMesh mesh = icosphere(2);
        jitter(mesh, 65, 0.01f);
        add_random_creases(mesh, semi_sharp ? 66 : 65, 0.25, semi_sharp);
        if (semi_sharp) mesh.crease_method = CreaseMethod::Chaikin;
        std::vector<float> uvs(2 * std::size_t(mesh.num_vertices()));
        for (int v = 0; v < mesh.num_vertices(); ++v)
            for (int k = 0; k < 2; ++k) uvs[2 * v + k] = uv_of(&mesh.positions[3 * v], k);
        const FaceVaryingLayer layer{mesh.triangles.data(), mesh.num_vertices()};
        MeshView view = mesh.view();
        view.face_varying = &layer;
        view.num_face_varying = 1;
        for (Rules rules : {Rules::Hoppe94, Rules::OpenSubdiv})
            for (int m = 0; m < int(FaceVaryingInterpolation::All); ++m)
                for (int levels = 1; levels <= 3; ++levels)
                    for (bool limit : {false, true}) {
                        Options options;
                        options.rules = rules;
                        options.crease_method = mesh.crease_method;
                        options.levels = levels;
                        options.face_varying = FaceVaryingInterpolation(m);
                        options.limit_surface = limit;
                        Plan plan(view, options);
                        std::vector<float> positions(3 * std::size_t(plan.num_output_vertices()));
                        plan.evaluate(interleaved(mesh.positions.data(), 3), interleaved(positions.data(), 3));
                        std::vector<float> values(2 * std::size_t(plan.num_output_face_varying_values(0)));
                        plan.evaluate_face_varying(0, interleaved(uvs.data(), 2), interleaved(values.data(), 2));
                        const std::int32_t* triangles = plan.output_triangles();
                        const std::int32_t* value_of = plan.output_face_varying_indices(0);
                        double worst = 0;
                        for (std::size_t c = 0; c < 3 * std::size_t(plan.num_output_triangles()); ++c)
                            for (int k = 0; k < 2; ++k)
                                worst = std::max(worst,
                                                 double(std::abs(values[2 * std::size_t(value_of[c]) + k] -
                                                                 uv_of(&positions[3 * std::size_t(triangles[c])], k))));
                        EXPECT_LT(worst, 2e-5)
                            << (semi_sharp ? "semi-sharp" : "sharp") << " creases, rules " << int(rules) << ", mode "
                            << m << ", levels " << levels << (limit ? ", limit" : "");
                    }
    }
}

// The generated meshes really have the valences and tags the cases above count on (a generator bug would
// otherwise quietly weaken the suite).
TEST(GeneratedMeshes, HaveTheAdvertisedShape) {
    for (int n : {3, 16, 64}) {
        const TestMesh m = bipyramid(n);
        int apex_valence = 0;
        for (const auto& e : unique_edges(m.triangles)) apex_valence += (e[0] == 0);
        EXPECT_EQ(apex_valence, n) << "bipyramid" << n;
    }
    EXPECT_EQ(icosphere(4).num_triangles(), 5120);
    TestMesh m = icosphere(2);
    add_random_creases(m, 21, 0.2, true);
    std::set<float> distinct(m.crease_sharpness.begin(), m.crease_sharpness.end());
    EXPECT_GT(m.num_vertices(), 0);
    EXPECT_GT(distinct.size(), 5u);  // semi-sharp values of several kinds, not one
    EXPECT_TRUE(std::any_of(distinct.begin(), distinct.end(), [](float s) { return s < 1; }));
    EXPECT_TRUE(std::any_of(distinct.begin(), distinct.end(), [](float s) { return s >= kInfiniteSharpness; }));
}

}  // namespace
}  // namespace loopsub::testing
