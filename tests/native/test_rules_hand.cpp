// The seed's rules (Rules::Hoppe94, docs/rules.md) on tiny hand-built meshes, one level at a time. Every
// expected value is a weighted sum written out here from the rule tables, never computed by the project's code.
//
// Meshes:
//   * closed fan of n: vertex 0 at the centre (interior, valence n), rim 1..n (boundary), triangles (0, i, i+1).
//   * half fan of k: vertex 0 on the boundary with k faces (valence k + 1), rim 1..k+1.
//   * grid: 4 x 3 vertices, id = 4 * row + column, each quad split along the same diagonal, so that the
//     non-corner boundary vertices have valence 4 (three faces) and the interior ones valence 6.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "loopsub/loopsub.h"

namespace {

using loopsub::VertexType;

constexpr double kPi = 3.14159265358979323846;
constexpr double kTolerance = 1e-5;  // positions are floats of magnitude ~1

struct Vec3 {
    double x = 0, y = 0, z = 0;
};

struct TestMesh : loopsub::MeshData {
    Vec3 p(int v) const { return {positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]}; }
};

// Irregular radii and heights, so that a wrong weight on any one neighbour shows in the result.
Vec3 rim_point(int i, double angle) {
    double radius = 1.0 + 0.13 * ((i * 5) % 7);
    return {radius * std::cos(angle), radius * std::sin(angle), 0.05 * ((i * 3) % 5) - 0.1};
}

void add_point(TestMesh& mesh, Vec3 p) {
    mesh.positions.insert(mesh.positions.end(), {float(p.x), float(p.y), float(p.z)});
}

TestMesh closed_fan(int n) {
    TestMesh mesh;
    add_point(mesh, {0.1, -0.05, 1.0});
    for (int i = 1; i <= n; ++i) {
        add_point(mesh, rim_point(i, 2 * kPi * (i - 1) / n));
        mesh.triangles.insert(mesh.triangles.end(), {0, i, i % n + 1});
    }
    return mesh;
}

TestMesh half_fan(int k) {
    TestMesh mesh;
    add_point(mesh, {0.05, 0.0, 0.4});
    for (int i = 1; i <= k + 1; ++i) add_point(mesh, rim_point(i, kPi * (i - 1) / k));
    for (int i = 1; i <= k; ++i) mesh.triangles.insert(mesh.triangles.end(), {0, i, i + 1});
    return mesh;
}

TestMesh grid() {
    TestMesh mesh;
    for (int row = 0; row < 3; ++row) {
        for (int column = 0; column < 4; ++column)
            add_point(mesh, {double(column), double(row), 0.1 * ((column * 7 + row * 3) % 5)});
    }
    for (int row = 0; row < 2; ++row) {
        for (int column = 0; column < 3; ++column) {
            int a = 4 * row + column, b = a + 1, c = a + 5, d = a + 4;
            mesh.triangles.insert(mesh.triangles.end(), {a, b, c, a, c, d});
        }
    }
    return mesh;
}

// The weighted average sum(w_i p_i) / sum(w_i): every rule of the seed is one.
Vec3 average(const TestMesh& mesh, std::initializer_list<std::pair<double, int>> terms) {
    Vec3 sum;
    double total = 0;
    for (auto [weight, v] : terms) {
        Vec3 p = mesh.p(v);
        sum.x += weight * p.x;
        sum.y += weight * p.y;
        sum.z += weight * p.z;
        total += weight;
    }
    return {sum.x / total, sum.y / total, sum.z / total};
}

// A closed fan's centre under a centre weight c0 and weight 1 on each of its n rim vertices.
Vec3 centre_with_ring(const TestMesh& mesh, int n, double c0) {
    Vec3 sum = mesh.p(0);
    sum = {c0 * sum.x, c0 * sum.y, c0 * sum.z};
    for (int i = 1; i <= n; ++i) {
        sum.x += mesh.p(i).x;
        sum.y += mesh.p(i).y;
        sum.z += mesh.p(i).z;
    }
    return {sum.x / (c0 + n), sum.y / (c0 + n), sum.z / (c0 + n)};
}

struct Refined {
    loopsub::Plan plan;
    std::vector<float> positions;

    Vec3 p(int v) const { return {positions[3 * v], positions[3 * v + 1], positions[3 * v + 2]}; }

    // The level-1 vertex made from level-0 edge a-b (either order); nullopt (and a failure) when there is none.
    std::optional<Vec3> edge_point(int a, int b) const {
        const std::vector<std::int32_t>& edges = plan.level_edges(0);
        for (std::size_t k = 0; k < edges.size(); k += 2) {
            if ((edges[k] == a && edges[k + 1] == b) || (edges[k] == b && edges[k + 1] == a)) {
                return p(plan.level_num_vertices(0) + int(k / 2));
            }
        }
        ADD_FAILURE() << "no edge " << a << "-" << b << " at level 0";
        return std::nullopt;
    }

    VertexType type(int v, int level = 0) const { return plan.level_vertex_types(level).at(std::size_t(v)); }
};

Refined refine(const TestMesh& mesh, int levels = 1, float crease_threshold = 0.0f) {
    loopsub::Options options;
    options.rules = loopsub::Rules::Hoppe94;
    options.levels = levels;
    options.crease_threshold = crease_threshold;
    Refined refined{loopsub::Plan(mesh.view(), options), {}};
    refined.positions.resize(std::size_t(refined.plan.num_output_vertices()) * 3);
    refined.plan.evaluate(loopsub::interleaved(static_cast<const float*>(mesh.positions.data()), 3),
                          loopsub::interleaved(refined.positions.data(), 3));
    return refined;
}

#define EXPECT_POINT_NEAR(actual, expected)                                 \
    do {                                                                    \
        const Vec3 actual_ = (actual), expected_ = (expected);              \
        EXPECT_NEAR(actual_.x, expected_.x, kTolerance) << "x of " #actual; \
        EXPECT_NEAR(actual_.y, expected_.y, kTolerance) << "y of " #actual; \
        EXPECT_NEAR(actual_.z, expected_.z, kTolerance) << "z of " #actual; \
    } while (0)

#define EXPECT_EDGE_POINT_NEAR(refined, a, b, expected)          \
    do {                                                         \
        std::optional<Vec3> point_ = (refined).edge_point(a, b); \
        if (point_) EXPECT_POINT_NEAR(*point_, expected);        \
    } while (0)

// cos(2 pi / 5) = (sqrt 5 - 1) / 4, so b(5) = (3 + (sqrt 5 - 1) / 2) / 8 = (5 + sqrt 5) / 16.
const double kB5 = (5.0 + std::sqrt(5.0)) / 16.0;
const double kA5 = 5.0 / 8.0 - kB5 * kB5;
const double kC0Valence5 = 5.0 / kA5 - 5.0;
// cos(2 pi / 6) = 1/2: b(6) = 1/2, a(6) = 5/8 - 1/4 = 3/8, c0 = 6 / (3/8) - 6 = 10.
constexpr double kC0Valence6 = 10.0;

TEST(Hoppe94Hand, SeedWorkedExampleConstants) {
    // The seed's slide: a(5) = 0.4205, c0 = 5 / a(5) - 5 = 6.892.
    EXPECT_NEAR(loopsub::loop_a(5), 0.4205, 0.5e-4);
    EXPECT_NEAR(5.0 / loopsub::loop_a(5) - 5.0, 6.892, 0.5e-3);
    EXPECT_NEAR(kC0Valence5, 6.892, 0.5e-3) << "the hand-derived constant the tests below use";
    EXPECT_NEAR(loopsub::loop_a(6), 0.375, 1e-12);
    EXPECT_NEAR(loopsub::loop_b(3), 0.25, 1e-12);
    EXPECT_NEAR(loopsub::loop_b(4), 0.375, 1e-12);
    EXPECT_NEAR(loopsub::loop_b(5), kB5, 1e-12);
    EXPECT_NEAR(loopsub::loop_b(6), 0.5, 1e-12);
}

TEST(Hoppe94Hand, SmoothValence5VertexIsTheSeedsWorkedExample) {
    TestMesh mesh = closed_fan(5);
    Refined refined = refine(mesh);
    EXPECT_EQ(refined.type(0), VertexType::Smooth);
    // (6.892 v0 + v1 + ... + v5) / 11.892
    EXPECT_POINT_NEAR(refined.p(0), centre_with_ring(mesh, 5, kC0Valence5));
}

TEST(Hoppe94Hand, SmoothEdgeIsThreeThreeOneOne) {
    TestMesh mesh = closed_fan(5);
    Refined refined = refine(mesh);
    // Edge 0-1 lies in triangles (0, 1, 2) and (0, 5, 1).
    EXPECT_EDGE_POINT_NEAR(refined, 0, 1, average(mesh, {{3, 0}, {3, 1}, {1, 2}, {1, 5}}));
    EXPECT_EDGE_POINT_NEAR(refined, 0, 3, average(mesh, {{3, 0}, {3, 3}, {1, 2}, {1, 4}}));
}

TEST(Hoppe94Hand, InteriorCreaseVertexUsesItsTwoCreaseNeighbours) {
    TestMesh mesh = closed_fan(6);
    mesh.add_crease(0, 1);
    mesh.add_crease(4, 0);
    Refined refined = refine(mesh);
    EXPECT_EQ(refined.type(0), VertexType::RegularCrease);
    EXPECT_POINT_NEAR(refined.p(0), average(mesh, {{6, 0}, {1, 1}, {1, 4}}));
}

TEST(Hoppe94Hand, BoundaryEdgesAreCreases) {
    TestMesh mesh = grid();
    Refined refined = refine(mesh);
    // Bottom row: boundary vertices whose crease neighbours are their boundary neighbours.
    EXPECT_POINT_NEAR(refined.p(1), average(mesh, {{6, 1}, {1, 0}, {1, 2}}));
    EXPECT_POINT_NEAR(refined.p(0), average(mesh, {{6, 0}, {1, 1}, {1, 4}}));
    EXPECT_POINT_NEAR(refined.p(3), average(mesh, {{6, 3}, {1, 2}, {1, 7}}));
    // An interior vertex of the grid stays smooth with valence 6.
    EXPECT_EQ(refined.type(5), VertexType::Smooth);
    EXPECT_POINT_NEAR(refined.p(5), average(mesh, {{kC0Valence6, 5}, {1, 0}, {1, 1}, {1, 4}, {1, 6}, {1, 9}, {1, 10}}));
    // A boundary edge has no wings: {1, 1, 0, 0} between two regular crease vertices.
    EXPECT_EDGE_POINT_NEAR(refined, 1, 2, average(mesh, {{1, 1}, {1, 2}}));
}

TEST(Hoppe94Hand, TaggedCornerStaysPut) {
    TestMesh mesh = closed_fan(5);
    mesh.add_corner(0, 1.0f);
    Refined refined = refine(mesh);
    EXPECT_EQ(refined.type(0), VertexType::Corner);
    EXPECT_POINT_NEAR(refined.p(0), mesh.p(0));
}

TEST(Hoppe94Hand, CornerTagWithZeroSharpnessIsNoCorner) {
    TestMesh mesh = closed_fan(5);
    mesh.add_corner(0, 0.0f);
    Refined refined = refine(mesh);
    EXPECT_EQ(refined.type(0), VertexType::Smooth);
    EXPECT_POINT_NEAR(refined.p(0), centre_with_ring(mesh, 5, kC0Valence5));
}

TEST(Hoppe94Hand, ThreeCreaseEdgesMakeACorner) {
    TestMesh mesh = closed_fan(6);
    mesh.add_crease(0, 1);
    mesh.add_crease(0, 3);
    mesh.add_crease(0, 5);
    Refined refined = refine(mesh);
    EXPECT_EQ(refined.type(0), VertexType::Corner);
    EXPECT_POINT_NEAR(refined.p(0), mesh.p(0));
}

// Boundary crease vertices of the grid: valence 4 regular, valence 3 and 2 irregular. The {5, 3, 0, 0} mask puts
// its 5 on the regular end whichever end the edge lists first: edge 0-1 has the regular end second, edge 2-3
// first.
TEST(Hoppe94Hand, FiveThreeEdgeOnBoundaryBothOrientations) {
    TestMesh mesh = grid();
    Refined refined = refine(mesh);
    EXPECT_EQ(refined.type(0), VertexType::IrregularCrease) << "boundary valence 3";
    EXPECT_EQ(refined.type(1), VertexType::RegularCrease) << "boundary valence 4";
    EXPECT_EQ(refined.type(2), VertexType::RegularCrease) << "boundary valence 4";
    EXPECT_EQ(refined.type(3), VertexType::IrregularCrease) << "boundary valence 2";
    EXPECT_EQ(refined.type(4), VertexType::RegularCrease) << "boundary valence 4, left side";

    EXPECT_EDGE_POINT_NEAR(refined, 0, 1, average(mesh, {{3, 0}, {5, 1}}));
    EXPECT_EDGE_POINT_NEAR(refined, 2, 3, average(mesh, {{5, 2}, {3, 3}}));
    EXPECT_EDGE_POINT_NEAR(refined, 0, 4, average(mesh, {{3, 0}, {5, 4}}));
    EXPECT_EDGE_POINT_NEAR(refined, 4, 8, average(mesh, {{5, 4}, {3, 8}}));
    // Two regular ends: the midpoint.
    EXPECT_EDGE_POINT_NEAR(refined, 1, 2, average(mesh, {{1, 1}, {1, 2}}));
}

// An interior crease row through the grid: 5 and 6 are regular (three faces each side), 4 and 7 become corners
// (two boundary edges and the crease). Edge 4-5 has the regular end second, edge 6-7 first; 5-6 joins two regular
// crease vertices and is bisected at its midpoint.
TEST(Hoppe94Hand, FiveThreeEdgeOnInteriorCreaseBothOrientations) {
    TestMesh mesh = grid();
    mesh.add_crease(4, 5);
    mesh.add_crease(6, 5);  // tag order must not matter either
    mesh.add_crease(7, 6);
    Refined refined = refine(mesh);
    EXPECT_EQ(refined.type(4), VertexType::Corner);
    EXPECT_EQ(refined.type(5), VertexType::RegularCrease);
    EXPECT_EQ(refined.type(6), VertexType::RegularCrease);
    EXPECT_EQ(refined.type(7), VertexType::Corner);

    EXPECT_EDGE_POINT_NEAR(refined, 4, 5, average(mesh, {{3, 4}, {5, 5}}));
    EXPECT_EDGE_POINT_NEAR(refined, 6, 7, average(mesh, {{5, 6}, {3, 7}}));
    EXPECT_EDGE_POINT_NEAR(refined, 5, 6, average(mesh, {{1, 5}, {1, 6}}));
    EXPECT_POINT_NEAR(refined.p(5), average(mesh, {{6, 5}, {1, 4}, {1, 6}}));
    EXPECT_POINT_NEAR(refined.p(4), mesh.p(4));
}

// The same vertex and crease under two labellings: the regular end as the higher and as the lower index.
TEST(Hoppe94Hand, FiveThreeEdgeDoesNotDependOnVertexNumbering) {
    // Closed fan of 6 with crease 0-1-...-4: the centre is regular, rim vertex 1 is a corner (boundary + crease).
    TestMesh mesh = closed_fan(6);
    mesh.add_crease(1, 0);
    mesh.add_crease(0, 4);
    Refined refined = refine(mesh);
    EXPECT_EQ(refined.type(1), VertexType::Corner);
    EXPECT_EDGE_POINT_NEAR(refined, 0, 1, average(mesh, {{5, 0}, {3, 1}}));

    // Relabel: centre 0 <-> rim 1.
    TestMesh swapped = mesh;
    for (std::vector<std::int32_t>* indices : {&swapped.triangles, &swapped.crease_edges}) {
        for (std::int32_t& v : *indices) v = v == 0 ? 1 : v == 1 ? 0 : v;
    }
    for (int axis = 0; axis < 3; ++axis) std::swap(swapped.positions[axis], swapped.positions[3 + axis]);
    Refined relabelled = refine(swapped);
    EXPECT_EQ(relabelled.type(1), VertexType::RegularCrease);
    EXPECT_EQ(relabelled.type(0), VertexType::Corner);
    EXPECT_EDGE_POINT_NEAR(relabelled, 0, 1, average(swapped, {{3, 0}, {5, 1}}));
}

TEST(Hoppe94Hand, OtherCreaseEdgesAreOneOneZeroZero) {
    // Corner next to irregular crease: the half fan's rim vertex 1 (one face) and rim vertex 2 (valence 3).
    TestMesh mesh = half_fan(3);
    mesh.add_corner(1);
    Refined refined = refine(mesh);
    EXPECT_EQ(refined.type(2), VertexType::IrregularCrease);
    EXPECT_EDGE_POINT_NEAR(refined, 1, 2, average(mesh, {{1, 1}, {1, 2}}));
    // Two irregular crease ends: rim vertices 2 and 3 (boundary valence 3 each).
    EXPECT_EQ(refined.type(3), VertexType::IrregularCrease);
    EXPECT_EDGE_POINT_NEAR(refined, 2, 3, average(mesh, {{1, 2}, {1, 3}}));
}

TEST(Hoppe94Hand, InteriorCreaseRegularityIsThreeFacesEachSide) {
    // Closed fan of 6: creases 0-1 and 0-4 leave three faces on each side; 0-1 and 0-3 leave two and four.
    TestMesh regular = closed_fan(6);
    regular.add_crease(0, 1);
    regular.add_crease(0, 4);
    TestMesh irregular = closed_fan(6);
    irregular.add_crease(0, 1);
    irregular.add_crease(0, 3);
    TestMesh adjacent = closed_fan(6);  // one face and five
    adjacent.add_crease(0, 1);
    adjacent.add_crease(0, 2);

    Refined r = refine(regular), i = refine(irregular), a = refine(adjacent);
    EXPECT_EQ(r.type(0), VertexType::RegularCrease);
    EXPECT_EQ(i.type(0), VertexType::IrregularCrease);
    EXPECT_EQ(a.type(0), VertexType::IrregularCrease);

    // Both are repositioned by the crease rule...
    EXPECT_POINT_NEAR(r.p(0), average(regular, {{6, 0}, {1, 1}, {1, 4}}));
    EXPECT_POINT_NEAR(i.p(0), average(irregular, {{6, 0}, {1, 1}, {1, 3}}));
    // ...but only the regular one pulls the crease edge towards itself (rim vertex 1 is a corner in both).
    EXPECT_EDGE_POINT_NEAR(r, 0, 1, average(regular, {{5, 0}, {3, 1}}));
    EXPECT_EDGE_POINT_NEAR(i, 0, 1, average(irregular, {{1, 0}, {1, 1}}));
}

TEST(Hoppe94Hand, InteriorValenceOtherThanSixIsAnIrregularCrease) {
    TestMesh mesh = closed_fan(8);
    mesh.add_crease(0, 1);
    mesh.add_crease(0, 5);  // four faces on each side, but valence 8
    Refined refined = refine(mesh);
    EXPECT_EQ(refined.type(0), VertexType::IrregularCrease);
    EXPECT_EDGE_POINT_NEAR(refined, 0, 1, average(mesh, {{1, 0}, {1, 1}}));
}

TEST(Hoppe94Hand, BoundaryRegularityIsValenceFour) {
    for (int faces : {2, 3, 4}) {
        SCOPED_TRACE("boundary vertex with " + std::to_string(faces) + " faces");
        TestMesh mesh = half_fan(faces);
        Refined refined = refine(mesh);
        const bool regular = faces == 3;  // valence 4
        EXPECT_EQ(refined.type(0), regular ? VertexType::RegularCrease : VertexType::IrregularCrease);
        // Rim vertex 1 has a single face: an irregular crease vertex (boundary valence 2).
        EXPECT_EQ(refined.type(1), VertexType::IrregularCrease);
        EXPECT_POINT_NEAR(refined.p(0), average(mesh, {{6, 0}, {1, 1}, {1, faces + 1}}));
        EXPECT_EDGE_POINT_NEAR(refined, 0, 1,
                               regular ? average(mesh, {{5, 0}, {3, 1}}) : average(mesh, {{1, 0}, {1, 1}}));
    }
}

TEST(Hoppe94Hand, CreaseWithADartEndIsBisectedAsSmooth) {
    TestMesh mesh = closed_fan(6);
    mesh.add_crease(0, 1);  // the centre's only crease edge: a dart; rim vertex 1 becomes a corner
    Refined refined = refine(mesh);
    EXPECT_EQ(refined.type(0), VertexType::Dart);
    EXPECT_EQ(refined.type(1), VertexType::Corner);
    // Edge 0-1 lies in triangles (0, 1, 2) and (0, 6, 1).
    EXPECT_EDGE_POINT_NEAR(refined, 0, 1, average(mesh, {{3, 0}, {3, 1}, {1, 2}, {1, 6}}));
    // A dart is repositioned by the smooth rule.
    EXPECT_POINT_NEAR(refined.p(0), centre_with_ring(mesh, 6, kC0Valence6));
}

TEST(Hoppe94Hand, NewVerticesOnCreaseEdgesAreRegularAndClassificationIsRedone) {
    TestMesh mesh = half_fan(2);
    Refined refined = refine(mesh, 2);
    ASSERT_EQ(refined.plan.levels(), 2);
    const int level0_vertices = refined.plan.level_num_vertices(0);
    const std::vector<std::int32_t>& edges = refined.plan.level_edges(0);
    for (std::size_t k = 0; k < edges.size(); k += 2) {
        const int a = edges[k], b = edges[k + 1];
        const bool boundary = !((a == 0 && b == 2) || (a == 2 && b == 0));  // 0-2 is the only interior edge
        EXPECT_EQ(refined.type(level0_vertices + int(k / 2), 1),
                  boundary ? VertexType::RegularCrease : VertexType::Smooth)
            << "vertex on edge " << a << "-" << b;
    }
    // Old vertices keep their valence: the centre still has three neighbours on the boundary.
    EXPECT_EQ(refined.type(0, 1), VertexType::IrregularCrease);
}

// Centre weight of a cone: c0 / (c0 + n) with c0 = n / (5/8 - b(n)) - n, which is 3/8 + b(n).
TEST(Hoppe94Hand, ConeVertexWeights) {
    const double b[] = {0, 0, 0, 0.25, 0.375, kB5, 0.5};  // b(3..6) by hand
    const double centre_weight[] = {0, 0, 0, 0.625, 0.75, 0.8273, 0.875};
    for (int n = 3; n <= 6; ++n) {
        SCOPED_TRACE("valence " + std::to_string(n));
        const double c0 = n / (5.0 / 8.0 - b[n]) - n;
        EXPECT_NEAR(c0 / (c0 + n), centre_weight[n], 0.5e-4) << "the hand table itself";

        TestMesh mesh = closed_fan(n);
        mesh.cone_vertices.push_back(0);
        Refined refined = refine(mesh);
        EXPECT_EQ(refined.type(0), VertexType::Cone);
        EXPECT_POINT_NEAR(refined.p(0), centre_with_ring(mesh, n, c0));
    }
}

TEST(Hoppe94Hand, ConeWithOneCreaseEdgeStaysACone) {
    TestMesh mesh = closed_fan(5);
    mesh.cone_vertices.push_back(0);
    mesh.add_crease(0, 1);
    Refined refined = refine(mesh);
    EXPECT_EQ(refined.type(0), VertexType::Cone);
    EXPECT_POINT_NEAR(refined.p(0), centre_with_ring(mesh, 5, 5 / (5.0 / 8.0 - kB5) - 5));
}

TEST(Hoppe94Hand, ConeWithTwoCreaseEdgesBecomesACorner) {
    TestMesh mesh = closed_fan(6);
    mesh.cone_vertices.push_back(0);
    mesh.add_crease(0, 1);
    mesh.add_crease(0, 4);
    Refined refined = refine(mesh);
    EXPECT_EQ(refined.type(0), VertexType::Corner);
    EXPECT_POINT_NEAR(refined.p(0), mesh.p(0));
}

TEST(Hoppe94Hand, CreaseThresholdSharpnessAtOrAboveIsACrease) {
    TestMesh mesh = closed_fan(6);
    mesh.add_crease(0, 1, 0.5f);
    mesh.add_crease(0, 4, 0.5f);
    const Vec3 crease = average(mesh, {{6, 0}, {1, 1}, {1, 4}});
    const Vec3 smooth = centre_with_ring(mesh, 6, kC0Valence6);

    Refined any_positive = refine(mesh, 1, 0.0f);
    EXPECT_EQ(any_positive.type(0), VertexType::RegularCrease) << "default threshold 0: any positive sharpness";
    EXPECT_POINT_NEAR(any_positive.p(0), crease);

    Refined equal = refine(mesh, 1, 0.5f);
    EXPECT_EQ(equal.type(0), VertexType::RegularCrease) << "sharpness == threshold";
    EXPECT_POINT_NEAR(equal.p(0), crease);

    Refined above = refine(mesh, 1, 0.6f);
    EXPECT_EQ(above.type(0), VertexType::Smooth) << "sharpness < threshold";
    EXPECT_POINT_NEAR(above.p(0), smooth);

    TestMesh zero = closed_fan(6);
    zero.add_crease(0, 1, 0.0f);
    zero.add_crease(0, 4, 0.0f);
    Refined zero_sharpness = refine(zero, 1, 0.0f);
    EXPECT_EQ(zero_sharpness.type(0), VertexType::Smooth) << "sharpness 0 is no crease, even at threshold 0";
    EXPECT_POINT_NEAR(zero_sharpness.p(0), smooth);
}

}  // namespace
