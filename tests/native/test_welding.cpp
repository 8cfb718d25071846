// loopsub::weld_corner_values and gather_welded_values: per-corner values welded into shared ones (the CLI's normals,
// the Python module's per-corner UVs), checked by hand and against a plain quadratic reference.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "loopsub/loopsub.h"

namespace {

struct Welded {
    std::vector<std::int32_t> indices;
    std::vector<float> values;
};

Welded weld(const std::vector<std::int32_t>& triangles, int num_vertices, const std::vector<float>& corner_values,
            int channels) {
    const int num_triangles = int(triangles.size() / 3);
    Welded w;
    w.indices.assign(triangles.size(), -1);
    const int count = loopsub::weld_corner_values(w.indices.data(), triangles.data(), num_triangles, num_vertices,
                                                  corner_values.data(), channels);
    w.values.assign(std::size_t(count) * std::size_t(channels), NAN);
    loopsub::gather_welded_values(w.values.data(), w.indices.data(), num_triangles, corner_values.data(), channels);
    return w;
}

std::uint32_t bits(float value) {
    std::uint32_t b;
    std::memcpy(&b, &value, sizeof b);
    return b;
}

// Written the slow, obvious way: vertex by vertex, each corner's value looked up among the vertex's values so far.
Welded reference(const std::vector<std::int32_t>& triangles, int num_vertices, const std::vector<float>& corner_values,
                 int channels) {
    const std::size_t w = std::size_t(channels);
    Welded r;
    r.indices.assign(triangles.size(), -1);
    for (int v = 0; v < num_vertices; ++v) {
        const std::size_t first_of_vertex = r.values.size() / w;
        for (std::size_t c = 0; c < triangles.size(); ++c) {
            if (triangles[c] != v) continue;
            std::size_t k = first_of_vertex;
            for (; k < r.values.size() / w; ++k) {
                bool same = true;
                for (std::size_t j = 0; j < w; ++j) same = same && r.values[k * w + j] == corner_values[c * w + j];
                if (same) break;
            }
            if (k == r.values.size() / w)
                r.values.insert(r.values.end(), &corner_values[c * w], &corner_values[c * w] + w);
            r.indices[c] = std::int32_t(k);
        }
    }
    return r;
}

TEST(Welding, CornersOfAVertexWithEqualValuesShareOneAndASeamSplitsThem) {
    // Two triangles over a square, 0 1 2 and 0 2 3; the second one's UVs are shifted at vertices 2 and 0: a seam
    // along their edge. Vertices 1 and 3 have one corner each.
    const std::vector<std::int32_t> triangles = {0, 1, 2, 0, 2, 3};
    const std::vector<float> uvs = {0, 0, 1, 0, 1, 1,   // triangle 0
                                    5, 0, 6, 1, 0, 1};  // triangle 1: vertex 0 at (5, 0), vertex 2 at (6, 1)
    const Welded w = weld(triangles, 4, uvs, 2);
    // Vertex 0: (0, 0) then (5, 0); vertex 1: (1, 0); vertex 2: (1, 1) then (6, 1); vertex 3: (0, 1).
    EXPECT_EQ(w.indices, (std::vector<std::int32_t>{0, 2, 3, 1, 4, 5}));
    EXPECT_EQ(w.values, (std::vector<float>{0, 0, 5, 0, 1, 0, 1, 1, 6, 1, 0, 1}));

    const std::vector<float> no_seam = {0, 0, 1, 0, 1, 1, 0, 0, 1, 1, 0, 1};
    const Welded joined = weld(triangles, 4, no_seam, 2);
    EXPECT_EQ(joined.indices, (std::vector<std::int32_t>{0, 1, 2, 0, 2, 3}));
    EXPECT_EQ(joined.values, (std::vector<float>{0, 0, 1, 0, 1, 1, 0, 1}));
}

TEST(Welding, MinusZeroIsZeroAndEachValueIsItsFirstCorners) {
    const std::vector<std::int32_t> triangles = {0, 1, 2, 0, 2, 1};
    const std::vector<float> values = {-0.0f, 1, 2, 0.0f, 2, 1};  // one channel
    const Welded w = weld(triangles, 3, values, 1);
    EXPECT_EQ(w.indices, (std::vector<std::int32_t>{0, 1, 2, 0, 2, 1}));
    ASSERT_EQ(w.values.size(), 3u);
    EXPECT_EQ(bits(w.values[0]), bits(-0.0f));  // vertex 0's first corner holds -0.0
    // A NaN is one value with itself (bit for bit), and a seam against any other.
    const Welded nan = weld({0, 1, 2, 0, 2, 1}, 3, {NAN, 1, 2, NAN, 2, 1}, 1);
    EXPECT_EQ(nan.indices, (std::vector<std::int32_t>{0, 1, 2, 0, 2, 1}));
}

TEST(Welding, NoChannelsOrNoTrianglesOrUnusedVertices) {
    EXPECT_EQ(weld({0, 1, 2, 2, 1, 3}, 4, {}, 0).indices, (std::vector<std::int32_t>{0, 1, 2, 2, 1, 3}));
    EXPECT_TRUE(weld({}, 5, {}, 3).indices.empty());
    const Welded w = weld({4, 1, 2}, 6, {7, 8, 9}, 1);  // vertices 0, 3 and 5 have no corner, so no value
    EXPECT_EQ(w.indices, (std::vector<std::int32_t>{2, 0, 1}));
    EXPECT_EQ(w.values, (std::vector<float>{8, 9, 7}));
}

TEST(Welding, VertexOutOfRangeIsAnInputError) {
    for (std::int32_t bad : {-1, 3, 2147483647}) {
        const std::vector<std::int32_t> triangles = {0, 1, 2, 0, 2, bad};
        std::vector<std::int32_t> indices(6);
        const std::vector<float> values(6, 0.0f);
        try {
            loopsub::weld_corner_values(indices.data(), triangles.data(), 2, 3, values.data(), 1);
            ADD_FAILURE() << "no error for vertex " << bad;
        } catch (const loopsub::InputError& e) {
            EXPECT_EQ(std::string(e.what()), "triangle 1 refers to vertex " + std::to_string(bad) +
                                                 ", outside 0..2 (the mesh has 3 vertices)");
        }
    }
    std::int32_t index = 0;
    EXPECT_THROW(loopsub::weld_corner_values(&index, nullptr, 0, -1, nullptr, 1), loopsub::InputError);
}

TEST(Welding, RandomMeshesAgreeWithTheReference) {
    std::mt19937 random(24);
    for (int trial = 0; trial < 200; ++trial) {
        const int num_vertices = 1 + int(random() % 12), num_triangles = int(random() % 30),
                  channels = 1 + int(random() % 3);
        std::vector<std::int32_t> triangles(3 * std::size_t(num_triangles));
        for (std::int32_t& v : triangles) v = std::int32_t(random() % unsigned(num_vertices));
        // Few distinct values, so that corners often share one.
        std::vector<float> values(triangles.size() * std::size_t(channels));
        for (float& x : values) x = float(int(random() % 3)) * 0.5f;
        SCOPED_TRACE("trial " + std::to_string(trial));
        const Welded w = weld(triangles, num_vertices, values, channels);
        const Welded r = reference(triangles, num_vertices, values, channels);
        EXPECT_EQ(w.indices, r.indices);
        EXPECT_EQ(w.values, r.values);
    }
}

}  // namespace
