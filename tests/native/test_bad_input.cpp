// Every bad-input class of the issue gives loopsub::InputError (or MemoryLimitError) with a message that says
// what and where, under both rule sets; degenerate-but-legal inputs (empty mesh, 0 levels, isolated vertices,
// non-manifold or mis-oriented triangles) give a result, never a crash.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "loopsub/loopsub.h"
#include "loopsub/tessellation.h"

namespace {

using loopsub::Rules;

const Rules kBothRules[] = {Rules::Hoppe94, Rules::OpenSubdiv};
const char* rules_name(Rules rules) { return rules == Rules::Hoppe94 ? "hoppe94" : "opensubdiv"; }

// A tetrahedron: closed, 4 vertices, 6 edges, 4 triangles.
struct Tetrahedron : loopsub::MeshData {
    Tetrahedron() {
        positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
        triangles = {0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2};
    }
};

loopsub::Options options_for(Rules rules, int levels = 1) {
    loopsub::Options options;
    options.rules = rules;
    options.levels = levels;
    return options;
}

// Builds a plan from `mesh` and expects InputError whose message contains every fragment.
void expect_plan_error(const loopsub::MeshView& mesh, const loopsub::Options& options,
                       std::initializer_list<std::string> fragments) {
    SCOPED_TRACE(rules_name(options.rules));
    try {
        loopsub::Plan plan(mesh, options);
        ADD_FAILURE() << "no InputError";
    } catch (const loopsub::InputError& e) {
        for (const std::string& fragment : fragments) {
            EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos)
                << "'" << fragment << "' not in: " << e.what();
        }
    }
}

std::vector<float> evaluate(loopsub::Plan& plan, const std::vector<float>& positions) {
    std::vector<float> out(std::size_t(plan.num_output_vertices()) * 3);
    plan.evaluate(loopsub::interleaved(positions.data(), 3), loopsub::interleaved(out.data(), 3));
    return out;
}

TEST(BadInput, VertexIndexOutOfRange) {
    for (Rules rules : kBothRules) {
        for (std::int32_t bad : {-1, 4, 1 << 30, std::numeric_limits<std::int32_t>::min()}) {
            Tetrahedron mesh;
            mesh.triangles[4] = bad;  // triangle 1, second corner
            expect_plan_error(mesh.view(), options_for(rules), {"triangle 1", std::to_string(bad)});
        }
    }
}

TEST(BadInput, DegenerateTriangle) {
    for (Rules rules : kBothRules) {
        Tetrahedron mesh;
        mesh.triangles[8] = mesh.triangles[6];  // triangle 2 becomes (1, 2, 1)
        expect_plan_error(mesh.view(), options_for(rules), {"triangle 2", "degenerate"});
    }
}

TEST(BadInput, NonFiniteCoordinatesAreCaughtByEvaluate) {
    for (Rules rules : kBothRules) {
        SCOPED_TRACE(rules_name(rules));
        Tetrahedron mesh;
        loopsub::Plan plan(mesh.view(), options_for(rules));
        for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                          -std::numeric_limits<float>::infinity()}) {
            std::vector<float> positions = mesh.positions;
            positions[3 * 2 + 1] = bad;  // vertex 2, y
            try {
                evaluate(plan, positions);
                ADD_FAILURE() << "no InputError for " << bad;
            } catch (const loopsub::InputError& e) {
                EXPECT_NE(std::string(e.what()).find("vertex 2"), std::string::npos) << e.what();
            }
        }
        // The failed calls leave the plan usable.
        std::vector<float> out = evaluate(plan, mesh.positions);
        for (float value : out) EXPECT_TRUE(std::isfinite(value));
    }
}

// Blender stores an infinite coordinate as the float maximum; 1e38 passes isfinite too. Summing a vertex's ring of
// such values overflows, so evaluate refuses them by name; values up to its bound refine to finite values.
TEST(BadInput, ValuesTooLargeToRefineAreRefused) {
    for (Rules rules : kBothRules) {
        SCOPED_TRACE(rules_name(rules));
        Tetrahedron mesh;
        loopsub::Plan plan(mesh.view(), options_for(rules, 2));
        for (float huge : {1e38f, std::numeric_limits<float>::max(), -3e38f}) {
            std::vector<float> positions = mesh.positions;
            positions[3 * 1 + 2] = huge;  // vertex 1, z
            try {
                evaluate(plan, positions);
                ADD_FAILURE() << "no InputError for " << huge;
            } catch (const loopsub::InputError& e) {
                EXPECT_NE(std::string(e.what()).find("vertex 1 has a value too large"), std::string::npos) << e.what();
            }
        }
        // The new vertices of level 1 have valence 6, so the kernels sum at most 6 values: an eighth of the float
        // maximum is accepted, in every coordinate at once, and refines to finite values.
        std::vector<float> positions(mesh.positions.size());
        for (std::size_t i = 0; i < positions.size(); ++i)
            positions[i] = (i % 2 ? 1.0f : -1.0f) * std::numeric_limits<float>::max() / 8.0f;
        for (float value : evaluate(plan, positions)) EXPECT_TRUE(std::isfinite(value)) << value;
    }
}

// Face-varying values: non-finite ones are refused by triangle and corner; the largest finite ones interpolate to
// finite values (midpoints once overflowed: found by fuzz_plan).
TEST(BadInput, FaceVaryingValuesNonFiniteOrHuge) {
    for (Rules rules : kBothRules) {
        SCOPED_TRACE(rules_name(rules));
        Tetrahedron mesh;
        loopsub::Plan plan(mesh.view(), options_for(rules, 2));
        std::vector<float> corners(4 * 3 * 2, std::numeric_limits<float>::max());
        std::vector<float> out(std::size_t(plan.num_output_triangles()) * 3 * 2);
        plan.evaluate_face_varying(corners.data(), out.data(), 2);
        for (float value : out) EXPECT_EQ(value, std::numeric_limits<float>::max());
        corners[2 * 3 * 2 + 1 * 2 + 1] = std::numeric_limits<float>::quiet_NaN();  // triangle 2, corner 1, channel 1
        try {
            plan.evaluate_face_varying(corners.data(), out.data(), 2);
            ADD_FAILURE() << "no InputError";
        } catch (const loopsub::InputError& e) {
            EXPECT_NE(std::string(e.what()).find("triangle 2, corner 1 has a non-finite value"), std::string::npos)
                << e.what();
        }
    }
}

// A face-varying layer whose corner refers past its values, or has none, is refused with the place; values that are
// not finite are refused by evaluate, as vertex values are.
TEST(BadInput, FaceVaryingLayerIndicesAndValues) {
    for (Rules rules : kBothRules) {
        Tetrahedron mesh;
        std::vector<std::int32_t> corner_values = {0, 1, 2, 0, 2, 3, 2, 1, 3, 0, 3, 1};
        loopsub::FaceVaryingLayer layer{corner_values.data(), 4};
        loopsub::MeshView view = mesh.view();
        view.face_varying = &layer;
        view.num_face_varying = 1;
        corner_values[7] = 4;  // triangle 2, corner 1
        expect_plan_error(view, options_for(rules), {"face-varying layer 0", "triangle 2", "value 4"});
        corner_values[7] = -1;
        expect_plan_error(view, options_for(rules), {"face-varying layer 0", "triangle 2", "value -1"});
        corner_values[7] = 1;
        layer.corner_values = nullptr;
        expect_plan_error(view, options_for(rules), {"face-varying layer 0", "null"});
        layer.corner_values = corner_values.data();

        loopsub::Plan plan(view, options_for(rules, 2));
        std::vector<float> values = {0, 0, 1, 0, 0, 1, std::numeric_limits<float>::infinity(), 1};
        std::vector<float> out(2 * std::size_t(plan.num_output_face_varying_values(0)));
        try {
            plan.evaluate_face_varying(0, loopsub::interleaved(values.data(), 2), loopsub::interleaved(out.data(), 2));
            ADD_FAILURE() << "no InputError";
        } catch (const loopsub::InputError& e) {
            EXPECT_NE(std::string(e.what()).find("non-finite"), std::string::npos) << e.what();
        }
        EXPECT_THROW(plan.output_face_varying_indices(1), std::out_of_range);
    }
}

// Face-varying layers are read by their values' ends, and a tessellation by its edges' ends: neither takes the
// triangles' own edges (MeshView::triangle_edges).
TEST(BadInput, TriangleEdgesWithFaceVaryingLayersOrForATessellation) {
    Tetrahedron mesh;
    std::vector<std::int32_t> edges = {0, 1, 2, 2, 3, 4, 1, 5, 3, 4, 5, 0};
    std::vector<std::int32_t> corner_values = {0, 1, 2, 0, 2, 3, 2, 1, 3, 0, 3, 1};
    loopsub::FaceVaryingLayer layer{corner_values.data(), 4};
    loopsub::MeshView view = mesh.view();
    view.triangle_edges = edges.data();
    view.face_varying = &layer;
    view.num_face_varying = 1;
    expect_plan_error(view, options_for(Rules::OpenSubdiv), {"triangle edges", "face-varying layers"});
    view.face_varying = nullptr, view.num_face_varying = 0;
    try {
        loopsub::Tessellation tessellation(view, options_for(Rules::OpenSubdiv), loopsub::TessellationRates{4});
        ADD_FAILURE() << "no InputError";
    } catch (const loopsub::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("tessellation: triangle_edges are not supported"), std::string::npos)
            << e.what();
    }
}

// Found by fuzz_plan: a face-varying layer on a mesh with vertices but no triangles.
TEST(BadInput, FaceVaryingLayerWithoutTriangles) {
    for (Rules rules : kBothRules) {
        loopsub::MeshData mesh;
        mesh.positions = {0, 0, 0, 1, 0, 0};
        loopsub::FaceVaryingLayer layer{nullptr, 0};
        loopsub::MeshView view = mesh.view();
        view.face_varying = &layer;
        view.num_face_varying = 1;
        loopsub::Options options = options_for(rules, 2);
        options.threads = 2;
        loopsub::Plan plan(view, options);
        EXPECT_EQ(plan.num_output_face_varying_values(0), 0);
        std::vector<float> none;
        plan.evaluate_face_varying(0, loopsub::interleaved(none.data(), 2), loopsub::interleaved(none.data(), 2));
    }
}

TEST(BadInput, HoleOutOfRange) {
    for (Rules rules : kBothRules) {
        for (std::int32_t bad : {-1, 4}) {
            Tetrahedron mesh;
            mesh.hole_triangles = {1, bad};
            expect_plan_error(mesh.view(), options_for(rules), {"hole 1", "triangle " + std::to_string(bad)});
        }
    }
}

TEST(BadInput, CreaseEdgeThatIsNotAnEdge) {
    for (Rules rules : kBothRules) {
        // A quad of two triangles: 0-2 is its diagonal, 1-3 is not an edge.
        std::vector<std::int32_t> triangles = {0, 1, 2, 0, 2, 3};
        std::vector<std::int32_t> crease = {0, 1, 1, 3};
        std::vector<float> sharpness = {1.0f, 1.0f};
        loopsub::MeshView mesh;
        mesh.num_vertices = 4;
        mesh.triangles = triangles.data();
        mesh.num_triangles = 2;
        mesh.crease_edges = crease.data();
        mesh.crease_sharpness = sharpness.data();
        mesh.num_crease_edges = 2;
        expect_plan_error(mesh, options_for(rules), {"crease edge 1", "not an edge"});

        crease = {2, 2};  // a vertex with itself
        mesh.crease_edges = crease.data();
        mesh.num_crease_edges = 1;
        expect_plan_error(mesh, options_for(rules), {"crease edge 0", "not an edge"});
    }
}

TEST(BadInput, TagIndexOutOfRange) {
    for (Rules rules : kBothRules) {
        for (std::int32_t bad : {-1, 4}) {
            Tetrahedron crease;
            crease.crease_edges = {0, 1, 2, bad};
            crease.crease_sharpness = {1.0f, 1.0f};
            expect_plan_error(crease.view(), options_for(rules), {"crease edge 1", std::to_string(bad)});

            Tetrahedron corner;
            corner.corner_vertices = {bad};
            corner.corner_sharpness = {1.0f};
            expect_plan_error(corner.view(), options_for(rules), {"corner 0", std::to_string(bad)});

            Tetrahedron cone;
            cone.cone_vertices = {0, bad};
            expect_plan_error(cone.view(), options_for(rules), {"cone 1", std::to_string(bad)});
        }
    }
}

TEST(BadInput, NegativeOrNonFiniteSharpness) {
    for (Rules rules : kBothRules) {
        for (float bad :
             {-1.0f, -0.0001f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
            Tetrahedron crease;
            crease.crease_edges = {0, 1};
            crease.crease_sharpness = {bad};
            expect_plan_error(crease.view(), options_for(rules), {"crease edge 0", "sharpness"});

            Tetrahedron corner;
            corner.corner_vertices = {3};
            corner.corner_sharpness = {bad};
            expect_plan_error(corner.view(), options_for(rules), {"corner 0", "sharpness"});
        }
    }
}

TEST(BadInput, BadOptions) {
    for (Rules rules : kBothRules) {
        Tetrahedron mesh;
        expect_plan_error(mesh.view(), options_for(rules, -1), {"levels", "-1"});
        expect_plan_error(mesh.view(), options_for(rules, loopsub::kMaxLevels + 1),
                          {"levels must be between 0 and 64", "65"});
        loopsub::Options options = options_for(rules);
        for (int threads : {0, -1, loopsub::kMaxThreads + 1, std::numeric_limits<int>::max()}) {
            options.threads = threads;
            expect_plan_error(mesh.view(), options, {"threads", std::to_string(threads)});
        }
        for (float bad : {-0.5f, std::numeric_limits<float>::quiet_NaN()}) {
            options = options_for(rules);
            options.crease_threshold = bad;
            expect_plan_error(mesh.view(), options, {"crease threshold"});
        }
    }
}

TEST(BadInput, MissingArraysAndNegativeCounts) {
    for (Rules rules : kBothRules) {
        Tetrahedron mesh;
        loopsub::MeshView view = mesh.view();
        view.triangles = nullptr;
        expect_plan_error(view, options_for(rules), {"triangles"});

        view = mesh.view();
        view.crease_edges = nullptr;
        view.crease_sharpness = nullptr;
        view.num_crease_edges = 1;
        expect_plan_error(view, options_for(rules), {"crease"});

        view = mesh.view();
        view.num_vertices = -4;
        expect_plan_error(view, options_for(rules), {"negative"});
    }
}

// The output of L levels holds at least 4^L * F triangles of three 4-byte indices: the memory error must name a
// requirement no smaller than that (saturated at 2^64 - 1 beyond what 64 bits count).
void expect_memory_error(int levels, std::uint64_t limit) {
    SCOPED_TRACE("levels " + std::to_string(levels) + ", limit " + std::to_string(limit));
    Tetrahedron mesh;
    loopsub::Options options = options_for(Rules::OpenSubdiv, levels);
    options.memory_limit_bytes = limit;
    try {
        loopsub::Plan plan(mesh.view(), options);
        ADD_FAILURE() << "no MemoryLimitError";
    } catch (const loopsub::MemoryLimitError& e) {
        const long double output_bytes = 12.0L * 4.0L * std::pow(4.0L, levels);
        const long double at_least = std::min(output_bytes, (long double)std::numeric_limits<std::uint64_t>::max());
        EXPECT_GE((long double)e.required_bytes, at_least) << e.what();
        EXPECT_GT(e.required_bytes, limit);
        EXPECT_NE(std::string(e.what()).find(std::to_string(e.required_bytes)), std::string::npos)
            << "the message should give the bytes needed: " << e.what();
    }
}

TEST(BadInput, LevelPastTheMemoryLimit) {
    expect_memory_error(3, 1000);
    expect_memory_error(12, loopsub::Options().memory_limit_bytes);
}

// Beyond ~31 levels 4^L triangles no longer fit in 64 bits: the check must not wrap around.
TEST(BadInput, LevelFarPastTheMemoryLimit) {
    for (int levels : {20, 31, 32, 40, loopsub::kMaxLevels})
        expect_memory_error(levels, loopsub::Options().memory_limit_bytes);
}

TEST(BadInput, WrongChannelCount) {
    for (Rules rules : kBothRules) {
        SCOPED_TRACE(rules_name(rules));
        Tetrahedron mesh;
        loopsub::Plan plan(mesh.view(), options_for(rules));
        std::vector<float> out(std::size_t(plan.num_output_vertices()) * 3);
        EXPECT_THROW(plan.evaluate(loopsub::interleaved(mesh.positions.data(), 3), loopsub::interleaved(out.data(), 2)),
                     loopsub::InputError);
        EXPECT_THROW(plan.evaluate(loopsub::interleaved(mesh.positions.data(), 0), loopsub::interleaved(out.data(), 0)),
                     loopsub::InputError);
        std::vector<float> uv_in(4 * 3 * 2), uv_out(16 * 3 * 2);
        EXPECT_THROW(plan.evaluate_face_varying(uv_in.data(), uv_out.data(), 0), loopsub::InputError);
    }
}

// Every kernel, since each walks its channels with its own pointer arithmetic (the scalar one once stepped off a
// null output pointer here: found by fuzz_plan).
const loopsub::Kernel kAllKernels[] = {loopsub::Kernel::Scalar, loopsub::Kernel::SSE41, loopsub::Kernel::AVX2};

TEST(EdgeCases, EmptyMeshGivesAnEmptyResult) {
    for (Rules rules : kBothRules) {
        for (loopsub::Kernel kernel : kAllKernels) {
            SCOPED_TRACE(std::string(rules_name(rules)) + " " + loopsub::kernel_name(kernel));
            loopsub::MeshView empty;
            loopsub::Options options = options_for(rules, 3);
            options.kernel = kernel;
            loopsub::Plan plan(empty, options);
            EXPECT_EQ(plan.num_output_vertices(), 0);
            EXPECT_EQ(plan.num_output_triangles(), 0);
            EXPECT_TRUE(plan.output_crease_edges().empty());
            std::vector<float> none;
            EXPECT_TRUE(evaluate(plan, none).empty());
            plan.evaluate_face_varying(nullptr, nullptr, 2);
        }
    }
}

// Vertices but no triangles (an OBJ whose faces were lost): nothing to refine, every vertex stays, at every level
// (refining a level whose vertices have no edges once bound a reference to a null pointer: found by fuzz_obj).
TEST(EdgeCases, VerticesWithoutTrianglesStayWhereTheyAre) {
    for (Rules rules : kBothRules) {
        for (loopsub::Kernel kernel : kAllKernels) {
            SCOPED_TRACE(std::string(rules_name(rules)) + " " + loopsub::kernel_name(kernel));
            loopsub::MeshData mesh;
            mesh.positions = {1, 2, 3, 4, 5, 6};
            loopsub::Options options = options_for(rules, 2);
            options.kernel = kernel;
            loopsub::Plan plan(mesh.view(), options);
            EXPECT_EQ(plan.num_output_triangles(), 0);
            EXPECT_EQ(evaluate(plan, mesh.positions), mesh.positions);
        }
    }
}

// A semi-sharp corner tag on a vertex in no triangle, with the limit surface: its sharpness outlasts every level, but
// it has no ring to refine until it is spent, and stays where it is (once a reference to a null pointer: found by
// fuzz_plan). Alone, and beside a triangle.
TEST(EdgeCases, SemiSharpVertexInNoTriangleStaysOnTheLimitSurface) {
    for (bool with_triangle : {false, true}) {
        SCOPED_TRACE(with_triangle ? "beside a triangle" : "alone");
        loopsub::MeshData mesh;
        mesh.positions = {1, 2, 3, 0, 0, 0, 1, 0, 0, 0, 1, 0};
        if (with_triangle) mesh.triangles = {1, 2, 3};
        mesh.corner_vertices = {0};
        mesh.corner_sharpness = {3.5f};
        loopsub::Options options = options_for(Rules::OpenSubdiv, 2);
        options.limit_surface = true;
        loopsub::Plan plan(mesh.view(), options);
        const std::vector<float> out = evaluate(plan, mesh.positions);
        EXPECT_EQ(std::vector<float>(out.begin(), out.begin() + 3), std::vector<float>({1, 2, 3}));
    }
}

TEST(EdgeCases, ZeroLevelsReturnsTheInputUnchanged) {
    for (Rules rules : kBothRules) {
        SCOPED_TRACE(rules_name(rules));
        Tetrahedron mesh;
        mesh.crease_edges = {0, 1};
        mesh.crease_sharpness = {2.5f};
        mesh.corner_vertices = {3};
        mesh.corner_sharpness = {10.0f};
        loopsub::Plan plan(mesh.view(), options_for(rules, 0));
        EXPECT_EQ(plan.num_output_vertices(), 4);
        ASSERT_EQ(plan.num_output_triangles(), 4);
        EXPECT_EQ(std::vector<std::int32_t>(plan.output_triangles(), plan.output_triangles() + 12), mesh.triangles);
        EXPECT_EQ(std::vector<std::int32_t>(plan.output_parent_triangles(), plan.output_parent_triangles() + 4),
                  (std::vector<std::int32_t>{0, 1, 2, 3}));
        EXPECT_EQ(evaluate(plan, mesh.positions), mesh.positions);
        EXPECT_EQ(plan.output_crease_sharpness(), mesh.crease_sharpness);
        ASSERT_EQ(plan.output_crease_edges().size(), 2u);
        EXPECT_EQ(std::min(plan.output_crease_edges()[0], plan.output_crease_edges()[1]), 0);
        EXPECT_EQ(std::max(plan.output_crease_edges()[0], plan.output_crease_edges()[1]), 1);
        EXPECT_EQ(plan.output_corner_vertices(), mesh.corner_vertices);
        EXPECT_EQ(plan.output_corner_sharpness(), mesh.corner_sharpness);

        std::vector<float> uvs(4 * 3 * 2);
        for (std::size_t k = 0; k < uvs.size(); ++k) uvs[k] = 0.01f * float(k);
        std::vector<float> uvs_out(uvs.size());
        plan.evaluate_face_varying(uvs.data(), uvs_out.data(), 2);
        EXPECT_EQ(uvs_out, uvs);
    }
}

TEST(EdgeCases, IsolatedVerticesStayWhereTheyAre) {
    for (Rules rules : kBothRules) {
        SCOPED_TRACE(rules_name(rules));
        Tetrahedron mesh;
        // Vertices 4 and 5 are in no triangle; 5 also carries a corner and a cone tag.
        mesh.positions.insert(mesh.positions.end(), {5, 6, 7, -1, -2, -3});
        mesh.corner_vertices = {5};
        mesh.corner_sharpness = {1.0f};
        if (rules == Rules::Hoppe94) mesh.cone_vertices = {5};
        loopsub::Plan plan(mesh.view(), options_for(rules, 2));
        EXPECT_EQ(plan.num_output_triangles(), 4 * 16);
        std::vector<float> out = evaluate(plan, mesh.positions);
        for (float value : out) ASSERT_TRUE(std::isfinite(value));
        for (int k = 12; k < 18; ++k)
            EXPECT_EQ(out[std::size_t(k)], mesh.positions[std::size_t(k)]) << "coordinate " << k;
    }
}

// Legal but unusual topology: an edge with three triangles, a bowtie vertex, a triangle repeated with the same
// and the opposite winding, neighbours with inconsistent winding. Made sharp where OpenSubdiv does; never a crash.
TEST(EdgeCases, NonManifoldAndMisorientedTopologyGivesAFiniteResult) {
    struct Case {
        const char* name;
        std::vector<std::int32_t> triangles;
    };
    const std::vector<Case> cases = {
        {"edge 0-1 in three triangles", {0, 1, 2, 1, 0, 3, 0, 1, 4}},
        {"two triangles sharing only vertex 0", {0, 1, 2, 0, 3, 4}},
        {"the same triangle twice", {0, 1, 2, 0, 1, 2}},
        {"a triangle and its reverse", {0, 1, 2, 0, 2, 1}},
        {"neighbours across 0-1 wound the same way", {0, 1, 2, 0, 1, 3}},
    };
    const std::vector<float> positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
    for (Rules rules : kBothRules) {
        for (const Case& c : cases) {
            SCOPED_TRACE(std::string(rules_name(rules)) + ": " + c.name);
            const std::vector<std::int32_t>& triangles = c.triangles;
            loopsub::MeshView mesh;
            mesh.num_vertices = 5;
            mesh.triangles = triangles.data();
            mesh.num_triangles = int(triangles.size() / 3);
            try {
                loopsub::Plan plan(mesh, options_for(rules, 2));
                EXPECT_EQ(plan.num_output_triangles(), mesh.num_triangles * 16);
                for (float value : evaluate(plan, positions)) ASSERT_TRUE(std::isfinite(value));
            } catch (const loopsub::InputError& e) {
                EXPECT_GT(std::string(e.what()).size(), 10u) << "a refusal must say why";
            }
        }
    }
}

}  // namespace
