// Tessellation of the limit surface at a rate per edge (issue 25): the box spline of a regular patch, the pattern of a
// triangle, and the tessellation against OpenSubdiv's Bfr at the same parameters (within 1e-5 of the bounding box's
// diagonal), crack-free for any rates, and at rates 2^L the vertices of L levels of refinement on the limit surface.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "bfr_reference.h"
#include "loopsub/tessellation.h"
#include "mesh_gen.h"
#include "rules/box_spline.h"
#include "topology/tessellation_pattern.h"

namespace loopsub::testing {
namespace {

using detail::box_spline_weights;
using detail::kBoxSplinePoints;

// The 12 control points on the unit triangular lattice, in box_spline.h's order (rows of 2, 3, 4, 3 points).
const double kLattice[kBoxSplinePoints][2] = {{1.0, 2.0}, {2.0, 2.0},  {0.5, 1.0},  {1.5, 1.0},
                                              {2.5, 1.0}, {0.0, 0.0},  {1.0, 0.0},  {2.0, 0.0},
                                              {3.0, 0.0}, {0.5, -1.0}, {1.5, -1.0}, {2.5, -1.0}};

TEST(BoxSpline, WeightsSumToOneAndReproduceTheLattice) {
    for (double v : {0.0, 0.125, 0.3, 0.5, 1.0})
        for (double w : {0.0, 0.2, 0.5})
            if (v + w <= 1.0) {
                double weights[kBoxSplinePoints], dv[kBoxSplinePoints], dw[kBoxSplinePoints];
                box_spline_weights(v, w, weights, dv, dw);
                double sum = 0.0, sum_v = 0.0, sum_w = 0.0, x = 0.0, y = 0.0, xv = 0.0, yw = 0.0;
                for (int i = 0; i < kBoxSplinePoints; ++i) {
                    sum += weights[i], sum_v += dv[i], sum_w += dw[i];
                    x += weights[i] * kLattice[i][0], y += weights[i] * kLattice[i][1];
                    xv += dv[i] * kLattice[i][0], yw += dw[i] * kLattice[i][1];
                }
                EXPECT_NEAR(sum, 1.0, 1e-14);
                EXPECT_NEAR(sum_v, 0.0, 1e-14);
                EXPECT_NEAR(sum_w, 0.0, 1e-14);
                // A box spline reproduces linear functions: the lattice point P3 + v (P6 - P3) + w (P7 - P3), and
                // derivatives P6 - P3 = (-0.5, -1) and P7 - P3 = (0.5, -1).
                const double u = 1.0 - v - w;
                EXPECT_NEAR(x, 1.5 * u + 1.0 * v + 2.0 * w, 1e-14);
                EXPECT_NEAR(y, 1.0 * u, 1e-14);
                EXPECT_NEAR(xv, -0.5, 1e-14);
                EXPECT_NEAR(yw, -1.0, 1e-14);
            }
}

TEST(BoxSpline, CornersTakeLoopsLimitMask) {
    // At a corner the surface is the limit point of a smooth vertex of valence 6: 1/2 of it, 1/12 of each neighbour.
    const int corner[3] = {3, 6, 7};
    const int neighbours[3][6] = {{0, 1, 2, 4, 6, 7}, {2, 3, 5, 7, 9, 10}, {3, 4, 6, 8, 10, 11}};
    const double at[3][2] = {{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}};
    for (int k = 0; k < 3; ++k) {
        double weights[kBoxSplinePoints], dv[kBoxSplinePoints], dw[kBoxSplinePoints];
        box_spline_weights(at[k][0], at[k][1], weights, dv, dw);
        for (int i = 0; i < kBoxSplinePoints; ++i) {
            const bool neighbour = std::find(neighbours[k], neighbours[k] + 6, i) != neighbours[k] + 6;
            EXPECT_NEAR(weights[i], i == corner[k] ? 0.5 : neighbour ? 1.0 / 12.0 : 0.0, 1e-15) << k << " " << i;
        }
    }
}

double signed_area(const detail::PatternPoint& a, const detail::PatternPoint& b, const detail::PatternPoint& c) {
    const double ax = double(a.b1) / a.den, ay = double(a.b2) / a.den, bx = double(b.b1) / b.den,
                 by = double(b.b2) / b.den, cx = double(c.b1) / c.den, cy = double(c.b2) / c.den;
    return 0.5 * ((bx - ax) * (cy - ay) - (by - ay) * (cx - ax));
}

TEST(TessellationPattern, CoversTheTriangleOnceCounterClockwise) {
    std::mt19937 random(25);
    std::vector<std::array<int, 3>> cases = {{1, 1, 1}, {2, 2, 2}, {7, 7, 7},   {1, 2, 1}, {2, 1, 1}, {3, 1, 2},
                                             {5, 3, 8}, {8, 1, 1}, {16, 9, 12}, {4, 4, 5}, {1, 1, 3}};
    for (int k = 0; k < 40; ++k)
        cases.push_back({int(random() % 12) + 1, int(random() % 12) + 1, int(random() % 12) + 1});
    for (const auto& rates : cases) {
        const int inner = *std::max_element(rates.begin(), rates.end());
        detail::FacePattern pattern;
        detail::tessellate_triangle(rates.data(), inner, pattern);
        const std::string name =
            std::to_string(rates[0]) + "," + std::to_string(rates[1]) + "," + std::to_string(rates[2]);
        ASSERT_EQ(std::int64_t(pattern.points.size()),
                  detail::first_edge_point(rates.data(), 3) + detail::num_inner_points(rates.data(), inner))
            << name;
        double area = 0.0;
        std::vector<int> used(pattern.points.size(), 0);
        for (std::size_t t = 0; t < pattern.triangles.size(); t += 3) {
            const auto& p = pattern.points;
            const double a = signed_area(p[std::size_t(pattern.triangles[t])], p[std::size_t(pattern.triangles[t + 1])],
                                         p[std::size_t(pattern.triangles[t + 2])]);
            EXPECT_GT(a, 1e-12) << name << ": triangle " << t / 3 << " is not counter-clockwise";
            area += a;
            for (int c = 0; c < 3; ++c) ++used[std::size_t(pattern.triangles[t + std::size_t(c)])];
        }
        EXPECT_NEAR(area, 0.5, 1e-12) << name;
        EXPECT_EQ(std::int64_t(pattern.triangles.size() / 3), detail::num_pattern_triangles(rates.data(), inner))
            << name;
        EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0) << name << ": a point in no triangle";
        // Each edge's points, in order from corner k, lie on it at i / rate.
        for (int k = 0; k < 3; ++k)
            for (int i = 1; i < rates[std::size_t(k)]; ++i) {
                const auto& q = pattern.points[std::size_t(detail::first_edge_point(rates.data(), k) + i - 1)];
                const double b[3] = {double(q.den - q.b1 - q.b2) / q.den, double(q.b1) / q.den, double(q.b2) / q.den};
                EXPECT_DOUBLE_EQ(b[(k + 1) % 3], double(i) / rates[std::size_t(k)]) << name;
                EXPECT_EQ(b[(k + 2) % 3], 0.0) << name;
            }
    }
}

// --- The tessellation ------------------------------------------------------------------------------------------

Options options_for(const TestMesh& mesh) {
    Options options;
    options.rules = Rules::OpenSubdiv;
    options.boundary = mesh.boundary;
    options.crease_method = mesh.crease_method;
    return options;
}

// Rates: a uniform one, or (uniform < 0) one drawn per edge from 1 .. -uniform.
struct RatesFor {
    std::vector<std::int32_t> edges, rates;
    TessellationRates view;
    RatesFor(const TestMesh& mesh, int uniform, unsigned seed) {
        view.uniform_rate = std::max(uniform, 1);
        if (uniform > 0) return;
        std::mt19937 random(seed);
        for (const auto& e : unique_edges(mesh.triangles)) {
            edges.push_back(e[0]), edges.push_back(e[1]);
            rates.push_back(int(random() % unsigned(-uniform)) + 1);
        }
        view.edges = edges.data(), view.rates = rates.data(), view.num_edges = int(rates.size());
    }
};

struct Errors {
    double position = 0.0, angle = 0.0;
};

// Every face point once, with its face and parameters (from the output triangles it is a corner of), and its point.
struct FacePoints {
    std::vector<BfrPoint> asked;
    std::vector<std::int32_t> point_of;
};
FacePoints face_points_of(const Tessellation& tessellation) {
    FacePoints out;
    out.asked.assign(std::size_t(tessellation.num_face_points()), BfrPoint{-1, 0.0, 0.0});
    out.point_of.assign(out.asked.size(), -1);
    const float* parameters = tessellation.face_point_parameters();
    for (int t = 0; t < tessellation.num_triangles(); ++t)
        for (int c = 0; c < 3; ++c) {
            const std::int32_t fp = tessellation.corner_face_points()[3 * t + c];
            out.asked[std::size_t(fp)] = {tessellation.parent_triangles()[t], parameters[2 * fp],
                                          parameters[2 * fp + 1]};
            out.point_of[std::size_t(fp)] = tessellation.triangles()[3 * t + c];
        }
    return out;
}

Errors errors_against_bfr(const TestMesh& mesh, const Tessellation& tessellation) {
    std::vector<float> points(3 * std::size_t(tessellation.num_points())),
        normals(3 * std::size_t(tessellation.num_face_points()));
    tessellation.evaluate(mesh.positions.data(), points.data(), normals.data());
    const auto [asked, point_of] = face_points_of(tessellation);
    const BfrLimit expected = bfr_evaluate(mesh, asked);
    // Normals are compared away from three kinds of input vertex. At a vertex with a single face Bfr's derivatives span
    // another plane than the limit tangents (test_limit_bfr.cpp). At a dart or an infinitely sharp corner Bfr's
    // tangent plane, that of its isolated patch 10 levels down, is still (0.68 or 0.75)^10 of a turn from the limit's,
    // and turns with the face it is asked in: there ours are checked against the limit's own definition
    // (test_rules_hand.cpp's dart masks, test_limit_normals.cpp's corners).
    std::vector<int> faces_at(std::size_t(mesh.num_vertices()), 0), sharp_at(faces_at);
    for (std::int32_t v : mesh.triangles) ++faces_at[std::size_t(v)];
    std::map<std::pair<int, int>, int> edge_faces;
    for (std::size_t c = 0; c < mesh.triangles.size(); ++c) {
        const int a = mesh.triangles[c], b = mesh.triangles[c - c % 3 + (c + 1) % 3];
        ++edge_faces[{std::min(a, b), std::max(a, b)}];
    }
    for (std::size_t e = 0; e < mesh.crease_sharpness.size(); ++e)
        if (mesh.crease_sharpness[e] >= kInfiniteSharpness) {
            const int a = mesh.crease_edges[2 * e], b = mesh.crease_edges[2 * e + 1];
            if (edge_faces[{std::min(a, b), std::max(a, b)}] == 2)
                ++sharp_at[std::size_t(a)], ++sharp_at[std::size_t(b)];
        }
    for (const auto& [edge, count] : edge_faces)
        if (count != 2) ++sharp_at[std::size_t(edge.first)], ++sharp_at[std::size_t(edge.second)];
    for (std::size_t k = 0; k < mesh.corner_sharpness.size(); ++k)
        if (mesh.corner_sharpness[k] >= kInfiniteSharpness) sharp_at[std::size_t(mesh.corner_vertices[k])] = 3;
    const double diagonal = bounding_box_diagonal(mesh.positions);
    Errors errors;
    for (std::size_t fp = 0; fp < asked.size(); ++fp) {
        double d2 = 0.0, dot = 0.0;
        for (int c = 0; c < 3; ++c) {
            d2 += std::pow(points[3 * std::size_t(point_of[fp]) + std::size_t(c)] - expected.positions[3 * fp + c], 2);
            dot += normals[3 * fp + std::size_t(c)] * expected.normals[3 * fp + c];
        }
        errors.position = std::max(errors.position, std::sqrt(d2) / diagonal);
        const bool input_vertex = point_of[fp] < mesh.num_vertices();
        const int sharp = input_vertex ? sharp_at[std::size_t(point_of[fp])] : 0;
        const bool skip_normal = input_vertex && (faces_at[std::size_t(point_of[fp])] == 1 || sharp == 1 || sharp > 2);
        const bool no_normal = expected.normals[3 * fp] == 0.0 && expected.normals[3 * fp + 1] == 0.0 &&
                               expected.normals[3 * fp + 2] == 0.0;
        if (!skip_normal && !no_normal) errors.angle = std::max(errors.angle, std::acos(std::clamp(dot, -1.0, 1.0)));
    }
    return errors;
}

struct ShapeCase {
    std::string name;
    std::function<TestMesh()> make;
};
void PrintTo(const ShapeCase& c, std::ostream* os) { *os << c.name; }

std::vector<ShapeCase> shapes() {
    std::vector<ShapeCase> out;
    for (const char* file :
         {"loop_chaikin0.obj", "loop_cube.obj", "loop_cube_creases0.obj", "loop_fvar_bound0.obj",
          "loop_icos_semisharp.obj", "loop_icosahedron.obj", "loop_pole8.obj", "loop_saddle_edgecorner.obj",
          "loop_tetrahedron.obj", "loop_triangle_edgecorner.obj", "loop_xord_interior.obj"}) {
        const std::string name(file);
        out.push_back({name.substr(0, name.rfind('.')), [file] { return peer_shape(file, true); }});
    }
    out.push_back({"torus_semisharp", [] {
                       TestMesh mesh = torus(8, 6);
                       jitter(mesh, 251, 0.02f);
                       for (int i = 0; i < 8; ++i)
                           mesh.add_crease(torus_vertex(6, i, 0), torus_vertex(6, (i + 1) % 8, 0), 0.4f + 0.4f * i);
                       mesh.add_crease(torus_vertex(6, 2, 3), torus_vertex(6, 2, 4));
                       return mesh;
                   }});
    out.push_back({"grid_creases_and_corners", [] {
                       TestMesh mesh = grid(6, 5);
                       jitter(mesh, 252, 0.02f);
                       mesh.boundary = Boundary::EdgesAndCorners;
                       for (int i = 0; i < 6; ++i) mesh.add_crease(grid_vertex(6, i, 2), grid_vertex(6, i + 1, 2));
                       mesh.add_crease(grid_vertex(6, 3, 3), grid_vertex(6, 3, 4), 1.7f);
                       mesh.add_corner(grid_vertex(6, 2, 2), 2.5f);
                       return mesh;
                   }});
    return out;
}

class TessellationAgainstBfr : public ::testing::TestWithParam<ShapeCase> {};

TEST_P(TessellationAgainstBfr, PointsAndNormalsAreTheLimitSurfaces) {
    TestMesh mesh;
    try {
        mesh = GetParam().make();
    } catch (const PeerShapesMissing& missing) { GTEST_SKIP() << missing.what(); }
    for (int uniform : {1, 2, 3, 5, 6, -7}) {
        const RatesFor rates(mesh, uniform, 25);
        const Tessellation tessellation(mesh.view(), options_for(mesh), rates.view);
        const Errors errors = errors_against_bfr(mesh, tessellation);
        const std::string where = GetParam().name + ", rate " +
                                  (uniform > 0 ? std::to_string(uniform) : "1.." + std::to_string(-uniform)) +
                                  ": position " + std::to_string(errors.position) + " of the diagonal, normal " +
                                  std::to_string(errors.angle) + " rad";
        EXPECT_LE(errors.position, 1e-5) << where;
        EXPECT_LE(errors.angle, 1e-3) << where;
    }
}

INSTANTIATE_TEST_SUITE_P(Shapes, TessellationAgainstBfr, ::testing::ValuesIn(shapes()), case_name<ShapeCase>);

// Boundary::None and hole tags: the faces Bfr gives no limit surface (FaceHasLimitSurface) get no triangles, and no
// points but the input vertices they share; the others are Bfr's surface, shaped by every face around them, those
// without a surface too. An input vertex of no face with a surface stays where it is.
std::vector<ShapeCase> shapes_with_holes() {
    std::vector<ShapeCase> out;
    for (const char* file : {"loop_fvar_bound0.obj", "loop_pole8.obj", "loop_saddle_edgecorner.obj",
                             "loop_triangle_edgecorner.obj", "loop_xord_interior.obj"}) {
        const std::string name(file);
        out.push_back({name.substr(0, name.rfind('.')) + "_boundary_none", [file] {
                           TestMesh mesh = peer_shape(file, true);
                           mesh.boundary = Boundary::None;
                           return mesh;
                       }});
    }
    out.push_back({"grid_boundary_none", [] {
                       TestMesh mesh = grid(7, 6);
                       jitter(mesh, 253, 0.02f);
                       mesh.boundary = Boundary::None;
                       return mesh;
                   }});
    // Boundary edges tagged infinitely sharp keep their faces; a semi-sharp tag does not. Creases and a corner inside.
    out.push_back({"grid_boundary_none_tagged", [] {
                       TestMesh mesh = grid(7, 6);
                       jitter(mesh, 254, 0.02f);
                       mesh.boundary = Boundary::None;
                       for (int i = 0; i < 7; ++i) mesh.add_crease(grid_vertex(7, i, 0), grid_vertex(7, i + 1, 0));
                       for (int j = 0; j < 3; ++j) mesh.add_crease(grid_vertex(7, 0, j), grid_vertex(7, 0, j + 1));
                       mesh.add_crease(grid_vertex(7, 7, 2), grid_vertex(7, 7, 3), 2.0f);
                       mesh.add_crease(grid_vertex(7, 2, 3), grid_vertex(7, 3, 3), 1.5f);
                       mesh.add_corner(grid_vertex(7, 4, 2), 10.0f);
                       return mesh;
                   }});
    out.push_back({"grid_seam_boundary_none", [] {
                       TestMesh mesh = grid(7, 6);
                       jitter(mesh, 256, 0.02f);
                       mesh.boundary = Boundary::None;
                       add_uvs_with_seam(mesh);
                       return mesh;
                   }});
    out.push_back({"icosphere_hole_tags", [] {
                       TestMesh mesh = icosphere(2);
                       jitter(mesh, 255, 0.01f);
                       for (int f : {0, 1, 7, 40, 41, 42, 150}) mesh.hole_triangles.push_back(f);
                       return mesh;
                   }});
    return out;
}

class TessellationWithHolesAgainstBfr : public ::testing::TestWithParam<ShapeCase> {};

TEST_P(TessellationWithHolesAgainstBfr, FacesWithoutASurfaceAreLeftOut) {
    TestMesh mesh;
    try {
        mesh = GetParam().make();
    } catch (const PeerShapesMissing& missing) { GTEST_SKIP() << missing.what(); }
    const std::vector<bool> has_surface = bfr_faces_with_surface(mesh);
    // Some faces have no surface (on two of OpenSubdiv's shapes, none has one: the result is empty).
    ASSERT_LT(std::count(has_surface.begin(), has_surface.end(), true), mesh.num_triangles()) << GetParam().name;
    for (int uniform : {1, 2, 3, 5, -7}) {
        const RatesFor rates(mesh, uniform, 27);
        const Tessellation tessellation(mesh.view(), options_for(mesh), rates.view);
        const std::string where =
            GetParam().name + ", rate " + (uniform > 0 ? std::to_string(uniform) : "1.." + std::to_string(-uniform));
        std::vector<bool> tessellated(has_surface.size(), false);
        std::vector<bool> used(std::size_t(tessellation.num_points()), false);
        for (int t = 0; t < tessellation.num_triangles(); ++t) {
            tessellated[std::size_t(tessellation.parent_triangles()[t])] = true;
            for (int c = 0; c < 3; ++c) used[std::size_t(tessellation.triangles()[3 * t + c])] = true;
        }
        EXPECT_EQ(tessellated, has_surface) << where;
        EXPECT_TRUE(std::all_of(used.begin() + mesh.num_vertices(), used.end(), [](bool u) { return u; }))
            << where << ": a point no triangle has";
        std::vector<float> points(3 * std::size_t(tessellation.num_points()));
        tessellation.evaluate(mesh.positions.data(), points.data(), nullptr);
        for (std::size_t v = 0; v < std::size_t(mesh.num_vertices()); ++v) {
            if (used[v]) continue;
            for (std::size_t c = 0; c < 3; ++c)
                EXPECT_EQ(points[3 * v + c], mesh.positions[3 * v + c]) << where << ": vertex " << v;
        }
        const Errors errors = errors_against_bfr(mesh, tessellation);
        EXPECT_LE(errors.position, 1e-5) << where << ": position " << errors.position;
        EXPECT_LE(errors.angle, 1e-3) << where << ": normal " << errors.angle;
        if (mesh.triangle_uvs.empty()) continue;
        // A UV layer leaves out the same faces: its face points are the surface's, Bfr's face-varying surface.
        const Tessellation with_layer(mesh.view_with_uvs(), options_for(mesh), rates.view);
        ASSERT_EQ(with_layer.num_face_points(), tessellation.num_face_points()) << where;
        std::vector<float> values(2 * std::size_t(with_layer.num_face_points()));
        with_layer.evaluate_face_varying(0, mesh.uvs.data(), 2, values.data());
        const std::vector<BfrPoint> asked = face_points_of(with_layer).asked;
        const std::vector<double> expected = bfr_evaluate_face_varying(mesh, asked, options_for(mesh).face_varying);
        double worst = 0.0;
        for (std::size_t fp = 0; fp < asked.size(); ++fp)
            worst = std::max(worst,
                             std::hypot(values[2 * fp] - expected[2 * fp], values[2 * fp + 1] - expected[2 * fp + 1]));
        EXPECT_LE(worst, 1e-5) << where << ": UV";
    }
}

INSTANTIATE_TEST_SUITE_P(Shapes, TessellationWithHolesAgainstBfr, ::testing::ValuesIn(shapes_with_holes()),
                         case_name<ShapeCase>);

// Face-varying layers are Bfr's face-varying surfaces at the same parameters (within 1e-5 of the UVs' extent), in every
// mode, at uniform and random rates: a layer is cut as a mesh of its own, its values classified as a plan classifies
// them. The meshes: OpenSubdiv's Loop shapes that have UVs, and a UV seam across an icosphere with no creases, with
// infinitely sharp ones and with semi-sharp ones, across a grid with Keep Corners, and across a torus (the seam's ends
// are darts of the layer). CornersPlus1 / CornersPlus2 leave out the semi-sharp mesh: there Bfr differs from the
// refinement itself at a value held for its sibling's features (test_limit_bfr.cpp).
struct LayerCase {
    std::string name;
    std::function<TestMesh()> make;
    bool semi_sharp = false;
};
void PrintTo(const LayerCase& c, std::ostream* os) { *os << c.name; }

std::vector<LayerCase> layer_shapes() {
    std::vector<LayerCase> out;
    for (const ShapeCase& shape : shapes()) {
        if (shape.name == "loop_pole8" || shape.name == "torus_semisharp" || shape.name == "grid_creases_and_corners")
            continue;  // no UVs
        out.push_back(
            {shape.name, shape.make,
             shape.name.find("semisharp") != std::string::npos || shape.name.find("chaikin") != std::string::npos});
    }
    out.push_back({"icosphere_seam", [] {
                       TestMesh mesh = icosphere(2);
                       jitter(mesh, 71, 0.01f);
                       add_uvs_with_seam(mesh);
                       return mesh;
                   }});
    out.push_back({"icosphere_seam_creases", [] {
                       TestMesh mesh = icosphere(2);
                       jitter(mesh, 72, 0.01f);
                       add_random_creases(mesh, 72, 0.15, false);
                       add_uvs_with_seam(mesh);
                       return mesh;
                   }});
    out.push_back({"icosphere_seam_semisharp",
                   [] {
                       TestMesh mesh = icosphere(2);
                       jitter(mesh, 61, 0.01f);
                       add_random_creases(mesh, 61, 0.2, true);
                       add_uvs_with_seam(mesh);
                       return mesh;
                   },
                   true});
    out.push_back({"grid_seam_keep_corners", [] {
                       TestMesh mesh = grid(6, 5);
                       jitter(mesh, 73, 0.02f);
                       mesh.boundary = Boundary::EdgesAndCorners;
                       add_uvs_with_seam(mesh);
                       return mesh;
                   }});
    out.push_back({"torus_seam", [] {
                       TestMesh mesh = torus(8, 6);
                       jitter(mesh, 74, 0.02f);
                       add_uvs_with_seam(mesh);
                       return mesh;
                   }});
    return out;
}

class TessellationLayerAgainstBfr : public ::testing::TestWithParam<LayerCase> {};

TEST_P(TessellationLayerAgainstBfr, LayersAreBfrsFaceVaryingSurfaces) {
    TestMesh mesh;
    try {
        mesh = GetParam().make();
    } catch (const PeerShapesMissing& missing) { GTEST_SKIP() << missing.what(); }
    ASSERT_FALSE(mesh.triangle_uvs.empty()) << GetParam().name << " has no UVs";
    const FaceVaryingLayer layer{mesh.triangle_uvs.data(), int(mesh.uvs.size() / 2)};
    MeshView view = mesh.view();
    view.face_varying = &layer, view.num_face_varying = 1;
    float low[2] = {INFINITY, INFINITY}, high[2] = {-INFINITY, -INFINITY};
    for (std::size_t i = 0; i < mesh.uvs.size(); ++i)
        low[i % 2] = std::min(low[i % 2], mesh.uvs[i]), high[i % 2] = std::max(high[i % 2], mesh.uvs[i]);
    const double extent = std::hypot(high[0] - low[0], high[1] - low[1]);
    // At an input dart (one infinitely sharp edge) Bfr's surface is not the limit: refinement converges to ours there
    // (an icosahedron's dart, refined 6, 8 and 9 levels: 9e-4, 2e-4 and 8e-5 from ours, each step about half the last),
    // while Bfr's point lies 1e-3 of the diagonal off. Those points are left out.
    std::vector<bool> at_dart(std::size_t(mesh.num_vertices()), false);
    {
        std::vector<int> sharp_edges(std::size_t(mesh.num_vertices()), 0);
        for (std::size_t e = 0; e < mesh.crease_sharpness.size(); ++e)
            if (mesh.crease_sharpness[e] >= kInfiniteSharpness)
                ++sharp_edges[std::size_t(mesh.crease_edges[2 * e])],
                    ++sharp_edges[std::size_t(mesh.crease_edges[2 * e + 1])];
        for (std::size_t v = 0; v < at_dart.size(); ++v) at_dart[v] = sharp_edges[v] == 1;
    }
    using Mode = FaceVaryingInterpolation;
    for (Mode mode :
         {Mode::None, Mode::CornersOnly, Mode::CornersPlus1, Mode::CornersPlus2, Mode::Boundaries, Mode::All}) {
        if (GetParam().semi_sharp && (mode == Mode::CornersPlus1 || mode == Mode::CornersPlus2)) continue;
        for (int uniform : {2, 4, 3, -6}) {
            const RatesFor rates(mesh, uniform, 26);
            Options options = options_for(mesh);
            options.face_varying = mode;
            const Tessellation tessellation(view, options, rates.view);
            ASSERT_EQ(tessellation.num_face_varying_layers(), 1);
            std::vector<float> values(2 * std::size_t(tessellation.num_face_points()));
            tessellation.evaluate_face_varying(0, mesh.uvs.data(), 2, values.data());
            const auto [asked, point_of] = face_points_of(tessellation);
            const std::vector<double> expected = bfr_evaluate_face_varying(mesh, asked, mode);
            double worst = 0.0;
            for (std::size_t fp = 0; fp < asked.size(); ++fp)
                if (point_of[fp] >= mesh.num_vertices() || !at_dart[std::size_t(point_of[fp])])
                    worst = std::max(worst, std::hypot(values[2 * fp] - expected[2 * fp],
                                                       values[2 * fp + 1] - expected[2 * fp + 1]) /
                                                extent);
            EXPECT_LE(worst, 1e-5) << GetParam().name << ", mode " << int(mode) << ", rate "
                                   << (uniform > 0 ? std::to_string(uniform) : "1.." + std::to_string(-uniform));
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Shapes, TessellationLayerAgainstBfr, ::testing::ValuesIn(layer_shapes()),
                         case_name<LayerCase>);

// The largest distance, over the bounding box's diagonal, from the tessellation's points at `rate` to the limit that
// OpenSubdiv alone computes (far_refined_limit, 8 levels down); and from Bfr's points to it.
std::pair<double, double> worst_from_refined_limit(const TestMesh& mesh, int rate) {
    const TessellationRates rates{rate};
    const Tessellation tessellation(mesh.view(), options_for(mesh), rates);
    std::vector<float> points(3 * std::size_t(tessellation.num_points()));
    tessellation.evaluate(mesh.positions.data(), points.data(), nullptr);
    const auto [asked, point_of] = face_points_of(tessellation);
    const std::vector<double> expected = far_refined_limit(mesh, asked, 8);
    const BfrLimit bfr = bfr_evaluate(mesh, asked);
    double worst = 0.0, bfr_worst = 0.0;
    for (std::size_t fp = 0; fp < asked.size(); ++fp) {
        double d2 = 0.0, bfr_d2 = 0.0;
        for (std::size_t c = 0; c < 3; ++c) {
            d2 += std::pow(points[3 * std::size_t(point_of[fp]) + c] - expected[3 * fp + c], 2);
            bfr_d2 += std::pow(bfr.positions[3 * fp + c] - expected[3 * fp + c], 2);
        }
        worst = std::max(worst, std::sqrt(d2));
        bfr_worst = std::max(bfr_worst, std::sqrt(bfr_d2));
    }
    const double diagonal = bounding_box_diagonal(mesh.positions);
    return {worst / diagonal, bfr_worst / diagonal};
}

// An interior vertex of valence 2 has its two faces on the same three vertices (a pillow), and so has every level's
// vertex there: the two edges between its neighbours, one inside each face, share their ends. A regular patch beside
// it walks its rings by the split's edges, not their ends (which took those edges for one of four faces, and the patch
// for irregular: 8e-4 of the diagonal off at rate 3). The truth, computed by OpenSubdiv alone: Far's uniform
// refinement 8 levels down, at the limit (far_refined_limit, linear inside the last level: 7 levels down is within
// 2e-6 of 9). Bfr agrees with it at every rate. The pillow's surface folds onto its own plane: its normals are no
// test.
TEST(Tessellation, AtAnInteriorVertexOfValenceTwoNonDyadicRatesAreTheRefinedLimit) {
    TestMesh pillow;
    pillow.positions = {0, 0, 0, 1, 0.1f, 0.2f, 0.2f, 1, -0.1f};
    pillow.triangles = {0, 1, 2, 0, 2, 1};
    TestMesh attached = pillow_on_icosahedron().mesh;
    for (const TestMesh* mesh : {&pillow, &attached}) {
        for (int rate : {3, 4, 6}) {
            const auto [worst, bfr_worst] = worst_from_refined_limit(*mesh, rate);
            const std::string where = (mesh == &pillow ? "pillow" : "pillow on an icosahedron") +
                                      std::string(", rate ") + std::to_string(rate);
            EXPECT_LE(worst, 2e-6) << where;
            EXPECT_LE(bfr_worst, 2e-6) << where << ": Bfr";
        }
    }
}

// Semi-sharp creases near a valence-2 vertex: the pillow on an icosahedron's vertex with a crease on an icosahedron
// edge at the pillow, or along one of the pillow's own edges from its valence-2 vertex. Two edges of a refined level
// share their ends there (the edges inside the pillow's two faces), and two readings of the level must keep them
// apart. The limit of a vertex beside them whose crease outlasts the level (rate 6's midpoint of a crease of
// sharpness 1.5, a vertex of level 1) was off by 2.2e-2 of the diagonal where its ring's two places on one
// neighbour were read as one. A triangle's neighbourhood refined on its own (the crease of sharpness 3.5, rates 3
// and 6) was off by up to 6.3e-4 where its plan read the two edges as one edge of four faces, sharp.
TEST(Tessellation, SemiSharpCreasesNearAValenceTwoVertexAreTheRefinedLimit) {
    const PillowOnIcosahedron attached = pillow_on_icosahedron();
    struct Case {
        std::int32_t a, b;
        float sharpness;
        const char* name;
    };
    const Case cases[] = {{attached.apex, attached.mesh.triangles[1], 1.5f, "beside"},
                          {attached.v, attached.apex, 1.5f, "along"},
                          {attached.v, attached.v + 1, 1.2f, "along the other edge"},
                          {attached.v, attached.apex, 3.5f, "along, sharper"}};
    for (const Case& c : cases) {
        TestMesh mesh = attached.mesh;
        mesh.add_crease(c.a, c.b, c.sharpness);
        for (int rate : {3, 4, 6})
            EXPECT_LE(worst_from_refined_limit(mesh, rate).first, 2e-6) << c.name << ", rate " << rate;
    }
}

// A plan's limit surface there: each vertex of a level-1 plan of that pillow, creased along its edge from the
// valence-2 vertex (sharpness 1.5, which outlasts the level), is the refined limit at its place on its input
// triangle. The creased edge's midpoint was off by 2.2e-2 of the diagonal (its ring's two places on one neighbour
// read as one).
TEST(LimitSurface, BesideAValenceTwoVertexIsTheRefinedLimit) {
    const PillowOnIcosahedron attached = pillow_on_icosahedron();
    TestMesh mesh = attached.mesh;
    mesh.add_crease(attached.v, attached.apex, 1.5f);
    Options options = options_for(mesh);
    options.levels = 1, options.limit_surface = true;
    Plan plan(mesh.view(), options);
    std::vector<float> points(3 * std::size_t(plan.num_output_vertices()));
    plan.evaluate(interleaved(mesh.positions.data(), 3), interleaved(points.data(), 3));
    // Child k < 3 of input triangle f is plan triangle 4f + k, (corner k, midpoint of edge k, midpoint of edge k - 1);
    // child 3 joins the midpoints. The places: the corners, then the midpoints of edges 0 to 2.
    const double place[6][2] = {{0, 0}, {1, 0}, {0, 1}, {0.5, 0}, {0.5, 0.5}, {0, 0.5}};
    std::vector<BfrPoint> asked;
    std::vector<std::int32_t> vertex;
    for (int t = 0; t < plan.num_output_triangles(); ++t) {
        const int k = t % 4, at[3] = {k < 3 ? k : 3, k < 3 ? 3 + k : 4, k < 3 ? 3 + (k + 2) % 3 : 5};
        for (int c = 0; c < 3; ++c) {
            asked.push_back({plan.output_parent_triangles()[t], place[at[c]][0], place[at[c]][1]});
            vertex.push_back(plan.output_triangles()[3 * t + c]);
        }
    }
    const std::vector<double> expected = far_refined_limit(mesh, asked, 8);
    double worst = 0.0;
    for (std::size_t i = 0; i < asked.size(); ++i) {
        double d2 = 0.0;
        for (std::size_t c = 0; c < 3; ++c)
            d2 += std::pow(points[3 * std::size_t(vertex[i]) + c] - expected[3 * i + c], 2);
        worst = std::max(worst, std::sqrt(d2));
    }
    EXPECT_LE(worst / bounding_box_diagonal(mesh.positions), 2e-6);
}

// On a closed mesh every edge of the result has exactly two triangles and V - E + F stays the input's: no crack,
// whatever the rates, and each point on an input edge is one point.
TEST(Tessellation, ClosedMeshesStayClosedForAnyRates) {
    for (unsigned seed = 0; seed < 12; ++seed) {
        TestMesh mesh = seed % 2 ? icosphere(1) : torus(6, 5);
        jitter(mesh, seed, 0.02f);
        const RatesFor rates(mesh, -int(2 + seed), seed);
        const Tessellation tessellation(mesh.view(), options_for(mesh), rates.view);
        std::map<std::pair<int, int>, int> uses;
        const std::int32_t* t = tessellation.triangles();
        for (int f = 0; f < tessellation.num_triangles(); ++f) {
            ASSERT_TRUE(t[3 * f] != t[3 * f + 1] && t[3 * f + 1] != t[3 * f + 2] && t[3 * f + 2] != t[3 * f]);
            for (int c = 0; c < 3; ++c) {
                const int a = t[3 * f + c], b = t[3 * f + (c + 1) % 3];
                ++uses[{std::min(a, b), std::max(a, b)}];
            }
        }
        for (const auto& [edge, count] : uses) ASSERT_EQ(count, 2) << "seed " << seed << ": edge " << edge.first;
        const int euler = tessellation.num_points() - int(uses.size()) + tessellation.num_triangles();
        EXPECT_EQ(euler, seed % 2 ? 2 : 0) << "seed " << seed;
    }
}

// Two triangles on the same three vertices, facing apart (a closed "pillow", which fuzz_tessellation met): each gets
// its whole lattice, the points on their shared edges once, every point finite. (The lattice edges between two edges'
// points at a corner then join the same two points in both triangles: output_edges gives them one edge with four
// triangles, as a mesh of vertex pairs must.)
TEST(Tessellation, TwoTrianglesOnTheSameThreeVerticesEachGetTheirLattice) {
    TestMesh mesh;
    mesh.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    mesh.triangles = {0, 1, 2, 0, 2, 1};
    const TessellationRates rates{5};
    const Tessellation tessellation(mesh.view(), options_for(mesh), rates);
    EXPECT_EQ(tessellation.num_triangles(), 2 * 25);
    EXPECT_EQ(tessellation.num_points(), 3 + 3 * 4 + 2 * 6);
    std::vector<float> points(3 * std::size_t(tessellation.num_points()));
    std::vector<float> normals(3 * std::size_t(tessellation.num_face_points()));
    tessellation.evaluate(mesh.positions.data(), points.data(), normals.data());
    for (float x : points) ASSERT_TRUE(std::isfinite(x));
    const Tessellation::Edges edges = tessellation.output_edges();
    EXPECT_EQ(edges.triangle_edges.size(), 3 * std::size_t(tessellation.num_triangles()));
}

// output_edges names each side of each triangle by the edge with its two ends, the same edge for both triangles on it
// and a different one for every other pair of ends, on closed and open meshes.
TEST(Tessellation, OutputEdgesAreEachPairOfEndsOnce) {
    for (unsigned seed = 0; seed < 6; ++seed) {
        TestMesh mesh = seed % 3 == 0 ? icosphere(1) : seed % 3 == 1 ? torus(6, 5) : grid(4, 3);
        const RatesFor rates(mesh, -int(2 + seed), seed);
        const Tessellation tessellation(mesh.view(), options_for(mesh), rates.view);
        const Tessellation::Edges edges = tessellation.output_edges();
        const std::int32_t* t = tessellation.triangles();
        ASSERT_EQ(edges.triangle_edges.size(), 3 * std::size_t(tessellation.num_triangles()));
        std::map<std::pair<int, int>, int> edge_of;
        for (int f = 0; f < tessellation.num_triangles(); ++f)
            for (int c = 0; c < 3; ++c) {
                const int a = t[3 * f + c], b = t[3 * f + (c + 1) % 3];
                const int e = edges.triangle_edges[3 * std::size_t(f) + std::size_t(c)];
                ASSERT_GE(e, 0);
                ASSERT_LT(std::size_t(e), edges.edge_vertices.size() / 2);
                const int u = edges.edge_vertices[2 * std::size_t(e)], v = edges.edge_vertices[2 * std::size_t(e) + 1];
                ASSERT_EQ(std::minmax(u, v), std::minmax(a, b)) << "seed " << seed << " triangle " << f;
                const auto [at, added] = edge_of.emplace(std::minmax(a, b), e);
                ASSERT_EQ(at->second, e) << "seed " << seed << ": two numbers for one edge";
            }
        EXPECT_EQ(edge_of.size(), edges.edge_vertices.size() / 2) << "seed " << seed << ": an edge no triangle has";
    }
}

TEST(Tessellation, RateTwoToTheLGivesLevelLOnTheLimitSurface) {
    TestMesh mesh = icosphere(1);
    jitter(mesh, 253, 0.03f);
    mesh.add_crease(0, mesh.triangles[1], 1.5f);
    for (int levels = 0; levels <= 3; ++levels) {
        TessellationRates rates;
        rates.uniform_rate = 1 << levels;
        const Tessellation tessellation(mesh.view(), options_for(mesh), rates);
        Options options = options_for(mesh);
        options.levels = levels, options.limit_surface = true;
        Plan plan(mesh.view(), options);
        ASSERT_EQ(tessellation.num_points(), plan.num_output_vertices());
        ASSERT_EQ(tessellation.num_triangles(), plan.num_output_triangles());
        std::vector<float> ours(3 * std::size_t(tessellation.num_points())), refined(ours.size());
        tessellation.evaluate(mesh.positions.data(), ours.data(), nullptr);
        plan.evaluate(interleaved(mesh.positions.data(), 3), interleaved(refined.data(), 3));
        // The same points, each within 1e-6 of the diagonal of one of the refinement's (a regular input triangle's
        // come from its box spline, not the limit masks: the same numbers but for rounding).
        const double tolerance = 1e-6 * bounding_box_diagonal(mesh.positions);
        std::vector<char> matched(refined.size() / 3, 0);
        int unmatched = 0;
        for (std::size_t i = 0; i < ours.size() / 3; ++i) {
            bool found = false;
            for (std::size_t j = 0; j < matched.size() && !found; ++j) {
                double d2 = 0.0;
                for (int c = 0; c < 3; ++c) d2 += std::pow(double(ours[3 * i + c]) - refined[3 * j + c], 2);
                if (!matched[j] && std::sqrt(d2) <= tolerance) matched[j] = 1, found = true;
            }
            unmatched += !found;
        }
        EXPECT_EQ(unmatched, 0) << "level " << levels;
    }
}

// The patch kernels (kernels.h, PatchFn): SSE4.1 gives the scalar reference's bits (the same sums in the same order);
// AVX2 fuses its multiply-adds, within rounding of them. A kernel the CPU lacks steps down to one it has.
TEST(Tessellation, EveryKernelPlacesThePointsOfTheScalarOne) {
    TestMesh mesh = icosphere(2);
    jitter(mesh, 256, 0.02f);
    mesh.add_crease(0, mesh.triangles[1]);
    const RatesFor rates(mesh, -11, 27);
    std::vector<float> points[3], normals[3];
    const Kernel kernels[3] = {Kernel::Scalar, Kernel::SSE41, Kernel::AVX2};
    for (int k = 0; k < 3; ++k) {
        Options options = options_for(mesh);
        options.kernel = kernels[k];
        const Tessellation t(mesh.view(), options, rates.view);
        points[k].resize(3 * std::size_t(t.num_points())), normals[k].resize(3 * std::size_t(t.num_face_points()));
        t.evaluate(mesh.positions.data(), points[k].data(), normals[k].data());
    }
    EXPECT_EQ(points[1], points[0]);
    EXPECT_EQ(normals[1], normals[0]);
    for (std::size_t i = 0; i < points[0].size(); ++i) ASSERT_NEAR(points[2][i], points[0][i], 1e-6) << i;
    for (std::size_t i = 0; i < normals[0].size(); ++i) ASSERT_NEAR(normals[2][i], normals[0][i], 1e-5) << i;
}

TEST(Tessellation, TwoThreadsPlaceTheSamePoints) {
    TestMesh mesh = icosphere(2);
    jitter(mesh, 255, 0.02f);
    mesh.add_crease(0, mesh.triangles[1], 2.5f);
    for (int uniform : {7, 8, -9}) {
        const RatesFor rates(mesh, uniform, 26);
        Options one = options_for(mesh), two = one;
        two.threads = 2;
        const Tessellation a(mesh.view(), one, rates.view), b(mesh.view(), two, rates.view);
        std::vector<float> points[2], normals[2];
        for (int k = 0; k < 2; ++k) {
            const Tessellation& t = k == 0 ? a : b;
            points[k].resize(3 * std::size_t(t.num_points())), normals[k].resize(3 * std::size_t(t.num_face_points()));
            t.evaluate(mesh.positions.data(), points[k].data(), normals[k].data());
        }
        EXPECT_EQ(points[0], points[1]) << uniform;
        EXPECT_EQ(normals[0], normals[1]) << uniform;
    }
}

// A cut at new rates that reuses an earlier cut's input topology is the cut made anew, bit for bit: its triangles,
// face points, parameters, points, normals and UV layer. Also where the earlier cut was of another mesh (other tags,
// another triangle), so that nothing of it may be taken; and with the earlier cut gone first.
TEST(Tessellation, AtNewRatesReusingTheInputTopologyIsTheCutMadeAnew) {
    TestMesh mesh = icosphere(2);
    jitter(mesh, 91, 0.02f);
    add_random_creases(mesh, 91, 0.1, true);
    add_uvs_with_seam(mesh);
    const FaceVaryingLayer layer{mesh.triangle_uvs.data(), int(mesh.uvs.size() / 2)};
    const Options options = options_for(mesh);
    auto view_of = [&layer](const TestMesh& m) {
        MeshView view = m.view();
        view.face_varying = &layer, view.num_face_varying = 1;
        return view;
    };
    TestMesh other_tags = mesh;
    other_tags.crease_sharpness[0] += 1.0f;
    TestMesh other_triangles = mesh;
    std::swap(other_triangles.triangles[0], other_triangles.triangles[1]);  // turned over: another mesh
    std::swap(other_triangles.triangle_uvs[0], other_triangles.triangle_uvs[1]);
    for (const TestMesh* earlier : {&mesh, &other_tags, &other_triangles}) {
        InputTopology kept;
        {
            const RatesFor rates(*earlier, -6, 31);
            kept = Tessellation(view_of(*earlier), options, rates.view).input_topology();
        }
        ASSERT_FALSE(kept.empty());
        for (int uniform : {-9, 5}) {
            const RatesFor rates(mesh, uniform, 32);
            const Tessellation anew(view_of(mesh), options, rates.view);
            const Tessellation reused(view_of(mesh), options, rates.view, kept);
            ASSERT_EQ(reused.num_triangles(), anew.num_triangles());
            ASSERT_EQ(reused.num_face_points(), anew.num_face_points());
            const std::size_t corners = 3 * std::size_t(anew.num_triangles());
            EXPECT_TRUE(std::equal(anew.triangles(), anew.triangles() + corners, reused.triangles()));
            EXPECT_TRUE(std::equal(anew.corner_face_points(), anew.corner_face_points() + corners,
                                   reused.corner_face_points()));
            EXPECT_TRUE(std::equal(anew.face_point_parameters(),
                                   anew.face_point_parameters() + 2 * std::size_t(anew.num_face_points()),
                                   reused.face_point_parameters()));
            std::vector<float> points[2], normals[2], uvs[2];
            for (int k = 0; k < 2; ++k) {
                const Tessellation& t = k == 0 ? anew : reused;
                points[k].resize(3 * std::size_t(t.num_points()));
                normals[k].resize(3 * std::size_t(t.num_face_points()));
                uvs[k].resize(2 * std::size_t(t.num_face_points()));
                t.evaluate(mesh.positions.data(), points[k].data(), normals[k].data());
                t.evaluate_face_varying(0, mesh.uvs.data(), 2, uvs[k].data());
            }
            EXPECT_EQ(points[0], points[1]) << uniform;
            EXPECT_EQ(normals[0], normals[1]) << uniform;
            EXPECT_EQ(uvs[0], uvs[1]) << uniform;
        }
    }
}

// A camera at the origin looking down -z, OpenGL's perspective with a 90 degree field of view (f = 1), a viewport of
// 100 x 100 pixels: a point (x, y, z) in view lands at pixel 50 (1 + x / -z) across.
Camera camera_down_z() {
    const float near = 0.1f, far = 100.0f;
    Camera camera;
    const float m[16] = {1, 0, 0,  0, 0, 1, 0, 0, 0, 0, (far + near) / (near - far), 2 * far * near / (near - far),
                         0, 0, -1, 0};
    std::copy(m, m + 16, camera.world_to_clip);
    camera.viewport_width = camera.viewport_height = 100.0f;
    return camera;
}

TEST(ScreenRates, AnEdgeIsCutIntoItsLengthOnScreenInSegments) {
    // Three triangles: one facing the camera at distance 2, one far off to the side (out of view, as deep), one
    // reaching behind the camera.
    MeshData mesh;
    mesh.positions = {-0.5f, 0,  -2, 0.5f, 0,  -2, 0,  0.5f, -2,  // 0-1: 1 unit at distance 2: 25 pixels
                      40,    0,  -2, 41,   0,  -2, 40, 1,    -2,  // 3-4: 25 pixels, all right of the view
                      0,     -1, -2, 0,    -1, 3,  1,  -1,   3};  // 6-7 runs behind the camera; 7-8 lies behind it
    mesh.triangles = {0, 1, 2, 3, 4, 5, 6, 7, 8};
    const ScreenRates rates = screen_space_rates(mesh.view(), mesh.positions.data(), camera_down_z(), 4.0f, 64);
    auto rate_of = [&](int a, int b) {
        for (std::size_t e = 0; e < rates.rates.size(); ++e)
            if (std::minmax(rates.edges[2 * e], rates.edges[2 * e + 1]) == std::minmax(a, b)) return rates.rates[e];
        return -1;
    };
    EXPECT_EQ(rates.rates.size(), 9u);
    EXPECT_EQ(rate_of(0, 1), 7);  // 25 / 4 = 6.25
    // As Cycles measures, at the midpoint's distance from the camera, not its depth: (40.5, 0, -2) is 40.55 away,
    // where a unit is 50 / 40.55 = 1.23 pixels; 1.23 / 4 = 0.31, and / 4 off screen.
    EXPECT_EQ(rate_of(3, 4), 1);
    // Midpoint (0, -1, 0.5), behind the camera, 1.118 away: 5 units are 223.6 pixels there, 55.9 / 4 off screen
    // = 13.98.
    EXPECT_EQ(rate_of(6, 7), 14);
    EXPECT_EQ(rate_of(7, 8), 1);
    // Farther away, fewer segments; never below one.
    const ScreenRates coarse = screen_space_rates(mesh.view(), mesh.positions.data(), camera_down_z(), 100.0f, 64);
    for (int rate : coarse.rates) EXPECT_GE(rate, 1);
    EXPECT_THROW(screen_space_rates(mesh.view(), mesh.positions.data(), camera_down_z(), 0.0f, 64), InputError);
    // A bent pair of faces, 2 units from the camera, by deviation: each edge's bulge is its new point off the chord of
    // its ends' new points after one split. The middle edge 0-1 runs straight: 3/8 (a + b) + 1/8 (c + d) against
    // ends moved to 3/4 a + 1/8 (c + d) and 3/4 b + 1/8 (c + d) along the boundary, 0. A boundary edge, 0-2: its
    // midpoint against 3/4 v0 + 1/8 (v2 + v3) and 3/4 v2 + 1/8 (v0 + v1), (v0 + v2 - v1 - v3) / 16 = (-1, 2, 0) / 16,
    // 0.140 long, at its midpoint's depth 1.75 3.99 pixels: sqrt(3.99 / 0.1) = 6.3 -> 7 segments; so are the three
    // others, by symmetry. Edge 0-1 is raised to its triangles' 7.
    MeshData bent;
    bent.positions = {-0.5f, 0, -2, 0.5f, 0, -2, 0, 1, -1.5f, 0, -1, -1.5f};
    bent.triangles = {0, 1, 2, 1, 0, 3};
    const ScreenRates bulge =
        screen_space_rates(bent.view(), bent.positions.data(), camera_down_z(), 0.1f, 64, DicingMeasure::Deviation);
    ASSERT_EQ(bulge.rates.size(), 5u);
    for (int rate : bulge.rates) EXPECT_EQ(rate, 7);
    EXPECT_THROW(screen_space_rates(mesh.view(), mesh.positions.data(), camera_down_z(), 1.0f, 0), InputError);
    // A tessellation at these rates: per triangle its inner rate's lattice, or (rates differing) the inner lattice
    // of rate n - 3 and a strip of r + n - 3 triangles along each edge of rate r (a fan of r around the centre below
    // an inner rate of 3).
    const Tessellation tessellation(mesh.view(), Options{}, rates.view());
    int expected = 0;
    for (int f = 0; f < 3; ++f) {
        int r[3];
        for (int k = 0; k < 3; ++k) r[k] = rate_of(mesh.triangles[3 * f + k], mesh.triangles[3 * f + (k + 1) % 3]);
        const int n = std::max({r[0], r[1], r[2]});
        if (r[0] == n && r[1] == n && r[2] == n) expected += n * n;
        else if (n >= 3) expected += (n - 3) * (n - 3) + (r[0] + n - 3) + (r[1] + n - 3) + (r[2] + n - 3);
        else expected += r[0] + r[1] + r[2];
    }
    EXPECT_EQ(tessellation.num_triangles(), expected);
}

// An icosahedron with a UV layer that has a seam; view() carries the layer.
struct IcosahedronWithLayer {
    IcosahedronWithLayer() : mesh(icosahedron()) {
        add_uvs_with_seam(mesh);
        layer = {mesh.triangle_uvs.data(), int(mesh.uvs.size() / 2)};
    }
    MeshView view() const {
        MeshView with_layer = mesh.view();
        with_layer.face_varying = &layer, with_layer.num_face_varying = 1;
        return with_layer;
    }
    TestMesh mesh;
    FaceVaryingLayer layer;
};

// The memory limit is one budget for everything a tessellation holds: its result, the plans of the triangles that are
// no patch (an icosahedron has no regular vertex: all of it), each face-varying layer's own cut. A limit one byte below
// what it counted refuses it; a limit that covers the result but not the plans did not, before.
TEST(Tessellation, OneMemoryBudgetCoversItsPlansAndLayers) {
    const IcosahedronWithLayer icosahedron_with_layer;
    const TestMesh& mesh = icosahedron_with_layer.mesh;
    const MeshView with_layer = icosahedron_with_layer.view();
    TessellationRates rates;
    rates.uniform_rate = 32;  // level 5
    const Options options = options_for(mesh);
    const Tessellation plain(mesh.view(), options, rates), layered(with_layer, options, rates);
    ASSERT_EQ(plain.levels(), 5);
    // The band's two plans, limit and control points, on the whole icosahedron, at level 5.
    const std::uint64_t plans = 2 * Plan::estimate_bytes(mesh.num_vertices(), mesh.num_triangles(), 5, 3, 30);
    EXPECT_GT(plain.estimated_bytes(), plans);
    EXPECT_GT(layered.estimated_bytes(), plain.estimated_bytes() + plans);  // the layer's cut has its own band
    for (const auto& [view, counted] :
         {std::pair(mesh.view(), plain.estimated_bytes()), std::pair(with_layer, layered.estimated_bytes())}) {
        Options limited = options;
        limited.memory_limit_bytes = counted;
        EXPECT_EQ(Tessellation(view, limited, rates).estimated_bytes(), counted);
        limited.memory_limit_bytes = counted - 1;
        try {
            Tessellation(view, limited, rates);
            ADD_FAILURE() << "made within a limit one byte below its count";
        } catch (const MemoryLimitError& error) { EXPECT_EQ(error.required_bytes, counted) << error.what(); }
    }
}

// A patch of the triangular lattice of unit edges, rows j = -3..3 and columns i = -4..4 (vertex (i, j) at
// x = i + j / 2, y = j sqrt(3) / 2), lifted to z = height(x, y) - 4 before camera_down_z. Edge (0, 0)-(1, 0) runs
// along x through the middle, its ends interior with six neighbours.
MeshData lattice(const std::function<double(double, double)>& height) {
    MeshData mesh;
    for (int j = -3; j <= 3; ++j)
        for (int i = -4; i <= 4; ++i) {
            const double x = i + 0.5 * j, y = 0.8660254037844386 * j;
            mesh.positions.insert(mesh.positions.end(), {float(x), float(y), float(height(x, y) - 4.0)});
        }
    auto at = [](int i, int j) { return (j + 3) * 9 + (i + 4); };
    for (int j = -3; j < 3; ++j)
        for (int i = -4; i < 4; ++i) {
            mesh.triangles.insert(mesh.triangles.end(), {at(i, j), at(i + 1, j), at(i, j + 1)});
            mesh.triangles.insert(mesh.triangles.end(), {at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    return mesh;
}

int lattice_rate(const ScreenRates& rates, int a, int b) {
    for (std::size_t e = 0; e < rates.rates.size(); ++e)
        if (std::minmax(rates.edges[2 * e], rates.edges[2 * e + 1]) == std::minmax(a, b)) return rates.rates[e];
    return -1;
}

// By deviation an edge is held to how far its segments stray from the surface along it. On z = x^2 + y^2 / 3 the
// middle edge a-b along x (h = 1, t = x): its new point is 3/8 (0 + 1) + 1/8 (0.5 + 0.5) = 1/2 high; its ends' new
// points 1/16 of their six neighbours' heights above them, 1/16 (1 + 1 + 4 (1/4 + 1/4)) = 1/4 (the Hessian's trace
// 8/3 times 3/2): the chord between them at 1/2 + 1/4, so the bulge is 1/4, (h^2 / 8) t'Ht. At the midpoint's distance
// 3.54 (0.5 across, 3.5 deep), 0.25 * 50 / 3.54 = 3.54 pixels: sqrt(3.54 / 0.2) = 4.2 -> 5 segments. The midpoint's
// distance from the old ends' midpoint, (c + d - a - b) / 8, is 0 there: blind to the curve along the edge. An edge
// whose ends' coordinates sum past the float range (each end finite, the edge itself short) is measured at its midpoint
// all the same: a rate between 1 and the cap, by length and by deviation, not a NaN made an integer (the fuzzer's find:
// the midpoint was half of an overflowed sum).
TEST(ScreenRates, AnEdgeFarOutIsMeasuredAtAFiniteMidpoint) {
    const float far_out = 3.0e38f;
    MeshData mesh;
    mesh.positions = {far_out, 0, -2, far_out, 1, -2, far_out, 0, -3};
    mesh.triangles = {0, 1, 2};
    for (DicingMeasure measure : {DicingMeasure::Length, DicingMeasure::Deviation}) {
        const ScreenRates rates =
            screen_space_rates(mesh.view(), mesh.positions.data(), camera_down_z(), 1.0f, 64, measure);
        ASSERT_EQ(rates.rates.size(), 3u);
        for (int rate : rates.rates) {
            EXPECT_GE(rate, 1);
            EXPECT_LE(rate, 64);
        }
    }
}

// An edge beside the camera, out of the picture at depth 1, is about as far away as one 10 units ahead: a quarter of
// its segments (the off-screen scale), where by depth it would take ten times theirs. 1 unit at distance 10 is 5
// pixels, 20 segments of 0.25 pixels ahead; at 10.05, 19.9 / 4 = 4.97 beside (by depth: 200 / 4 = 50).
TEST(ScreenRates, AnEdgeBesideTheCameraIsMeasuredAtItsDistance) {
    MeshData mesh;
    mesh.positions = {-0.5f, 0,     -10, 0.5f, 0,    -10, 0,  0.5f, -10,     // ahead, in view
                      10,    -0.5f, -1,  10,   0.5f, -1,  10, 0,    -1.5f};  // beside, out of view
    mesh.triangles = {0, 1, 2, 3, 4, 5};
    const ScreenRates rates = screen_space_rates(mesh.view(), mesh.positions.data(), camera_down_z(), 0.25f, 64);
    EXPECT_EQ(lattice_rate(rates, 0, 1), 20);
    EXPECT_EQ(lattice_rate(rates, 3, 4), 5);
}

// A matrix whose frame cannot be told apart (an x or y row along the w row, or none at all) is measured at the
// depth, as an orthographic one: every rate between 1 and the cap, never a NaN made an integer.
TEST(ScreenRates, AProjectionWithoutAFrameIsMeasuredAtItsDepth) {
    MeshData mesh;
    mesh.positions = {0, 0, -2, 1, 0, -2, 0, 1, -2};
    mesh.triangles = {0, 1, 2};
    Camera along = camera_down_z(), flat = camera_down_z();
    std::copy(along.world_to_clip + 12, along.world_to_clip + 16, along.world_to_clip);  // x row = w row
    std::fill(flat.world_to_clip, flat.world_to_clip + 8, 0.0f);                         // no x or y row
    for (const Camera& camera : {along, flat})
        for (DicingMeasure measure : {DicingMeasure::Length, DicingMeasure::Deviation}) {
            const ScreenRates rates = screen_space_rates(mesh.view(), mesh.positions.data(), camera, 1.0f, 64, measure);
            ASSERT_EQ(rates.rates.size(), 3u);
            for (int rate : rates.rates) {
                EXPECT_GE(rate, 1);
                EXPECT_LE(rate, 64);
            }
        }
    // Along: its y row still measures 1 unit at depth 2 as 25 pixels, as the matrix said before.
    const ScreenRates along_rates = screen_space_rates(mesh.view(), mesh.positions.data(), along, 1.0f, 64);
    EXPECT_EQ(lattice_rate(along_rates, 0, 1), 25);
}

TEST(ScreenRates, ByDeviationAnEdgeIsHeldToItsCurveAlongIt) {
    const MeshData curved = lattice([](double x, double y) { return x * x + y * y / 3.0; });
    const int a = 3 * 9 + 4, b = a + 1;
    const ScreenRates rates =
        screen_space_rates(curved.view(), curved.positions.data(), camera_down_z(), 0.2f, 64, DicingMeasure::Deviation);
    EXPECT_EQ(lattice_rate(rates, a, b), 5);
    // On z = y^2 every edge along x is straight (bulge 0), and the surface curves across it: each takes the largest
    // rate of its triangles' other edges, more than one segment, so that no strip of slivers fans from its ends.
    const MeshData across = lattice([](double, double y) { return y * y; });
    const ScreenRates raised =
        screen_space_rates(across.view(), across.positions.data(), camera_down_z(), 0.1f, 64, DicingMeasure::Deviation);
    for (int j = -2; j <= 2; ++j)
        for (int i = -3; i < 3; ++i) {
            const int from = (j + 3) * 9 + (i + 4);
            EXPECT_GT(lattice_rate(raised, from, from + 1), 1) << "edge along x at row " << j;
        }
}

TEST(Tessellation, RefusesBadRatesAndUnsupportedInput) {
    TestMesh mesh = icosahedron();
    auto refuses = [&](const MeshView& view, const Options& options, const TessellationRates& rates,
                       const std::string& words) {
        try {
            Tessellation(view, options, rates);
            ADD_FAILURE() << "accepted: " << words;
        } catch (const InputError& error) {
            EXPECT_NE(std::string(error.what()).find(words), std::string::npos) << error.what();
        }
    };
    Options options = options_for(mesh);
    TessellationRates rates;
    rates.uniform_rate = 0;
    refuses(mesh.view(), options, rates, "uniform_rate must be between 1 and 4096, got 0");
    rates.uniform_rate = kMaxTessellationRate + 1;
    refuses(mesh.view(), options, rates, "got 4097");
    rates.uniform_rate = 2;
    const std::int32_t not_an_edge[2] = {0, 0}, zero[1] = {0};
    rates.edges = not_an_edge, rates.rates = zero, rates.num_edges = 1;
    refuses(mesh.view(), options, rates, "rated edge 0 (0, 0) is not an edge of the mesh");
    const std::int32_t edge[2] = {mesh.triangles[0], mesh.triangles[1]};
    rates.edges = edge;
    refuses(mesh.view(), options, rates,
            "rated edge 0 (" + std::to_string(edge[0]) + ", " + std::to_string(edge[1]) +
                ") has rate 0; a rate must be between 1 and 4096");
    rates.num_edges = 0;
    // Past the memory limit: refused with what it would need, before anything is allocated.
    Options small = options;
    small.memory_limit_bytes = 1 << 20;
    TessellationRates fine;
    fine.uniform_rate = 200;  // 20 triangles of 40,000 each
    try {
        Tessellation(mesh.view(), small, fine);
        ADD_FAILURE() << "a tessellation past the memory limit was made";
    } catch (const MemoryLimitError& error) { EXPECT_GT(error.required_bytes, small.memory_limit_bytes); }
    MeshView broken = mesh.view();
    broken.num_vertices = 3;  // the triangles name vertices past it: the plan's own check
    EXPECT_THROW(Tessellation(broken, options, rates), InputError);
}

// --- The tessellation's checks of the caller's data, as InputProblems ---------------------------------------------

// The problem `call` throws, its message what() gives after `context`; a test failure where it throws none.
template <typename Call>
InputProblem problem_of(Call&& call, const std::string& context) {
    try {
        call();
        ADD_FAILURE() << "no InputError";
    } catch (const InputError& error) {
        if (error.problem()) {
            EXPECT_EQ(std::string(error.what()), context + error.problem()->message());
            return *error.problem();
        }
        ADD_FAILURE() << "an InputError without a problem: " << error.what();
    }
    return {};
}

// Rated edges: the first that is no edge of the mesh or whose rate is out of range, with its index, its ends and
// (out of range) its rate and the largest.
TEST(TessellationChecks, RatedEdgesAreNotAnEdgeAndRateOutOfRange) {
    TestMesh mesh = icosahedron();
    const Options options = options_for(mesh);
    const std::int32_t a = mesh.triangles[0], b = mesh.triangles[1], c = mesh.triangles[2];
    const std::int32_t edges[6] = {a, b, b, c, a, a}, good_rates[3] = {3, 5, 2}, bad_rates[3] = {3, 4097, 2};
    TessellationRates rates;
    rates.uniform_rate = 2, rates.edges = edges, rates.rates = good_rates, rates.num_edges = 3;
    // The third names no edge (a, a).
    InputProblem p = problem_of([&] { Tessellation(mesh.view(), options, rates); }, "tessellation: ");
    EXPECT_EQ(p.kind, InputProblem::Kind::NotAnEdge);
    EXPECT_EQ(p.element, InputProblem::Element::RatedEdge);
    EXPECT_EQ(p.index, 2);
    EXPECT_EQ(p.refers_to, a);
    EXPECT_EQ(p.other, a);
    EXPECT_STREQ(problem_name(p.element), "rated_edge");
    // The second's rate comes first.
    rates.rates = bad_rates;
    p = problem_of([&] { Tessellation(mesh.view(), options, rates); }, "tessellation: ");
    EXPECT_EQ(p.kind, InputProblem::Kind::RateOutOfRange);
    EXPECT_EQ(p.element, InputProblem::Element::RatedEdge);
    EXPECT_EQ(p.index, 1);
    EXPECT_EQ(p.refers_to, b);
    EXPECT_EQ(p.other, c);
    EXPECT_EQ(p.value, 4097.0f);
    EXPECT_EQ(p.limit, float(kMaxTessellationRate));
    EXPECT_STREQ(problem_name(p.kind), "rate_out_of_range");
    // Sound, the rates are taken.
    rates.num_edges = 2, rates.rates = good_rates;
    EXPECT_GT(Tessellation(mesh.view(), options, rates).num_points(), 0);
    // An argument, not data: a plain InputError.
    rates.uniform_rate = 0;
    try {
        Tessellation(mesh.view(), options, rates);
        ADD_FAILURE() << "a uniform rate of 0 accepted";
    } catch (const InputError& error) { EXPECT_EQ(error.problem(), nullptr); }
}

// A frame's positions and a layer's values: NonFiniteValue and ValueTooLarge at their vertex or value and channel.
TEST(TessellationChecks, PositionsAndLayerValuesAreNonFiniteOrTooLarge) {
    const IcosahedronWithLayer icosahedron_with_layer;
    const TestMesh& mesh = icosahedron_with_layer.mesh;
    TessellationRates rates;
    rates.uniform_rate = 3;
    const Tessellation tessellation(icosahedron_with_layer.view(), options_for(mesh), rates);
    std::vector<float> points(3 * std::size_t(tessellation.num_points()));
    std::vector<float> positions = mesh.positions;
    positions[3 * 7 + 2] = std::numeric_limits<float>::infinity();
    InputProblem p =
        problem_of([&] { tessellation.evaluate(positions.data(), points.data(), nullptr); }, "tessellation: ");
    EXPECT_EQ(p.kind, InputProblem::Kind::NonFiniteValue);
    EXPECT_EQ(p.element, InputProblem::Element::Vertex);
    EXPECT_EQ(p.index, 7);
    EXPECT_EQ(p.channel, 2);
    positions[3 * 7 + 2] = std::numeric_limits<float>::max() / 2;
    p = problem_of([&] { tessellation.evaluate(positions.data(), points.data(), nullptr); }, "tessellation: ");
    EXPECT_EQ(p.kind, InputProblem::Kind::ValueTooLarge);
    EXPECT_EQ(p.index, 7);
    EXPECT_EQ(p.limit, std::numeric_limits<float>::max() / 64);
    std::vector<float> uvs = mesh.uvs, out(2 * std::size_t(tessellation.num_face_points()));
    uvs[2 * 5 + 1] = std::numeric_limits<float>::quiet_NaN();
    p = problem_of([&] { tessellation.evaluate_face_varying(0, uvs.data(), 2, out.data()); }, "tessellation: ");
    EXPECT_EQ(p.kind, InputProblem::Kind::NonFiniteValue);
    EXPECT_EQ(p.element, InputProblem::Element::FaceVaryingValue);
    EXPECT_EQ(p.index, 5);
    EXPECT_EQ(p.layer, 0);
    EXPECT_EQ(p.channel, 1);
}

// screen_space_rates: the camera's matrix (its entry), the triangles' vertices and the positions.
TEST(TessellationChecks, ScreenRatesCheckTheCameraTrianglesAndPositions) {
    MeshData mesh;
    mesh.positions = {-0.5f, 0, -2, 0.5f, 0, -2, 0, 0.5f, -2};
    mesh.triangles = {0, 1, 2};
    Camera camera = camera_down_z();
    camera.world_to_clip[6] = std::numeric_limits<float>::quiet_NaN();
    auto rates = [&](const MeshView& view, const float* positions) {
        screen_space_rates(view, positions, camera, 1.0f, 64);
    };
    InputProblem p = problem_of([&] { rates(mesh.view(), mesh.positions.data()); }, "screen_space_rates: ");
    EXPECT_EQ(p.kind, InputProblem::Kind::NonFiniteValue);
    EXPECT_EQ(p.element, InputProblem::Element::Camera);
    EXPECT_EQ(p.index, 6);
    EXPECT_STREQ(problem_name(p.element), "camera");
    EXPECT_EQ(p.message(), "the camera's world_to_clip entry 6 (row 1, column 2) has a non-finite value (nan)");
    camera = camera_down_z();
    MeshView out_of_range = mesh.view();
    out_of_range.num_vertices = 2;
    p = problem_of([&] { rates(out_of_range, mesh.positions.data()); }, "screen_space_rates: ");
    EXPECT_EQ(p.kind, InputProblem::Kind::VertexOutOfRange);
    EXPECT_EQ(p.element, InputProblem::Element::Triangle);
    EXPECT_EQ(p.index, 0);
    EXPECT_EQ(p.corner, 2);
    EXPECT_EQ(p.refers_to, 2);
    EXPECT_EQ(p.other, 2);
    std::vector<float> positions = mesh.positions;
    positions[4] = -std::numeric_limits<float>::infinity();
    p = problem_of([&] { rates(mesh.view(), positions.data()); }, "screen_space_rates: ");
    EXPECT_EQ(p.kind, InputProblem::Kind::NonFiniteValue);
    EXPECT_EQ(p.element, InputProblem::Element::Vertex);
    EXPECT_EQ(p.index, 1);
    EXPECT_EQ(p.channel, 1);
}

}  // namespace
}  // namespace loopsub::testing
