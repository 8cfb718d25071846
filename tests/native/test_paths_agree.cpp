// The evaluation paths a user can pick, or that the library picks for them, give the same result: scalar vs SSE4.1
// vs AVX2 kernels (within float rounding), 1 vs 2 threads (bit for bit), a re-evaluated plan vs a fresh one (bit
// for bit), and many channels in one call, interleaved, planar or padded, vs one channel at a time.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "loopsub/loopsub.h"
#include "mesh_gen.h"

namespace loopsub::testing {
namespace {

bool cpu_runs(Kernel kernel) {
    switch (kernel) {
        case Kernel::SSE41: return __builtin_cpu_supports("sse4.1");
        case Kernel::AVX2: return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
        default: return true;
    }
}

struct PathCase {
    std::string name;
    std::function<TestMesh()> make;
    Rules rules;
    int levels;
    bool limit_surface = false;
};
// gtest prints a parameter with this (instead of its bytes) when a case fails.
void PrintTo(const PathCase& c, std::ostream* os) { *os << c.name; }

std::vector<PathCase> path_cases() {
    return {
        {"opensubdiv_semisharp_icosphere1280_L3",
         [] {
             TestMesh m = icosphere(3);
             jitter(m, 91, 0.01f);
             add_random_creases(m, 91, 0.15, true);
             add_random_corners(m, 92, 10, true);
             return m;
         },
         Rules::OpenSubdiv, 3},
        {"opensubdiv_chaikin_grid30_edges_and_corners_L2",
         [] {
             TestMesh m = grid(30, 30);
             m.boundary = Boundary::EdgesAndCorners;
             m.crease_method = CreaseMethod::Chaikin;
             add_random_creases(m, 93, 0.1, true);
             return m;
         },
         Rules::OpenSubdiv, 2},
        {"hoppe94_creases_corners_cones_icosphere1280_L3",
         [] {
             TestMesh m = icosphere(3);
             jitter(m, 94, 0.01f);
             add_random_creases(m, 94, 0.1, false);
             add_random_corners(m, 95, 5, false);
             for (int v : {3, 40, 200, 500}) m.cone_vertices.push_back(v);
             return m;
         },
         Rules::Hoppe94, 3},
        {"opensubdiv_bipyramid64_L3", [] { return bipyramid(64); }, Rules::OpenSubdiv, 3},
        // A fin (an edge of three faces) and boundaries: rings and wings of every kind of edge.
        {"opensubdiv_fin_on_grid_L3", [] { return fin_on_grid(); }, Rules::OpenSubdiv, 3},
        {"hoppe94_open_cylinder_L2", [] { return open_cylinder(12, 5); }, Rules::Hoppe94, 2},
        // The limit is one more pass of the same kernels.
        {"opensubdiv_semisharp_icosphere1280_L2_limit",
         [] {
             TestMesh m = icosphere(3);
             jitter(m, 96, 0.01f);
             add_random_creases(m, 96, 0.15, true);
             return m;
         },
         Rules::OpenSubdiv, 2, true},
        {"hoppe94_creases_cones_grid30_L2_limit",
         [] {
             TestMesh m = grid(30, 30);
             add_random_creases(m, 97, 0.1, false);
             for (int v : {40, 200, 500}) m.cone_vertices.push_back(v);
             return m;
         },
         Rules::Hoppe94, 2, true},
    };
}

Options options_for(const PathCase& c, const TestMesh& mesh, Kernel kernel, int threads) {
    Options options;
    options.rules = c.rules;
    options.levels = c.levels;
    options.boundary = mesh.boundary;
    options.crease_method = mesh.crease_method;
    options.kernel = kernel;
    options.threads = threads;
    options.limit_surface = c.limit_surface;
    return options;
}

// Five channels per vertex: the position and two more (a vertex-group weight and a colour-like value), interleaved.
std::vector<float> five_channels(const TestMesh& mesh) {
    std::vector<float> data(5 * std::size_t(mesh.num_vertices()));
    for (int v = 0; v < mesh.num_vertices(); ++v) {
        for (int k = 0; k < 3; ++k) data[5 * v + k] = mesh.positions[3 * v + k];
        data[5 * v + 3] = 0.5f + 0.5f * std::sin(7.0f * mesh.positions[3 * v]);
        data[5 * v + 4] = 100.0f + float(v % 17);
    }
    return data;
}

// Largest |a - b| over the values, relative to the largest |value| of the expected data (so that a channel of
// magnitude 100 is held to the same number of significant digits as one of magnitude 1).
double max_relative_difference(const std::vector<float>& expected, const std::vector<float>& got) {
    double scale = 0, diff = 0;
    for (float e : expected) scale = std::max(scale, double(std::abs(e)));
    for (std::size_t i = 0; i < expected.size(); ++i)
        diff = std::max(diff, std::abs(double(expected[i]) - double(got[i])));
    return scale > 0 ? diff / scale : diff;
}

bool bitwise_equal(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// Two plans of one mesh give the same positions and five channels bit for bit, and the same triangles.
void expect_same_results_bit_for_bit(Plan& a, Plan& b, const TestMesh& mesh, const std::vector<float>& channels) {
    EXPECT_TRUE(bitwise_equal(evaluate_positions(a, mesh), evaluate_positions(b, mesh))) << "3 channels";
    std::vector<float> out_a(5 * std::size_t(a.num_output_vertices())), out_b(out_a.size());
    a.evaluate(interleaved(channels.data(), 5), interleaved(out_a.data(), 5));
    b.evaluate(interleaved(channels.data(), 5), interleaved(out_b.data(), 5));
    EXPECT_TRUE(bitwise_equal(out_a, out_b)) << "5 channels";
    ASSERT_EQ(a.num_output_triangles(), b.num_output_triangles());
    EXPECT_TRUE(
        std::equal(a.output_triangles(), a.output_triangles() + 3 * a.num_output_triangles(), b.output_triangles()));
}

// The output's edges, then each output triangle's (Plan::output_edges).
std::vector<std::int32_t> output_edges(const Plan& plan) {
    const std::size_t ends = 2 * std::size_t(plan.num_output_edges());
    std::vector<std::int32_t> edges(ends + 3 * std::size_t(plan.num_output_triangles()));
    plan.output_edges(edges.data(), edges.data() + ends);
    return edges;
}

// What the plans report besides the output's points: its edges, each level's edges and vertex classes, the output's
// tags.
void expect_same_levels_and_tags(const Plan& a, const Plan& b) {
    EXPECT_EQ(output_edges(a), output_edges(b));
    for (int level = 0; level < a.levels(); ++level) EXPECT_EQ(a.level_edges(level), b.level_edges(level));
    for (int level = 0; level <= a.levels(); ++level)
        EXPECT_EQ(a.level_vertex_types(level), b.level_vertex_types(level)) << "level " << level;
    EXPECT_EQ(a.output_sharp_edges(), b.output_sharp_edges());
    EXPECT_EQ(a.output_crease_edges(), b.output_crease_edges());
    EXPECT_EQ(a.output_corner_vertices(), b.output_corner_vertices());
}

class PathsAgree : public ::testing::TestWithParam<PathCase> {};

// Each SIMD kernel the CPU has is used when asked for, and agrees with the scalar reference within 1e-6 of the
// data's magnitude (the kernels may contract multiply-adds differently, nothing more).
TEST_P(PathsAgree, SimdKernelsMatchScalar) {
    const TestMesh mesh = GetParam().make();
    Plan scalar(mesh.view(), options_for(GetParam(), mesh, Kernel::Scalar, 1));
    ASSERT_EQ(scalar.kernel(), Kernel::Scalar);
    const std::vector<float> expected = evaluate_positions(scalar, mesh);
    for (Kernel kernel : {Kernel::SSE41, Kernel::AVX2, Kernel::Auto}) {
        SCOPED_TRACE(kernel_name(kernel));
        if (!cpu_runs(kernel)) {
            std::cout << "  (this CPU cannot run " << kernel_name(kernel) << ": not compared)\n";
            continue;
        }
        Plan plan(mesh.view(), options_for(GetParam(), mesh, kernel, 1));
        if (kernel != Kernel::Auto) { EXPECT_EQ(plan.kernel(), kernel) << "the plan did not use the kernel asked for"; }
        const std::vector<float> got = evaluate_positions(plan, mesh);
        ASSERT_EQ(got.size(), expected.size());
        EXPECT_LE(max_relative_difference(expected, got), 1e-6);
    }
}

// Two threads split the work, never the arithmetic: the result is identical, for every kernel and channel count.
TEST_P(PathsAgree, TwoThreadsEqualOneBitForBit) {
    const TestMesh mesh = GetParam().make();
    const std::vector<float> channels = five_channels(mesh);
    for (Kernel kernel : {Kernel::Scalar, Kernel::SSE41, Kernel::AVX2}) {
        if (!cpu_runs(kernel)) continue;
        SCOPED_TRACE(kernel_name(kernel));
        Plan one(mesh.view(), options_for(GetParam(), mesh, kernel, 1));
        Plan two(mesh.view(), options_for(GetParam(), mesh, kernel, 2));
        // The topology does not depend on the thread count either.
        expect_same_results_bit_for_bit(one, two, mesh, channels);
        if (HasFatalFailure()) return;
        expect_same_levels_and_tags(one, two);
    }
}

// Tables derived as each evaluation runs (Options::level_tables) give the stored tables' result bit for bit: the same
// rings in the same order, the same edges, the same triangles and tags.
TEST_P(PathsAgree, DerivedTablesEqualStoredBitForBit) {
    const TestMesh mesh = GetParam().make();
    const std::vector<float> channels = five_channels(mesh);
    for (Kernel kernel : {Kernel::Scalar, Kernel::SSE41, Kernel::AVX2}) {
        for (int threads : {1, 2}) {
            if (!cpu_runs(kernel)) continue;
            SCOPED_TRACE(std::string(kernel_name(kernel)) + ", threads " + std::to_string(threads));
            Options stored_options = options_for(GetParam(), mesh, kernel, threads), derived_options = stored_options;
            stored_options.level_tables = LevelTables::Stored;
            derived_options.level_tables = LevelTables::Derived;
            Plan stored(mesh.view(), stored_options), derived(mesh.view(), derived_options);
            expect_same_results_bit_for_bit(stored, derived, mesh, channels);
            if (HasFatalFailure()) return;
            expect_same_levels_and_tags(stored, derived);
        }
    }
}

// The per-frame use: one plan, new positions each frame. Each evaluation equals a fresh plan's on the same data,
// and going back to the first positions gives the first result again (no state carried between frames).
TEST_P(PathsAgree, ReevaluatedPlanEqualsFreshPlan) {
    const TestMesh mesh = GetParam().make();
    TestMesh moved = mesh;
    jitter(moved, 96, 0.05f);
    for (float& p : moved.positions) p = 1.5f * p + 0.25f;  // also scaled and shifted: a different frame
    for (int threads : {1, 2}) {
        SCOPED_TRACE("threads " + std::to_string(threads));
        Plan reused(mesh.view(), options_for(GetParam(), mesh, Kernel::Auto, threads));
        const std::vector<float> first = evaluate_positions(reused, mesh);
        const std::vector<float> second = evaluate_positions(reused, moved);
        Plan fresh(moved.view(), options_for(GetParam(), moved, Kernel::Auto, threads));
        EXPECT_TRUE(bitwise_equal(second, evaluate_positions(fresh, moved)));
        EXPECT_FALSE(bitwise_equal(first, second)) << "test set-up: the two frames must differ";
        EXPECT_TRUE(bitwise_equal(first, evaluate_positions(reused, mesh)));
        // A different channel count on the same plan, then back to positions.
        const std::vector<float> channels = five_channels(mesh);
        std::vector<float> five(5 * std::size_t(reused.num_output_vertices()));
        reused.evaluate(interleaved(channels.data(), 5), interleaved(five.data(), 5));
        EXPECT_TRUE(bitwise_equal(second, evaluate_positions(reused, moved)));
    }
}

// Any number of channels in any layout gives per channel what a one-channel evaluation gives: interleaved
// (n x 5), planar (5 x n), and interleaved with padding (8 floats per vertex, 5 used; the padding is left alone).
// Exact on the scalar path; within float rounding on the SIMD paths, which may group the work differently.
TEST_P(PathsAgree, ChannelsInAnyLayoutEqualOneChannelAtATime) {
    const TestMesh mesh = GetParam().make();
    const std::vector<float> channels = five_channels(mesh);
    const std::size_t n_in = std::size_t(mesh.num_vertices());
    for (Kernel kernel : {Kernel::Scalar, Kernel::SSE41, Kernel::AVX2}) {
        if (!cpu_runs(kernel)) continue;
        SCOPED_TRACE(kernel_name(kernel));
        Plan plan(mesh.view(), options_for(GetParam(), mesh, kernel, 1));
        const std::size_t n_out = std::size_t(plan.num_output_vertices());

        std::vector<std::vector<float>> single(5, std::vector<float>(n_out));
        for (int c = 0; c < 5; ++c) {
            std::vector<float> in(n_in);
            for (std::size_t v = 0; v < n_in; ++v) in[v] = channels[5 * v + c];
            plan.evaluate(interleaved(in.data(), 1), interleaved(single[c].data(), 1));
        }

        std::vector<float> inter(5 * n_out);
        plan.evaluate(interleaved(channels.data(), 5), interleaved(inter.data(), 5));

        std::vector<float> planar_in(5 * n_in), planar_out(5 * n_out);
        for (std::size_t v = 0; v < n_in; ++v)
            for (int c = 0; c < 5; ++c) planar_in[c * n_in + v] = channels[5 * v + c];
        plan.evaluate(ChannelsView<const float>{planar_in.data(), 5, n_in, 1},
                      ChannelsView<float>{planar_out.data(), 5, n_out, 1});

        const float kPad = -12345.0f;
        std::vector<float> padded_in(8 * n_in, kPad), padded_out(8 * n_out, kPad);
        for (std::size_t v = 0; v < n_in; ++v)
            for (int c = 0; c < 5; ++c) padded_in[8 * v + c] = channels[5 * v + c];
        plan.evaluate(ChannelsView<const float>{padded_in.data(), 5, 1, 8},
                      ChannelsView<float>{padded_out.data(), 5, 1, 8});

        for (int c = 0; c < 5; ++c) {
            SCOPED_TRACE("channel " + std::to_string(c));
            std::vector<float> from_inter(n_out), from_planar(n_out), from_padded(n_out);
            for (std::size_t v = 0; v < n_out; ++v) {
                from_inter[v] = inter[5 * v + c];
                from_planar[v] = planar_out[c * n_out + v];
                from_padded[v] = padded_out[8 * v + c];
            }
            if (kernel == Kernel::Scalar) {
                EXPECT_TRUE(bitwise_equal(single[c], from_inter)) << "interleaved";
                EXPECT_TRUE(bitwise_equal(single[c], from_planar)) << "planar";
                EXPECT_TRUE(bitwise_equal(single[c], from_padded)) << "padded";
            } else {
                EXPECT_LE(max_relative_difference(single[c], from_inter), 1e-6) << "interleaved";
                EXPECT_LE(max_relative_difference(single[c], from_planar), 1e-6) << "planar";
                EXPECT_LE(max_relative_difference(single[c], from_padded), 1e-6) << "padded";
            }
        }
        int touched_padding = 0;
        for (std::size_t v = 0; v < n_out; ++v)
            for (int c = 5; c < 8; ++c) touched_padding += padded_out[8 * v + c] != kPad;
        EXPECT_EQ(touched_padding, 0) << "evaluate wrote outside the channels of the view";
    }
}

INSTANTIATE_TEST_SUITE_P(Evaluation, PathsAgree, ::testing::ValuesIn(path_cases()),
                         [](const ::testing::TestParamInfo<PathCase>& info) { return info.param.name; });

// Large enough that two threads really split the levels (icosphere of 5,120 triangles to level 3), with
// semi-sharp creases so that the special-vertex lists are split too; three threads cut the work into other pieces.
TEST(PathsAgreeLarge, MoreThreadsEqualOneOnIcosphere5120) {
    TestMesh mesh = icosphere(4);
    jitter(mesh, 97, 0.005f);
    add_random_creases(mesh, 97, 0.05, true);
    for (Kernel kernel : {Kernel::Scalar, Kernel::Auto}) {
        Options options;
        options.rules = Rules::OpenSubdiv;
        options.levels = 3;
        options.kernel = kernel;
        Plan one(mesh.view(), options);
        const std::vector<float> expected = evaluate_positions(one, mesh);
        for (int threads : {2, 3}) {
            SCOPED_TRACE(std::string(kernel_name(kernel)) + ", threads " + std::to_string(threads));
            options.threads = threads;
            Plan more(mesh.view(), options);
            EXPECT_TRUE(bitwise_equal(expected, evaluate_positions(more, mesh)));
            ASSERT_EQ(one.num_output_triangles(), more.num_output_triangles());
            EXPECT_TRUE(std::equal(one.output_triangles(), one.output_triangles() + 3 * one.num_output_triangles(),
                                   more.output_triangles()));
            EXPECT_EQ(output_edges(one), output_edges(more));
        }
    }
}

}  // namespace
}  // namespace loopsub::testing
