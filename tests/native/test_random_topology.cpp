// Arbitrary triangle soups through both rule sets: a refinement either refuses its input with a clear error or
// gives a well-formed result. Whatever an artist's mesh looks like (fins, bowties, flipped or doubled faces, loose
// vertices, tags anywhere), the native module must not crash Blender; under the sanitizer build this test is the
// one that would show an out-of-bounds access on such topology.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "loopsub/loopsub.h"

namespace {

using loopsub::MeshData;

// Few vertices for many triangles, so that edges are shared by three or more faces, fans touch at single vertices,
// faces repeat with either winding; some triangles are degenerate on purpose.
MeshData random_soup(std::mt19937& rng) {
    MeshData mesh;
    const int vertices = std::uniform_int_distribution<int>(3, 14)(rng);
    const int triangles = std::uniform_int_distribution<int>(1, 24)(rng);
    std::uniform_real_distribution<float> coordinate(-1.0f, 1.0f);
    for (int i = 0; i < 3 * vertices; ++i) mesh.positions.push_back(coordinate(rng));
    std::uniform_int_distribution<int> vertex(0, vertices - 1);
    std::bernoulli_distribution allow_degenerate(0.05);
    for (int f = 0; f < triangles; ++f) {
        int a = vertex(rng), b = vertex(rng), c = vertex(rng);
        while (!allow_degenerate(rng) && (a == b || b == c || a == c))
            a = vertex(rng), b = vertex(rng), c = vertex(rng);
        mesh.triangles.insert(mesh.triangles.end(), {a, b, c});
    }
    std::uniform_real_distribution<float> sharpness(0.0f, 12.0f);
    const int creases = std::uniform_int_distribution<int>(0, triangles)(rng);
    for (int k = 0; k < creases; ++k) {
        // Mostly edges of the mesh, sometimes a pair that is not one (which must be refused, not ignored).
        const int f = std::uniform_int_distribution<int>(0, triangles - 1)(rng), corner = f % 3;
        const bool real_edge = std::bernoulli_distribution(0.9)(rng);
        mesh.add_crease(mesh.triangles[3 * f + corner],
                        real_edge ? mesh.triangles[3 * f + (corner + 1) % 3] : vertex(rng), sharpness(rng));
    }
    const int corners = std::uniform_int_distribution<int>(0, 3)(rng);
    for (int k = 0; k < corners; ++k) mesh.add_corner(vertex(rng), sharpness(rng));
    const int cones = std::uniform_int_distribution<int>(0, 2)(rng);
    for (int k = 0; k < cones; ++k) mesh.cone_vertices.push_back(vertex(rng));
    return mesh;
}

// The soup's own edges (MeshView::triangle_edges): numbered by their ends, but a tenth of the corners with a number of
// their own (a second edge on the same ends, as a refined level has next to a valence-2 vertex, or several), and one
// soup in eight with a number out of range or on other ends.
std::vector<std::int32_t> random_triangle_edges(const MeshData& mesh, std::mt19937& rng) {
    std::map<std::pair<std::int32_t, std::int32_t>, std::int32_t> number_of_ends;
    std::vector<std::int32_t> edges(mesh.triangles.size());
    std::bernoulli_distribution own(0.1);
    for (std::size_t c = 0; c < edges.size(); ++c) {
        const std::int32_t a = mesh.triangles[c], b = mesh.triangles[c - c % 3 + (c + 1) % 3];
        edges[c] =
            own(rng) ? std::int32_t(c) : number_of_ends.try_emplace(std::minmax(a, b), std::int32_t(c)).first->second;
    }
    if (std::bernoulli_distribution(0.125)(rng))
        edges[std::uniform_int_distribution<std::size_t>(0, edges.size() - 1)(rng)] =
            std::uniform_int_distribution<std::int32_t>(-1, std::int32_t(edges.size()))(rng);
    return edges;
}

TEST(RandomTopology, RefinesOrRefusesCleanly) {
    std::mt19937 rng(20261121);
    int refined = 0, refused = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const MeshData mesh = random_soup(rng);
        loopsub::Options options;
        options.rules = trial % 2 ? loopsub::Rules::OpenSubdiv : loopsub::Rules::Hoppe94;
        options.levels = trial % 4;
        options.boundary = trial % 3 ? loopsub::Boundary::EdgesOnly : loopsub::Boundary::EdgesAndCorners;
        options.crease_method = trial % 5 ? loopsub::CreaseMethod::Uniform : loopsub::CreaseMethod::Chaikin;
        options.crease_threshold = trial % 7 ? 0.0f : 3.0f;
        options.threads = 1 + trial % 2;
        SCOPED_TRACE("trial " + std::to_string(trial));
        loopsub::MeshView view = mesh.view();
        std::vector<std::int32_t> edges;
        if (trial % 3 == 0) {
            edges = random_triangle_edges(mesh, rng);
            view.triangle_edges = edges.data();
            options.limit_surface = trial % 2 == 0;
        }
        try {
            loopsub::Plan plan(view, options);
            std::vector<float> out(3 * std::size_t(plan.num_output_vertices()));
            plan.evaluate(loopsub::interleaved(mesh.positions.data(), 3), loopsub::interleaved(out.data(), 3));
            ++refined;

            ASSERT_EQ(plan.num_output_triangles(), mesh.num_triangles() << (2 * options.levels));
            for (int i = 0; i < 3 * plan.num_output_triangles(); ++i) {
                ASSERT_GE(plan.output_triangles()[i], 0);
                ASSERT_LT(plan.output_triangles()[i], plan.num_output_vertices());
            }
            // Every output point is an affine combination of input points: finite and inside their bounding box.
            float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
            for (int v = 0; v < mesh.num_vertices(); ++v)
                for (int c = 0; c < 3; ++c)
                    lo[c] = std::min(lo[c], mesh.positions[3 * v + c]),
                    hi[c] = std::max(hi[c], mesh.positions[3 * v + c]);
            for (std::size_t i = 0; i < out.size(); ++i) {
                ASSERT_TRUE(std::isfinite(out[i]));
                // Loop's masks have negative-free weights except OpenSubdiv's Chaikin blend (weights can exceed 1):
                // allow a margin of the box size rather than none.
                const int c = int(i % 3);
                const float margin = 0.5f * (hi[c] - lo[c]) + 1e-5f;
                ASSERT_GE(out[i], lo[c] - margin);
                ASSERT_LE(out[i], hi[c] + margin);
            }
            // The output tags name edges and vertices of the output.
            for (std::int32_t v : plan.output_crease_edges()) ASSERT_LT(v, plan.num_output_vertices());
            for (std::int32_t v : plan.output_corner_vertices()) ASSERT_LT(v, plan.num_output_vertices());
        } catch (const loopsub::InputError& error) {
            ++refused;
            EXPECT_GT(std::string(error.what()).size(), 10u);  // a message that says something
        }
    }
    // Both outcomes occur, so both paths are exercised.
    EXPECT_GT(refined, 100);
    EXPECT_GT(refused, 20);
}

// The limit surface over two levels or three takes the last level's rings from its grandparent wherever the soup
// allows (fins, bowties and flipped faces are sharp features, whose neighbourhoods are built): the same bits as from
// rings built and stored for the whole last level, positions and normals alike, or the same refusal.
TEST(RandomTopology, LimitFromTheGrandparentIsTheStoredRingsBitForBit) {
    std::mt19937 rng(20261127);
    int compared = 0;
    for (int trial = 0; trial < 300; ++trial) {
        const MeshData mesh = random_soup(rng);
        loopsub::Options options;
        options.rules = trial % 2 ? loopsub::Rules::OpenSubdiv : loopsub::Rules::Hoppe94;
        options.levels = 2 + trial % 2;
        options.boundary = trial % 3 ? loopsub::Boundary::EdgesOnly : loopsub::Boundary::EdgesAndCorners;
        options.crease_method = trial % 5 ? loopsub::CreaseMethod::Uniform : loopsub::CreaseMethod::Chaikin;
        options.limit_surface = true;
        options.threads = 1 + trial % 2;
        loopsub::Options stored_options = options;
        stored_options.level_tables = loopsub::LevelTables::Stored;
        SCOPED_TRACE("trial " + std::to_string(trial));
        std::string refusals[2];
        std::vector<float> positions[2], normals[2], corner_normals[2];
        for (int k = 0; k < 2; ++k) {
            try {
                loopsub::Plan plan(mesh.view(), k == 0 ? options : stored_options);
                positions[k].resize(3 * std::size_t(plan.num_output_vertices()));
                normals[k].resize(3 * std::size_t(plan.num_limit_normals()));
                corner_normals[k].resize(9 * std::size_t(plan.num_output_triangles()));
                const auto in = loopsub::interleaved(mesh.positions.data(), 3);
                plan.evaluate(in, loopsub::interleaved(positions[k].data(), 3),
                              loopsub::Plan::LimitNormals{normals[k].data()});
                plan.evaluate(in, loopsub::interleaved(positions[k].data(), 3), corner_normals[k].data());
            } catch (const loopsub::InputError& error) { refusals[k] = error.what(); }
        }
        ASSERT_EQ(refusals[0], refusals[1]);
        if (!refusals[0].empty()) continue;
        ++compared;
        // memcmp-like equality: NaN never appears (a refinement's points are finite), so == on floats is exact here.
        EXPECT_EQ(positions[0], positions[1]);
        EXPECT_EQ(normals[0], normals[1]);
        EXPECT_EQ(corner_normals[0], corner_normals[1]);
    }
    EXPECT_GT(compared, 100);
}

}  // namespace
