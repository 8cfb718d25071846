// The limit surface by hand and by convergence (the comparison with OpenSubdiv's Limit is in
// test_opensubdiv_exact.cpp): normals on a folded sheet are its planes' normals on either side of the fold, and
// the Hoppe 94 limit is where its own refinement goes when it is carried on for many more levels.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "loopsub/loopsub.h"
#include "mesh_gen.h"

namespace loopsub::testing {
namespace {

constexpr double kFoldAngle = 1.0;  // radians

// A flat sheet (z = 0) folded up along the column x = 0.5 by kFoldAngle, the fold tagged as a crease: every point
// of the limit surface lies in one of the two planes.
TestMesh folded_sheet() {
    TestMesh mesh = grid(8, 6);
    for (int v = 0; v < mesh.num_vertices(); ++v) {
        const double x = mesh.positions[3 * v] - 0.5;
        mesh.positions[3 * v + 2] = 0.0f;
        if (x > 0) {
            mesh.positions[3 * v] = float(0.5 + x * std::cos(kFoldAngle));
            mesh.positions[3 * v + 2] = float(x * std::sin(kFoldAngle));
        }
    }
    for (int j = 0; j < 6; ++j) mesh.add_crease(grid_vertex(8, 4, j), grid_vertex(8, 4, j + 1));
    return mesh;
}

class FoldedSheet : public ::testing::TestWithParam<Rules> {};

TEST_P(FoldedSheet, EachSideOfTheFoldHasItsPlanesNormal) {
    const TestMesh mesh = folded_sheet();
    // The winding of the first input triangle says which way the flat half faces.
    const float* p = mesh.positions.data();
    const std::int32_t* t0 = mesh.triangles.data();
    const double e1x = p[3 * t0[1]] - p[3 * t0[0]], e1y = p[3 * t0[1] + 1] - p[3 * t0[0] + 1];
    const double e2x = p[3 * t0[2]] - p[3 * t0[0]], e2y = p[3 * t0[2] + 1] - p[3 * t0[0] + 1];
    const double up = e1x * e2y - e1y * e2x > 0 ? 1.0 : -1.0;
    const double flat_normal[3] = {0.0, 0.0, up};
    const double folded_normal[3] = {-up * std::sin(kFoldAngle), 0.0, up * std::cos(kFoldAngle)};

    for (int levels = 1; levels <= 3; ++levels) {
        Options options;
        options.rules = GetParam();
        options.levels = levels;
        options.limit_surface = true;
        Plan plan(mesh.view(), options);
        const auto [limit, normals] = evaluate_limit(plan, mesh);

        // The folded half's input points are rounded to floats off its exact plane, which tilts normals computed
        // from differences of nearby points by up to ~1e-6 at level 3.
        constexpr double kNormalTolerance = 1e-5;
        int bad = 0;
        bool flat_on_fold = false, folded_on_fold = false;
        const std::int32_t* tris = plan.output_triangles();
        for (int f = 0; f < plan.num_output_triangles(); ++f) {
            double centre_x = 0.0;
            for (int k = 0; k < 3; ++k) centre_x += limit[3 * tris[3 * f + k]] / 3.0;
            const double* expected = centre_x > 0.5 ? folded_normal : flat_normal;
            for (int k = 0; k < 3; ++k) {
                const float* n = &normals[9 * f + 3 * k];
                double error = 0.0;
                for (int c = 0; c < 3; ++c) error = std::max(error, std::abs(n[c] - expected[c]));
                if (!(error <= kNormalTolerance) && bad++ < 5)
                    ADD_FAILURE() << "level " << levels << " triangle " << f << " corner " << k << ": normal (" << n[0]
                                  << ", " << n[1] << ", " << n[2] << ") is off its plane's by " << error;
                const float x = limit[3 * tris[3 * f + k]];
                if (std::abs(x - 0.5f) < 1e-6f) (expected == flat_normal ? flat_on_fold : folded_on_fold) = true;
            }
        }
        EXPECT_EQ(bad, 0) << "level " << levels;
        EXPECT_TRUE(flat_on_fold && folded_on_fold)
            << "level " << levels << ": the fold's corners should take both planes' normals";
        // The limit stays in the planes too.
        for (int v = 0; v < plan.num_output_vertices(); ++v) {
            const double x = limit[3 * v] - 0.5, z = limit[3 * v + 2];
            const double off_plane =
                x <= 0 ? std::abs(z) : std::abs(-x * std::sin(kFoldAngle) + z * std::cos(kFoldAngle));
            ASSERT_LE(off_plane, 1e-6) << "level " << levels << " vertex " << v;
        }
    }
}

INSTANTIATE_TEST_SUITE_P(BothRules, FoldedSheet, ::testing::Values(Rules::Hoppe94, Rules::OpenSubdiv),
                         [](const auto& info) {
                             return std::string(info.param == Rules::Hoppe94 ? "hoppe94" : "opensubdiv");
                         });

// An octahedron with a creased equator (irregular crease vertices: two faces on each side), a corner on it, and a
// cone at the bottom apex: under Hoppe 94 the crease next to the corner takes the {5,3} edges, so its limit is not
// OpenSubdiv's B-spline one.
TestMesh creased_octahedron() {
    TestMesh mesh = bipyramid(4);
    for (int k = 0; k < 4; ++k) mesh.add_crease(2 + k, 2 + (k + 1) % 4);
    mesh.add_corner(2);
    mesh.cone_vertices.push_back(1);
    return mesh;
}

// Vertex v of level 1 keeps its index at every later level, and there converges to its limit at the rate of the
// largest eigenvalue that moves the vertex itself: 1/4 per level at smooth and regular crease vertices, 3/8 at an
// irregular crease vertex between {5,3} edges and at the valence-4 cone (b(4)). Eight more levels leave errors of
// ~1e-5 and ~4e-5 where a wrong mask (OpenSubdiv's (1,4,1)/6 at an irregular crease vertex, the smooth mask at the
// cone) would be off by 1e-2.
TEST(HoppeLimit, IsWhereItsOwnRefinementConverges) {
    const TestMesh mesh = creased_octahedron();
    Options options;
    options.rules = Rules::Hoppe94;
    options.levels = 1;
    options.limit_surface = true;
    Plan limit_plan(mesh.view(), options);
    const std::vector<float> limit = evaluate_positions(limit_plan, mesh);
    const std::vector<VertexType>& types = limit_plan.level_vertex_types(1);

    options.limit_surface = false;
    options.levels = 9;
    Plan deep_plan(mesh.view(), options);
    const std::vector<float> deep = evaluate_positions(deep_plan, mesh);

    std::set<VertexType> seen;
    for (int v = 0; v < limit_plan.num_output_vertices(); ++v) {
        seen.insert(types[v]);
        double distance = 0.0;
        for (int k = 0; k < 3; ++k) distance = std::max(distance, double(std::abs(limit[3 * v + k] - deep[3 * v + k])));
        const double tolerance = types[v] == VertexType::Cone || types[v] == VertexType::IrregularCrease ? 1e-4 : 2e-5;
        EXPECT_LE(distance, tolerance) << "vertex " << v << " of class " << int(types[v]);
    }
    for (VertexType type : {VertexType::Smooth, VertexType::RegularCrease, VertexType::IrregularCrease,
                            VertexType::Corner, VertexType::Cone})
        EXPECT_TRUE(seen.count(type)) << "the mesh should have a vertex of class " << int(type) << " at level 1";
}

TEST(LimitSurface, NormalsNeedTheLimitAndPositions) {
    const TestMesh mesh = icosphere(1);
    Options options;
    options.levels = 1;
    Plan plan(mesh.view(), options);
    std::vector<float> out(3 * std::size_t(plan.num_output_vertices())),
        normals(9 * std::size_t(plan.num_output_triangles()));
    EXPECT_THROW(plan.evaluate(interleaved(mesh.positions.data(), 3), interleaved(out.data(), 3), normals.data()),
                 InputError);
    options.limit_surface = true;
    Plan limit_plan(mesh.view(), options);
    EXPECT_THROW(limit_plan.evaluate(interleaved(mesh.positions.data(), 2), interleaved(out.data(), 2), normals.data()),
                 InputError);
    EXPECT_EQ(limit_plan.level_vertex_types(1).size(), std::size_t(limit_plan.num_output_vertices()));
    EXPECT_THROW(plan.level_vertex_types(2), std::out_of_range);
}

// Level 0 with the limit: the input's own vertices go to the limit, as OpenSubdiv's Limit of an unrefined mesh.
TEST(LimitSurface, LevelZeroPutsTheInputOnTheLimit) {
    TestMesh mesh = bipyramid(6);
    Options options;
    options.rules = Rules::OpenSubdiv;
    options.levels = 0;
    options.limit_surface = true;
    Plan plan(mesh.view(), options);
    const std::vector<float> limit = evaluate_positions(plan, mesh);
    // Apex 0 has the six ring vertices 2..7 around it, valence 6: 1/2 itself, 1/12 each neighbour.
    for (int k = 0; k < 3; ++k) {
        double expected = 0.5 * mesh.positions[k];
        for (int r = 2; r < 8; ++r) expected += mesh.positions[3 * r + k] / 12.0;
        EXPECT_NEAR(limit[k], expected, 1e-6);
    }
}

// Evaluate accepts values up to a bound that keeps refinement finite; the tangents of such a triangle's limit sum
// offsets near the float maximum, which overflowed to NaN normals (found by fuzz_plan). At the largest scale
// accepted, a flat triangle's normals are still its plane's.
TEST(LimitSurface, HugeButAcceptedCoordinatesGiveUnitNormals) {
    for (Rules rules : {Rules::Hoppe94, Rules::OpenSubdiv})
        for (int levels = 0; levels <= 2; ++levels) {
            SCOPED_TRACE("rules " + std::to_string(int(rules)) + ", levels " + std::to_string(levels));
            Options options;
            options.rules = rules;
            options.levels = levels;
            options.limit_surface = true;
            bool accepted = false;
            for (float scale = std::numeric_limits<float>::max() / 2; !accepted && scale > 1.0f; scale /= 2) {
                TestMesh mesh;
                mesh.positions = {0, 0, 0, scale, 0, 0, 0, scale, 0};
                mesh.triangles = {0, 1, 2};
                Plan plan(mesh.view(), options);
                LimitEvaluation limit;
                try {
                    limit = evaluate_limit(plan, mesh);
                } catch (const InputError&) { continue; }
                accepted = true;
                for (float value : limit.positions) EXPECT_TRUE(std::isfinite(value)) << value << " at scale " << scale;
                ASSERT_EQ(limit.normals.size(), 9 * std::size_t(plan.num_output_triangles()));
                for (std::size_t c = 0; c < limit.normals.size(); c += 3) {
                    EXPECT_NEAR(limit.normals[c], 0.0f, 1e-6) << "corner " << c / 3 << " at scale " << scale;
                    EXPECT_NEAR(limit.normals[c + 1], 0.0f, 1e-6) << "corner " << c / 3 << " at scale " << scale;
                    EXPECT_NEAR(limit.normals[c + 2], 1.0f, 1e-6) << "corner " << c / 3 << " at scale " << scale;
                }
            }
            EXPECT_TRUE(accepted);
        }
}

// The normals' arithmetic is float's: a mesh far smaller or larger than a unit, whose tangents' products leave the
// float range, takes the normals it has at unit scale, bit for bit (a power of two changes no bits of them).
TEST(LimitSurface, NormalsDoNotDependOnAPowerOfTwoScale) {
    TestMesh base = icosphere(2);
    jitter(base, 3, 0.01f);
    add_random_creases(base, 3, 0.1, true);
    for (Kernel kernel : {Kernel::Scalar, Kernel::SSE41, Kernel::AVX2}) {
        auto normals_at = [&](int exponent) {
            TestMesh mesh = base;
            for (float& x : mesh.positions) x = std::ldexp(x, exponent);
            Options options;
            options.rules = Rules::OpenSubdiv;
            options.levels = 3;
            options.limit_surface = true;
            options.kernel = kernel;
            Plan plan(mesh.view(), options);
            return evaluate_limit(plan, mesh).normals;
        };
        const std::vector<float> unit_scale = normals_at(0);
        for (int exponent : {-100, -60, 60, 100})
            EXPECT_EQ(normals_at(exponent), unit_scale) << "kernel " << int(kernel) << ", scale 2^" << exponent;
    }
}

// Threads split the limit plan's steps and the normals pass, never their arithmetic or their order: any number gives
// one thread's per-corner normals, and its compact normals in the same rows (the sides' too), whether the limit is
// planned over the last level itself (one level) or from its grandparent (two); the scalar kernel's limit gives the
// same normals to float rounding.
TEST(LimitSurface, NormalsAgreeAcrossThreadsAndKernels) {
    TestMesh mesh = icosphere(3);
    jitter(mesh, 7, 0.01f);
    add_random_creases(mesh, 7, 0.1, true);
    for (int levels : {1, 2}) {
        SCOPED_TRACE("levels " + std::to_string(levels));
        auto plan_for = [&](int threads, Kernel kernel) {
            Options options;
            options.rules = Rules::OpenSubdiv;
            options.levels = levels;
            options.limit_surface = true;
            options.threads = threads;
            options.kernel = kernel;
            return Plan(mesh.view(), options);
        };
        auto compact_normals = [&](Plan& plan) {
            std::vector<float> out(3 * std::size_t(plan.num_output_vertices()));
            std::vector<float> normals(3 * std::size_t(plan.num_limit_normals()));
            plan.evaluate(interleaved(mesh.positions.data(), 3), interleaved(out.data(), 3),
                          Plan::LimitNormals{normals.data()});
            const std::int32_t* rows = plan.corner_normal_indices();
            return std::make_pair(normals, std::vector<std::int32_t>(rows, rows + 3 * plan.num_output_triangles()));
        };
        Plan one = plan_for(1, Kernel::Auto);
        ASSERT_GT(one.num_limit_normals(), one.num_output_vertices());  // infinitely sharp creases part some fans
        const std::vector<float> corner_normals = evaluate_limit(one, mesh).normals;
        const auto compact = compact_normals(one);
        for (int threads : {2, 3, 8}) {
            SCOPED_TRACE("threads " + std::to_string(threads));
            Plan more = plan_for(threads, Kernel::Auto);
            EXPECT_EQ(corner_normals, evaluate_limit(more, mesh).normals);
            EXPECT_EQ(compact, compact_normals(more));
        }
        Plan scalar_plan = plan_for(1, Kernel::Scalar);
        const std::vector<float> scalar = evaluate_limit(scalar_plan, mesh).normals;
        for (std::size_t i = 0; i < corner_normals.size(); ++i)
            ASSERT_NEAR(corner_normals[i], scalar[i], 1e-5) << "component " << i;
    }
}

// Every level up to the last has classes, the last one an entry per output vertex; with neither levels nor the limit
// surface nothing was classified.
TEST(VertexTypes, EveryLevelUpToTheLast) {
    const TestMesh mesh = icosphere(1);
    Options options;
    options.levels = 0;
    const Plan none(mesh.view(), options);
    EXPECT_THROW(none.level_vertex_types(0), std::out_of_range);
    options.levels = 2;
    const Plan two(mesh.view(), options);
    for (int level = 0; level <= 2; ++level)
        EXPECT_EQ(two.level_vertex_types(level).size(), std::size_t(two.level_num_vertices(level)))
            << "level " << level;
    EXPECT_THROW(two.level_vertex_types(3), std::out_of_range);
    EXPECT_THROW(two.level_vertex_types(-1), std::out_of_range);
}

// The last level's classes (what an application tags the output with) are the ones a plan one level deeper
// repositions that level with, and the ones the limit uses: one classification, three ways to reach it.
TEST(VertexTypes, LastLevelEqualsTheNextLevelsAndTheLimits) {
    for (Rules rules : {Rules::Hoppe94, Rules::OpenSubdiv}) {
        TestMesh mesh = grid(6, 5);
        jitter(mesh, 9, 0.01f);
        add_random_creases(mesh, 9, 0.3, rules == Rules::OpenSubdiv);
        add_random_corners(mesh, 10, 3, rules == Rules::OpenSubdiv);
        if (rules == Rules::Hoppe94) mesh.cone_vertices = {grid_vertex(6, 3, 3)};
        for (int levels = 1; levels <= 3; ++levels) {
            Options options;
            options.rules = rules;
            options.levels = levels;
            const Plan plan(mesh.view(), options);
            options.levels = levels + 1;
            const Plan deeper(mesh.view(), options);
            options.levels = levels;
            options.limit_surface = true;
            const Plan limit(mesh.view(), options);
            EXPECT_EQ(plan.level_vertex_types(levels), deeper.level_vertex_types(levels)) << "levels " << levels;
            EXPECT_EQ(plan.level_vertex_types(levels), limit.level_vertex_types(levels)) << "levels " << levels;
            std::set<VertexType> seen(plan.level_vertex_types(levels).begin(), plan.level_vertex_types(levels).end());
            EXPECT_GE(seen.size(), 4u) << "the grid should show several classes at level " << levels;
        }
    }
}

}  // namespace
}  // namespace loopsub::testing
