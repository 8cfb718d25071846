// The compact limit normals (Plan::num_limit_normals, corner_normal_indices, evaluate with LimitNormals), checked
// against the per-corner normals: gathered by the indices they are those normals bit for bit, and the indices at an
// edge's end differ exactly where the per-corner normals of random positions do.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "loopsub/loopsub.h"
#include "mesh_gen.h"

namespace loopsub::testing {
namespace {

struct Case {
    std::string name;
    TestMesh mesh;
    Rules rules;
};

std::vector<Case> cases() {
    std::vector<Case> out;
    TestMesh creased = icosphere(2);
    jitter(creased, 3, 0.02f);
    add_random_creases(creased, 3, 0.15, false);
    add_random_corners(creased, 3, 4, false);
    out.push_back({"sharp creases and corners, hoppe94", creased, Rules::Hoppe94});
    out.push_back({"sharp creases and corners, opensubdiv", creased, Rules::OpenSubdiv});
    TestMesh semi = icosphere(2);
    jitter(semi, 5, 0.02f);
    add_random_creases(semi, 5, 0.15, true);
    add_random_corners(semi, 5, 4, true);
    out.push_back({"semi-sharp, opensubdiv", semi, Rules::OpenSubdiv});
    out.push_back({"grid (boundary)", grid(5, 4), Rules::OpenSubdiv});
    out.push_back({"fin on a grid (non-manifold edges)", fin_on_grid(), Rules::OpenSubdiv});
    out.push_back({"bowtie (non-manifold vertex)", bowtie(5), Rules::Hoppe94});
    return out;
}

std::vector<float> random_positions(int num_vertices, unsigned seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<float> unit(0.0f, 1.0f);
    std::vector<float> positions(3 * std::size_t(num_vertices));
    for (float& x : positions) x = unit(random);
    return positions;
}

Options limit_options(Rules rules, int levels, int threads = 1) {
    Options options;
    options.rules = rules;
    options.levels = levels;
    options.limit_surface = true;
    options.threads = threads;
    return options;
}

TEST(CompactLimitNormals, GatheredByTheirIndicesAreThePerCornerNormals) {
    for (const Case& c : cases())
        for (int levels = 0; levels <= 2; ++levels)
            for (int threads = 1; threads <= 2; ++threads) {
                SCOPED_TRACE(c.name + ", levels " + std::to_string(levels) + ", threads " + std::to_string(threads));
                Plan plan(c.mesh.view(), limit_options(c.rules, levels, threads));
                const int nv = plan.num_output_vertices(), corners = 3 * plan.num_output_triangles();
                const std::vector<float> in = c.mesh.positions;
                std::vector<float> out(3 * std::size_t(nv)), corner_normals(3 * std::size_t(corners));
                plan.evaluate(interleaved(in.data(), 3), interleaved(out.data(), 3), corner_normals.data());
                std::vector<float> compact_out(out.size()), normals(3 * std::size_t(plan.num_limit_normals()));
                plan.evaluate(interleaved(in.data(), 3), interleaved(compact_out.data(), 3),
                              Plan::LimitNormals{normals.data()});
                EXPECT_EQ(out, compact_out);
                ASSERT_GE(plan.num_limit_normals(), nv);
                const std::int32_t* index = plan.corner_normal_indices();
                const std::int32_t* triangles = plan.output_triangles();
                std::vector<int> side_vertex(std::size_t(plan.num_limit_normals() - nv), -1);
                for (int k = 0; k < corners; ++k) {
                    ASSERT_GE(index[k], 0) << "corner " << k;
                    ASSERT_LT(index[k], plan.num_limit_normals()) << "corner " << k;
                    // A corner takes its own vertex's normal or a side's, and a side is one vertex's.
                    if (index[k] < nv) {
                        ASSERT_EQ(index[k], triangles[k]) << "corner " << k;
                    } else {
                        int& vertex = side_vertex[std::size_t(index[k] - nv)];
                        if (vertex < 0) vertex = triangles[k];
                        ASSERT_EQ(vertex, triangles[k]) << "corner " << k;
                    }
                    for (int a = 0; a < 3; ++a)
                        ASSERT_EQ(normals[3 * std::size_t(index[k]) + a], corner_normals[3 * std::size_t(k) + a])
                            << "corner " << k;
                }
                // Every side is some corners' normal.
                for (int vertex : side_vertex) EXPECT_GE(vertex, 0);
            }
}

// Each kernel takes the normals from the loads of its limit points (kernels_limit.h): asking for them leaves the limit
// positions the same bits, with positions alone or beside other channels (the first four channels run together), and
// the normals agree with the scalar reference's within the kernels' rounding (multiply-adds contracted or not).
TEST(CompactLimitNormals, LeaveTheLimitPointsAsTheyAreInEveryKernel) {
    for (const Case& c : cases())
        for (int channels : {3, 5}) {
            std::vector<float> in(std::size_t(channels) * c.mesh.positions.size() / 3);
            const std::vector<float> extra = random_positions(int(in.size()), 7);
            for (std::size_t v = 0; v < c.mesh.positions.size() / 3; ++v)
                for (int k = 0; k < channels; ++k)
                    in[v * channels + k] = k < 3 ? c.mesh.positions[3 * v + k] : extra[v * channels + k];
            std::vector<float> reference;
            for (Kernel kernel : {Kernel::Scalar, Kernel::SSE41, Kernel::AVX2}) {
                SCOPED_TRACE(c.name + ", " + std::to_string(channels) + " channels, " + kernel_name(kernel));
                Options options = limit_options(c.rules, 2);
                options.kernel = kernel;
                Plan plan(c.mesh.view(), options);
                if (plan.kernel() != kernel) continue;  // not on this CPU
                const std::size_t size = std::size_t(channels) * std::size_t(plan.num_output_vertices());
                std::vector<float> alone(size), beside(size), normals(3 * std::size_t(plan.num_limit_normals()));
                plan.evaluate(interleaved(in.data(), channels), interleaved(alone.data(), channels));
                plan.evaluate(interleaved(in.data(), channels), interleaved(beside.data(), channels),
                              Plan::LimitNormals{normals.data()});
                EXPECT_EQ(alone, beside);
                if (kernel == Kernel::Scalar) reference = normals;
                ASSERT_EQ(normals.size(), reference.size());
                for (std::size_t i = 0; i < normals.size(); ++i)
                    ASSERT_NEAR(normals[i], reference[i], 1e-5) << "component " << i;
            }
        }
}

// A surface plans its limit from the last level's grandparent (LimitTables::from_grandparent: no level before the
// last, no rings stored for most vertices, the SIMD kernels by kind, their LimitFn again for the vertices next to
// tags) unless its tables are to be stored: the same bits either way. Positions alone and beside other channels,
// compact and per-corner normals, a UV layer's values, in every kernel, on one thread and three, two levels and three
// (the grandparent the input and a split level), on surfaces with vertices of valence 3 to 9, with a UV layer and
// without; with boundaries, with sharp and semi-sharp creases and corners, darts and Hoppe 94's cones (without a UV
// layer: with one and tags the level before the last is built); and at non-manifold places, which are sharp.
TEST(CompactLimitNormals, FromTheGrandparentAreThoseFromStoredRings) {
    TestMesh sphere = icosphere(1);
    jitter(sphere, 11, 0.05f);
    struct Tagged {
        TestMesh mesh;
        Rules rules;
    };
    TestMesh pillow;  // two triangles on the same three vertices, facing apart: closed, every fan two faces
    pillow.name = "pillow";
    pillow.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0.5f};
    pillow.triangles = {0, 1, 2, 0, 2, 1};
    std::vector<Tagged> meshes;
    for (TestMesh mesh : {icosahedron(), sphere, torus(5, 6), bipyramid(9), cube(), bipyramid(3), pillow})
        meshes.push_back({mesh, Rules::OpenSubdiv});
    TestMesh creased = icosphere(2), semi = icosphere(2);
    jitter(creased, 3, 0.02f), jitter(semi, 5, 0.02f);
    add_random_creases(creased, 3, 0.15, false), add_random_corners(creased, 3, 4, false);
    add_random_creases(semi, 5, 0.15, true), add_random_corners(semi, 5, 4, true);
    TestMesh cones = creased;
    cones.cone_vertices = {0, 5, 17};
    TestMesh dart = icosahedron();
    dart.add_crease(0, dart.triangles[1]);  // one sharp edge: a dart at each end
    // Not manifold at a few places, as meshes from elsewhere often are: an edge of three faces, a vertex where two fans
    // meet, a face the other way round from its neighbours, two spheres sharing a vertex.
    TestMesh flipped = grid(5, 4);
    flipped.name = "grid_with_a_flipped_face";
    std::swap(flipped.triangles[7], flipped.triangles[8]);
    TestMesh touching = icosahedron();  // and a copy moved out by twice its vertex 0, whose antipode meets it there
    touching.name = "two_icosahedra_at_a_vertex";
    const std::vector<float> at = touching.positions;
    const std::vector<int> faces = touching.triangles;
    std::vector<int> placed;  // each vertex's number in the copy
    for (std::size_t v = 0; v < at.size() / 3; ++v) {
        const bool antipode = at[3 * v] == -at[0] && at[3 * v + 1] == -at[1] && at[3 * v + 2] == -at[2];
        placed.push_back(antipode ? 0 : touching.num_vertices());
        if (!antipode)
            for (int k = 0; k < 3; ++k)
                touching.positions.push_back(at[3 * v + std::size_t(k)] + 2.0f * at[std::size_t(k)]);
    }
    for (int corner : faces) touching.triangles.push_back(placed[std::size_t(corner)]);
    for (TestMesh mesh : {grid(5, 4), open_cylinder(7, 2), hemisphere(1), fin_on_grid(), bowtie(4), flipped, touching})
        for (Rules rules : {Rules::OpenSubdiv, Rules::Hoppe94}) meshes.push_back({mesh, rules});
    meshes.push_back({creased, Rules::OpenSubdiv});
    meshes.push_back({creased, Rules::Hoppe94});
    meshes.push_back({semi, Rules::OpenSubdiv});
    meshes.push_back({cones, Rules::Hoppe94});
    meshes.push_back({dart, Rules::OpenSubdiv});
    for (Tagged& tagged : meshes) {
        TestMesh& mesh = tagged.mesh;
        add_uvs_with_seam(mesh);
        const FaceVaryingLayer layer{mesh.triangle_uvs.data(), int(mesh.uvs.size() / 2)};
        MeshView with_layer = mesh.view();
        with_layer.face_varying = &layer;
        with_layer.num_face_varying = 1;
        for (const MeshView& view : {mesh.view(), with_layer})
            for (int levels = 2; levels <= 3; ++levels)
                for (int channels : {3, 5})
                    for (int threads : {1, 3})
                        for (Kernel kernel : {Kernel::Scalar, Kernel::SSE41, Kernel::AVX2}) {
                            SCOPED_TRACE(mesh.name + (view.num_face_varying ? " with UVs" : "") + ", levels " +
                                         std::to_string(levels) + ", " + std::to_string(channels) + " channels, " +
                                         std::to_string(threads) + " threads, " + kernel_name(kernel));
                            Options options = limit_options(tagged.rules, levels, threads);
                            options.kernel = kernel;
                            Plan plan(view, options);
                            if (plan.kernel() != kernel) continue;  // not on this CPU
                            options.level_tables = LevelTables::Stored;
                            Plan stored(view, options);
                            ASSERT_EQ(plan.num_limit_normals(), stored.num_limit_normals());
                            std::vector<float> in(std::size_t(channels) * std::size_t(mesh.num_vertices()));
                            const std::vector<float> extra = random_positions(int(in.size()), 13);
                            for (std::size_t v = 0; v < std::size_t(mesh.num_vertices()); ++v)
                                for (int k = 0; k < channels; ++k)
                                    in[v * channels + k] = k < 3 ? mesh.positions[3 * v + k] : extra[v * channels + k];
                            const std::size_t size = std::size_t(channels) * std::size_t(plan.num_output_vertices());
                            std::vector<float> values[2], normals[2], corner_normals[2], uvs[2];
                            Plan* plans[2] = {&plan, &stored};
                            for (int k = 0; k < 2; ++k) {
                                values[k].resize(size), normals[k].resize(3 * std::size_t(plan.num_limit_normals()));
                                corner_normals[k].resize(9 * std::size_t(plan.num_output_triangles()));
                                std::vector<float> alone(size);
                                plans[k]->evaluate(interleaved(in.data(), channels),
                                                   interleaved(alone.data(), channels));
                                plans[k]->evaluate(interleaved(in.data(), channels),
                                                   interleaved(values[k].data(), channels),
                                                   Plan::LimitNormals{normals[k].data()});
                                EXPECT_EQ(alone, values[k]);
                                plans[k]->evaluate(interleaved(in.data(), channels),
                                                   interleaved(alone.data(), channels), corner_normals[k].data());
                                if (view.num_face_varying == 0) continue;
                                uvs[k].resize(2 * std::size_t(plans[k]->num_output_face_varying_values(0)));
                                plans[k]->evaluate_face_varying(0, interleaved(mesh.uvs.data(), 2),
                                                                interleaved(uvs[k].data(), 2));
                            }
                            EXPECT_EQ(values[0], values[1]);
                            EXPECT_EQ(normals[0], normals[1]);
                            EXPECT_EQ(corner_normals[0], corner_normals[1]);
                            EXPECT_EQ(uvs[0], uvs[1]);
                        }
    }
}

// A fan that sharp edges leave whole (open at a boundary) is one side, whose normal is its vertex's own: an open mesh
// without creases has one normal per vertex, every corner taking its vertex's; unit ones, the boundary's too.
TEST(CompactLimitNormals, AnOpenFanIsItsVertexsOwnRow) {
    for (int levels = 0; levels <= 2; ++levels) {
        SCOPED_TRACE("levels " + std::to_string(levels));
        const TestMesh mesh = grid(5, 4);
        Plan plan(mesh.view(), limit_options(Rules::OpenSubdiv, levels));
        ASSERT_EQ(plan.num_limit_normals(), plan.num_output_vertices());
        const std::int32_t* index = plan.corner_normal_indices();
        for (int k = 0; k < 3 * plan.num_output_triangles(); ++k)
            ASSERT_EQ(index[k], plan.output_triangles()[k]) << "corner " << k;
        std::vector<float> out(3 * std::size_t(plan.num_output_vertices())), normals(out.size());
        plan.evaluate(interleaved(mesh.positions.data(), 3), interleaved(out.data(), 3),
                      Plan::LimitNormals{normals.data()});
        for (std::size_t v = 0; v < normals.size() / 3; ++v) {
            const float length = std::sqrt(normals[3 * v] * normals[3 * v] + normals[3 * v + 1] * normals[3 * v + 1] +
                                           normals[3 * v + 2] * normals[3 * v + 2]);
            ASSERT_NEAR(length, 1.0f, 1e-5) << "vertex " << v;
        }
    }
    // A crease through the middle splits its vertices' fans: they keep rows of their own per side.
    for (const Case& c : cases()) {
        if (c.name.find("sharp creases") == std::string::npos) continue;
        Plan plan(c.mesh.view(), limit_options(c.rules, 1));
        EXPECT_GT(plan.num_limit_normals(), plan.num_output_vertices()) << c.name;
    }
}

// Only infinitely sharp edges (creases, boundaries, non-manifold edges) part a vertex's corners: a vertex on none of
// them has one index for all its corners.
TEST(CompactLimitNormals, CornersOfAVertexOnNoSharpEdgeShareAnIndex) {
    for (const Case& c : cases()) {
        SCOPED_TRACE(c.name);
        Plan plan(c.mesh.view(), limit_options(c.rules, 2));
        const std::vector<std::int32_t>& sharp = plan.output_sharp_edges();
        const std::vector<float>& sharpness = plan.output_sharp_edge_sharpness();
        std::vector<std::uint8_t> on_sharp(std::size_t(plan.num_output_vertices()), 0);
        for (std::size_t e = 0; e < sharpness.size(); ++e)
            if (sharpness[e] >= kInfiniteSharpness)
                on_sharp[std::size_t(sharp[2 * e])] = on_sharp[std::size_t(sharp[2 * e + 1])] = 1;
        std::vector<int> first(std::size_t(plan.num_output_vertices()), -1);
        const std::int32_t* index = plan.corner_normal_indices();
        const std::int32_t* triangles = plan.output_triangles();
        int checked = 0;
        for (int k = 0; k < 3 * plan.num_output_triangles(); ++k) {
            const int v = triangles[k];
            if (on_sharp[std::size_t(v)]) continue;
            int& seen = first[std::size_t(v)];
            if (seen < 0) seen = index[k];
            ASSERT_EQ(index[k], seen) << "corner " << k << " of vertex " << v;
            ++checked;
        }
        EXPECT_GT(checked, 0);
    }
}

// Where the normals split, found independently: per-corner normals of random positions, compared across each edge's
// two faces at each of its ends (generic positions give each side a normal of its own), against the indices there.
TEST(CompactLimitNormals, IndicesDifferAtAnEdgeWherePerCornerNormalsOfRandomPositionsDo) {
    for (const Case& c : cases())
        for (int levels = 1; levels <= 2; ++levels) {
            SCOPED_TRACE(c.name + ", levels " + std::to_string(levels));
            Plan plan(c.mesh.view(), limit_options(c.rules, levels));
            const std::vector<float> in = random_positions(c.mesh.num_vertices(), 11);
            std::vector<float> out(3 * std::size_t(plan.num_output_vertices())),
                normals(9 * std::size_t(plan.num_output_triangles()));
            plan.evaluate(interleaved(in.data(), 3), interleaved(out.data(), 3), normals.data());
            const int num_edges = plan.num_output_edges();
            std::vector<std::int32_t> ends(2 * std::size_t(num_edges)),
                triangle_edges(3 * std::size_t(plan.num_output_triangles()));
            plan.output_edges(ends.data(), triangle_edges.data());
            // Per (edge, vertex), the normals of the corners there, and their indices.
            std::vector<std::set<std::vector<float>>> at_end(2 * std::size_t(num_edges));
            std::vector<std::set<std::int32_t>> indices_at_end(2 * std::size_t(num_edges));
            const std::int32_t* triangles = plan.output_triangles();
            const std::int32_t* index = plan.corner_normal_indices();
            for (std::size_t t = 0; t < triangle_edges.size() / 3; ++t)
                for (int k = 0; k < 3; ++k) {
                    const std::size_t e = std::size_t(triangle_edges[3 * t + k]);
                    for (int corner : {k, (k + 1) % 3}) {
                        const std::size_t c = 3 * t + std::size_t(corner);
                        const std::size_t end = 2 * e + (triangles[c] == ends[2 * e + 1] ? 1 : 0);
                        at_end[end].insert({normals[3 * c], normals[3 * c + 1], normals[3 * c + 2]});
                        indices_at_end[end].insert(index[c]);
                    }
                }
            int splits = 0;
            for (std::size_t end = 0; end < at_end.size(); ++end) {
                const bool split = at_end[end].size() > 1;
                ASSERT_EQ(indices_at_end[end].size() > 1, split)
                    << "edge " << end / 2 << " (" << ends[end - end % 2] << ", " << ends[end - end % 2 + 1] << ")";
                splits += split;
            }
            // A boundary's and a bowtie's sides meet at no edge of two faces.
            if (c.name.find("grid (") == std::string::npos && c.name.find("bowtie") == std::string::npos) {
                EXPECT_GT(splits, 0);
            }
        }
}

TEST(CompactLimitNormals, NeedTheLimitSurface) {
    const TestMesh mesh = icosphere(1);
    Options options;
    options.levels = 1;
    Plan plan(mesh.view(), options);
    std::vector<float> out(3 * std::size_t(plan.num_output_vertices())),
        normals(3 * std::size_t(plan.num_output_vertices()));
    EXPECT_THROW(plan.num_limit_normals(), std::logic_error);
    EXPECT_THROW(plan.corner_normal_indices(), std::logic_error);
    EXPECT_THROW(plan.evaluate(interleaved(mesh.positions.data(), 3), interleaved(out.data(), 3),
                               Plan::LimitNormals{normals.data()}),
                 InputError);
    Plan limit_plan(mesh.view(), limit_options(Rules::OpenSubdiv, 1));
    EXPECT_EQ(limit_plan.num_limit_normals(), limit_plan.num_output_vertices());  // a smooth sphere: no sides
    EXPECT_THROW(limit_plan.evaluate(interleaved(mesh.positions.data(), 3), interleaved(out.data(), 3),
                                     Plan::LimitNormals{nullptr}),
                 InputError);
}

// Holes drop their triangles' corners from the indices as from the triangles.
TEST(CompactLimitNormals, FollowTheTrianglesAroundHoles) {
    TestMesh mesh = icosphere(2);
    add_random_creases(mesh, 9, 0.2, false);
    for (int t = 0; t < mesh.num_triangles(); t += 7) mesh.hole_triangles.push_back(t);
    Plan plan(mesh.view(), limit_options(Rules::OpenSubdiv, 2));
    std::vector<float> out(3 * std::size_t(plan.num_output_vertices())),
        corner_normals(9 * std::size_t(plan.num_output_triangles()));
    std::vector<float> normals(3 * std::size_t(plan.num_limit_normals()));
    plan.evaluate(interleaved(mesh.positions.data(), 3), interleaved(out.data(), 3), corner_normals.data());
    plan.evaluate(interleaved(mesh.positions.data(), 3), interleaved(out.data(), 3),
                  Plan::LimitNormals{normals.data()});
    const std::int32_t* index = plan.corner_normal_indices();
    for (int k = 0; k < 3 * plan.num_output_triangles(); ++k) {
        ASSERT_TRUE(index[k] == plan.output_triangles()[k] || index[k] >= plan.num_output_vertices()) << "corner " << k;
        for (int a = 0; a < 3; ++a)
            ASSERT_EQ(normals[3 * std::size_t(index[k]) + a], corner_normals[3 * std::size_t(k) + a]);
    }
}

}  // namespace
}  // namespace loopsub::testing
