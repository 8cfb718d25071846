// Rules::Hoppe94 (the seed's rules, docs/rules.md) against OpenSubdiv with infinitely sharp creases.
//
// The two rule sets share the smooth, crease and corner vertex masks, the smooth edge mask and the midpoint rule
// for sharp edges. They differ only
//   (a) on a crease edge between a regular crease vertex and an irregular crease vertex or corner: the seed's
//       {5,3,0,0} with the 5 on the regular end, where OpenSubdiv takes the midpoint;
//   (b) on a crease edge with a dart end: the seed's smooth {3,3,1,1}, where OpenSubdiv takes the midpoint;
//   (c) at cone vertices, which OpenSubdiv does not have.
// So: on meshes where none of (a)-(c) occurs, every level must equal OpenSubdiv; on meshes made to contain one of
// them, every vertex must equal OpenSubdiv except the listed ones, and those must have the seed's value, computed
// here by hand from the seed's masks (never by the project's code).
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "loopsub/loopsub.h"
#include "mesh_gen.h"
#include "osd_reference.h"

namespace loopsub::testing {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Vec3 {
    double x, y, z;
};
Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec3 operator*(double s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
double distance(Vec3 a, Vec3 b) {
    return std::sqrt((a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) + (a.z - b.z) * (a.z - b.z));
}
std::ostream& operator<<(std::ostream& os, Vec3 v) { return os << "(" << v.x << ", " << v.y << ", " << v.z << ")"; }

template <typename T>
Vec3 point(const std::vector<T>& positions, int v) {
    return {double(positions[3 * v]), double(positions[3 * v + 1]), double(positions[3 * v + 2])};
}

Options hoppe_options(int levels) {
    Options options;
    options.rules = Rules::Hoppe94;
    options.levels = levels;
    return options;
}

// Our vertex of level+1 that bisects the level's edge a-b (the documented seed order: after the level's vertices,
// one per edge in level_edges order). Fails the test when a-b is not an edge.
int edge_point(const Plan& plan, int level, int a, int b) {
    const std::vector<std::int32_t>& edges = plan.level_edges(level);
    for (std::size_t k = 0; 2 * k < edges.size(); ++k) {
        if ((edges[2 * k] == a && edges[2 * k + 1] == b) || (edges[2 * k] == b && edges[2 * k + 1] == a))
            return plan.level_num_vertices(level) + int(k);
    }
    ADD_FAILURE() << "no level-" << level << " edge " << a << "-" << b;
    return 0;
}

// The third vertices C and D of the two triangles on edge a-b of the input mesh.
std::vector<int> opposite_vertices(const TestMesh& mesh, int a, int b) {
    std::vector<int> opposite;
    for (int t = 0; t < mesh.num_triangles(); ++t) {
        const std::int32_t* tri = &mesh.triangles[3 * t];
        for (int k = 0; k < 3; ++k)
            if ((tri[k] == a && tri[(k + 1) % 3] == b) || (tri[k] == b && tri[(k + 1) % 3] == a))
                opposite.push_back(tri[(k + 2) % 3]);
    }
    return opposite;
}

double seed_b(int n) { return (3.0 + 2.0 * std::cos(2.0 * kPi / n)) / 8.0; }

// A vertex whose Hoppe94 value the test knows, and why.
struct SeedValue {
    int vertex;
    Vec3 expected;
    std::string rule;
};

// Runs Hoppe94 for `levels` and OpenSubdiv (sharp creases, edges-only boundary) on the same mesh. Every vertex not
// in `differences` must equal OpenSubdiv; each one in it must equal its seed value, and that value must differ from
// OpenSubdiv's (or the case would not test the difference it is about).
void expect_seed_values_and_opensubdiv_elsewhere(
    const TestMesh& mesh, int levels,
    const std::function<std::vector<SeedValue>(const Plan&, const MappedReference&)>& differences,
    float crease_threshold = 0.0f, const TestMesh* osd_mesh = nullptr) {
    Options options = hoppe_options(levels);
    options.crease_threshold = crease_threshold;
    Plan plan(mesh.view(), options);
    const std::vector<float> ours = evaluate_positions(plan, mesh);
    const TestMesh& reference_mesh = osd_mesh ? *osd_mesh : mesh;
    OsdReference reference(reference_mesh.view(), reference_mesh.positions.data(),
                           {Boundary::EdgesOnly, CreaseMethod::Uniform, levels});
    ASSERT_EQ(plan.num_output_vertices(), reference.num_vertices(levels));
    const MappedReference mapped = reference.map(plan);
    ASSERT_TRUE(mapped.errors.empty()) << mapped.errors.front();
    const std::vector<double>& osd = mapped.positions[levels];
    const double tolerance = 1e-5 * bounding_box_diagonal(mesh.positions);

    const std::vector<SeedValue> seed_values = differences(plan, mapped);
    std::set<int> special;
    for (const SeedValue& s : seed_values) {
        special.insert(s.vertex);
        const Vec3 got = point(ours, s.vertex), opensubdiv = point(osd, s.vertex);
        EXPECT_LE(distance(got, s.expected), tolerance)
            << s.rule << ": level-" << levels << " vertex " << s.vertex << " expected " << s.expected << " got " << got
            << " (OpenSubdiv's value " << opensubdiv << ")";
        EXPECT_GT(distance(s.expected, opensubdiv), 10 * tolerance)
            << "test set-up: the seed's value at vertex " << s.vertex << " (" << s.rule
            << ") does not differ from OpenSubdiv's, so this case tests nothing";
    }
    std::ostringstream report;
    int bad = 0;
    for (int v = 0; v < plan.num_output_vertices(); ++v) {
        if (special.count(v)) continue;
        const double d = distance(point(ours, v), point(osd, v));
        if (!(d <= tolerance) && bad++ < 5)
            report << "  vertex " << v << ": OpenSubdiv " << point(osd, v) << " got " << point(ours, v) << "\n    "
                   << reference.describe_origin(plan, mapped, levels, v) << "\n";
    }
    EXPECT_EQ(bad, 0) << "vertices where the rules coincide differ from OpenSubdiv:\n" << report.str();
}

// --- Meshes where the two rule sets coincide -----------------------------------------------------------------

struct AgreementCase {
    std::string name;
    std::function<TestMesh()> make;
    int level;
};
// gtest prints a parameter with this (instead of its bytes) when a case fails.
void PrintTo(const AgreementCase& c, std::ostream* os) { *os << c.name; }

// Crease loops along j = const on a torus: every crease vertex is interior, valence 6, three faces on each side:
// regular, and no loop ends (no dart, no corner).
TestMesh torus_with_crease_loops(const std::vector<int>& rows, float sharpness = kInfiniteSharpness) {
    TestMesh m = torus(12, 8);
    for (int j : rows)
        for (int i = 0; i < 12; ++i) m.add_crease(torus_vertex(8, i, j), torus_vertex(8, (i + 1) % 12, j), sharpness);
    return m;
}

std::vector<AgreementCase> agreement_cases() {
    std::vector<AgreementCase> cases;
    auto add = [&](const std::string& name, std::function<TestMesh()> make, int max_level) {
        for (int level = 1; level <= max_level; ++level)
            cases.push_back({name + "_L" + std::to_string(level), make, level});
    };
    // Smooth closed meshes: smooth vertex and edge masks only.
    add(
        "icosphere320",
        [] {
            TestMesh m = icosphere(2);
            jitter(m, 7, 0.01f);
            return m;
        },
        3);
    for (int n : {3, 4, 5, 7, 12, 32, 64}) {
        add(
            "bipyramid" + std::to_string(n),
            [n] {
                TestMesh m = bipyramid(n);
                jitter(m, 200 + n, 0.01f);
                return m;
            },
            2);
    }
    // Closed crease loops of regular crease vertices, parallel and adjacent (rows 0 and 1), and a lone one.
    add(
        "torus_crease_loops",
        [] {
            TestMesh m = torus_with_crease_loops({0, 1, 4});
            jitter(m, 8, 0.01f);
            return m;
        },
        3);
    // An open tube: every boundary vertex has valence 4 (regular), so the boundary is a regular crease curve;
    // once smooth, once with an interior crease loop too.
    add(
        "open_cylinder", [] { return open_cylinder(10, 4); }, 3);
    add(
        "open_cylinder_crease_loop",
        [] {
            TestMesh m = open_cylinder(10, 4);
            for (int i = 0; i < 10; ++i) m.add_crease(i * 5 + 2, ((i + 1) % 10) * 5 + 2, kInfiniteSharpness);
            jitter(m, 9, 0.01f);
            return m;
        },
        3);
    // All cube edges sharp: the corners (three crease edges) touch only corners, so no {5,3} at level 1 (from
    // level 2 on, the corners have regular crease neighbours: see CubeCornersFromLevel2 below).
    add(
        "cube_all_edges_sharp",
        [] {
            TestMesh m = cube();
            for (const auto& e : unique_edges(m.triangles))
                if (__builtin_popcount(unsigned(e[0] ^ e[1])) == 1) m.add_crease(e[0], e[1], kInfiniteSharpness);
            return m;
        },
        1);
    return cases;
}

class HoppeAgreesWithOpenSubdiv : public ::testing::TestWithParam<AgreementCase> {};

TEST_P(HoppeAgreesWithOpenSubdiv, EveryVertex) {
    const TestMesh mesh = GetParam().make();
    expect_seed_values_and_opensubdiv_elsewhere(
        mesh, GetParam().level, [](const Plan&, const MappedReference&) { return std::vector<SeedValue>{}; });
}

INSTANTIATE_TEST_SUITE_P(Hoppe94, HoppeAgreesWithOpenSubdiv, ::testing::ValuesIn(agreement_cases()),
                         case_name<AgreementCase>);

// The crease threshold: edges below it are smooth. Loops of sharpness 10 and 0.5 with threshold 1 must give
// OpenSubdiv's result for the sharpness-10 loop alone (and not OpenSubdiv's semi-sharp blend of the 0.5 loop).
TEST(Hoppe94VsOpenSubdiv, CreaseThresholdDropsWeakerCreases) {
    TestMesh tagged = torus_with_crease_loops({0});
    for (int i = 0; i < 12; ++i) tagged.add_crease(torus_vertex(8, i, 4), torus_vertex(8, (i + 1) % 12, 4), 0.5f);
    TestMesh strong_only = torus_with_crease_loops({0});
    jitter(tagged, 23, 0.01f);
    jitter(strong_only, 23, 0.01f);  // the same offsets: same seed, same vertex count
    for (int levels = 1; levels <= 2; ++levels) {
        SCOPED_TRACE("levels " + std::to_string(levels));
        expect_seed_values_and_opensubdiv_elsewhere(
            tagged, levels, [](const Plan&, const MappedReference&) { return std::vector<SeedValue>{}; }, 1.0f,
            &strong_only);
    }
}

// --- One test per difference ---------------------------------------------------------------------------------

// (a) Interior irregular crease vertices: a closed crease loop on a torus with four bends. At a bend the crease
// turns, leaving 2 faces on one side and 4 on the other: an irregular crease vertex; the straight stretches
// between bends are regular. Each crease edge from a bend to its regular neighbour gets {5,3,0,0} with the 5 on
// the regular vertex; nothing else differs at level 1 (the bends themselves use the crease mask in both).
TEST(Hoppe94VsOpenSubdiv, FiveThreeNextToIrregularInteriorCreaseVertices) {
    const int nu = 12, nv = 6;
    TestMesh mesh = torus(nu, nv);
    jitter(mesh, 17, 0.01f);
    auto v = [&](int i, int j) { return torus_vertex(nv, (i + nu) % nu, j); };
    std::vector<int> loop;                                      // the crease loop as a vertex sequence
    for (int i = 9; i <= 12 + 3; ++i) loop.push_back(v(i, 0));  // j = 0 from i = 9 round to i = 3
    loop.push_back(v(4, 1));                                    // diagonal (3,0)-(4,1)-(5,2)
    for (int i = 5; i <= 9; ++i) loop.push_back(v(i, 2));       // j = 2 from 5 to 9
    loop.push_back(v(9, 1));                                    // down (9,2)-(9,1)-(9,0)
    for (std::size_t k = 0; k < loop.size(); ++k)
        mesh.add_crease(loop[k], loop[(k + 1) % loop.size()], kInfiniteSharpness);

    // (regular end, bend) of each {5,3} edge.
    const int pairs[8][2] = {{v(2, 0), v(3, 0)}, {v(4, 1), v(3, 0)}, {v(4, 1), v(5, 2)}, {v(6, 2), v(5, 2)},
                             {v(8, 2), v(9, 2)}, {v(9, 1), v(9, 2)}, {v(9, 1), v(9, 0)}, {v(10, 0), v(9, 0)}};
    expect_seed_values_and_opensubdiv_elsewhere(mesh, 1, [&](const Plan& plan, const MappedReference&) {
        std::vector<SeedValue> values;
        for (const auto& p : pairs) {
            const Vec3 regular = point(mesh.positions, p[0]), bend = point(mesh.positions, p[1]);
            values.push_back({edge_point(plan, 0, p[0], p[1]), (1.0 / 8) * (5 * regular + 3 * bend),
                              "{5,3}: regular " + std::to_string(p[0]) + ", irregular " + std::to_string(p[1])});
        }
        return values;
    });
}

// (a) On the boundary: boundary edges are creases; a boundary vertex with valence 4 (three faces) is a regular
// crease vertex, the grid's corners (valence 2 and 3) are irregular. So each boundary edge that leaves a grid corner
// gets {5,3} with the 5 away from the corner; OpenSubdiv's edges-only boundary takes the midpoint.
TEST(Hoppe94VsOpenSubdiv, FiveThreeNextToBoundaryCorners) {
    const int nx = 4, ny = 3;
    TestMesh mesh = grid(nx, ny);
    jitter(mesh, 18, 0.01f);
    auto g = [&](int i, int j) { return grid_vertex(nx, i, j); };
    const int pairs[8][2] = {{g(1, 0), g(0, 0)}, {g(0, 1), g(0, 0)}, {g(3, 0), g(4, 0)}, {g(4, 1), g(4, 0)},
                             {g(1, 3), g(0, 3)}, {g(0, 2), g(0, 3)}, {g(3, 3), g(4, 3)}, {g(4, 2), g(4, 3)}};
    expect_seed_values_and_opensubdiv_elsewhere(mesh, 1, [&](const Plan& plan, const MappedReference&) {
        std::vector<SeedValue> values;
        for (const auto& p : pairs) {
            const Vec3 regular = point(mesh.positions, p[0]), corner = point(mesh.positions, p[1]);
            values.push_back(
                {edge_point(plan, 0, p[0], p[1]), (1.0 / 8) * (5 * regular + 3 * corner),
                 "boundary {5,3}: regular " + std::to_string(p[0]) + ", irregular " + std::to_string(p[1])});
        }
        return values;
    });
}

// (a) Next to a tagged corner on a closed crease loop of regular vertices.
TEST(Hoppe94VsOpenSubdiv, FiveThreeNextToTaggedCorner) {
    TestMesh mesh = torus_with_crease_loops({0});
    jitter(mesh, 19, 0.01f);
    const int corner = torus_vertex(8, 0, 0);
    mesh.add_corner(corner, kInfiniteSharpness);
    expect_seed_values_and_opensubdiv_elsewhere(mesh, 1, [&](const Plan& plan, const MappedReference&) {
        std::vector<SeedValue> values;
        for (int neighbour : {torus_vertex(8, 1, 0), torus_vertex(8, 11, 0)}) {
            values.push_back({edge_point(plan, 0, neighbour, corner),
                              (1.0 / 8) * (5 * point(mesh.positions, neighbour) + 3 * point(mesh.positions, corner)),
                              "{5,3} next to a corner"});
        }
        return values;
    });
}

// (a) From level 2 on, every corner has regular crease neighbours (the new vertices on its crease edges), so on
// the cube with sharp edges exactly the 24 level-2 edge points next to the 8 corners differ. Their seed value comes
// from the level-1 positions, which equal OpenSubdiv's (HoppeAgreesWithOpenSubdiv cube_all_edges_sharp_L1).
TEST(Hoppe94VsOpenSubdiv, CubeCornersFromLevel2) {
    TestMesh mesh = cube();
    std::vector<std::array<std::int32_t, 2>> cube_edges;
    for (const auto& e : unique_edges(mesh.triangles))
        if (__builtin_popcount(unsigned(e[0] ^ e[1])) == 1) {
            mesh.add_crease(e[0], e[1], kInfiniteSharpness);
            cube_edges.push_back(e);
        }
    ASSERT_EQ(cube_edges.size(), 12u);
    expect_seed_values_and_opensubdiv_elsewhere(mesh, 2, [&](const Plan& plan, const MappedReference& mapped) {
        std::vector<SeedValue> values;
        const std::vector<double>& level1 = mapped.positions[1];
        for (const auto& e : cube_edges) {
            const int middle = edge_point(plan, 0, e[0], e[1]);  // a regular crease vertex at level 1
            for (int corner : {e[0], e[1]}) {
                values.push_back({edge_point(plan, 1, middle, corner),
                                  (1.0 / 8) * (5 * point(level1, middle) + 3 * point(level1, corner)),
                                  "level-2 {5,3} next to cube corner " + std::to_string(corner)});
            }
        }
        return values;
    });
}

// (b) Crease edges with a dart end are bisected with the smooth mask {3,3,1,1}: a crease segment of three edges
// inside a torus (darts at both ends, regular crease vertices between), and a lone crease edge (darts at both
// ends). The middle edge of the segment joins two regular crease vertices: midpoint, as OpenSubdiv.
TEST(Hoppe94VsOpenSubdiv, DartEndedCreaseEdgeUsesSmoothMask) {
    TestMesh mesh = torus(12, 6);
    jitter(mesh, 20, 0.01f);
    auto v = [](int i, int j) { return torus_vertex(6, i, j); };
    for (int i = 2; i < 5; ++i) mesh.add_crease(v(i, 3), v(i + 1, 3), kInfiniteSharpness);
    mesh.add_crease(v(8, 1), v(9, 2), kInfiniteSharpness);
    const int dart_edges[3][2] = {{v(2, 3), v(3, 3)}, {v(4, 3), v(5, 3)}, {v(8, 1), v(9, 2)}};
    expect_seed_values_and_opensubdiv_elsewhere(mesh, 1, [&](const Plan& plan, const MappedReference&) {
        std::vector<SeedValue> values;
        for (const auto& e : dart_edges) {
            const std::vector<int> cd = opposite_vertices(mesh, e[0], e[1]);
            EXPECT_EQ(cd.size(), 2u);
            const Vec3 a = point(mesh.positions, e[0]), b = point(mesh.positions, e[1]);
            const Vec3 c = point(mesh.positions, cd.at(0)), d = point(mesh.positions, cd.at(1));
            values.push_back({edge_point(plan, 0, e[0], e[1]), (1.0 / 8) * (3 * a + 3 * b + c + d),
                              "dart-ended crease edge {3,3,1,1}"});
        }
        return values;
    });
}

// (c) A tagged cone with no crease edge: centre weight 3/8 + b(n), the rest (5/8 - b(n)) shared by the n
// neighbours (docs/rules.md: c0 = n / (5/8 - b(n)) - n, ci = 1). Valences 3 to 12 at a bipyramid's apex.
TEST(Hoppe94VsOpenSubdiv, ConeVertexMask) {
    for (int n : {3, 4, 5, 6, 8, 12}) {
        SCOPED_TRACE("valence " + std::to_string(n));
        TestMesh mesh = bipyramid(n);
        jitter(mesh, 300 + n, 0.01f);
        mesh.cone_vertices.push_back(0);
        const double b = seed_b(n);
        Vec3 ring{0, 0, 0};
        for (int k = 0; k < n; ++k) ring = ring + point(mesh.positions, 2 + k);
        const Vec3 expected = (3.0 / 8 + b) * point(mesh.positions, 0) + ((5.0 / 8 - b) / n) * ring;
        expect_seed_values_and_opensubdiv_elsewhere(mesh, 1, [&](const Plan&, const MappedReference&) {
            return std::vector<SeedValue>{{0, expected, "cone, centre weight 3/8 + b(n)"}};
        });
    }
}

// (c) A cone with one crease edge (s = 1) is still a cone; the crease edge's other end is a dart, so that edge is
// bisected with {3,3,1,1}.
TEST(Hoppe94VsOpenSubdiv, ConeWithOneCreaseEdge) {
    const int n = 6;
    TestMesh mesh = bipyramid(n);
    jitter(mesh, 21, 0.01f);
    mesh.cone_vertices.push_back(0);
    mesh.add_crease(0, 2, kInfiniteSharpness);
    const double b = seed_b(n);
    Vec3 ring{0, 0, 0};
    for (int k = 0; k < n; ++k) ring = ring + point(mesh.positions, 2 + k);
    const Vec3 cone = (3.0 / 8 + b) * point(mesh.positions, 0) + ((5.0 / 8 - b) / n) * ring;
    const std::vector<int> cd = opposite_vertices(mesh, 0, 2);
    ASSERT_EQ(cd.size(), 2u);
    const Vec3 edge = (1.0 / 8) * (3 * point(mesh.positions, 0) + 3 * point(mesh.positions, 2) +
                                   point(mesh.positions, cd[0]) + point(mesh.positions, cd[1]));
    expect_seed_values_and_opensubdiv_elsewhere(mesh, 1, [&](const Plan& plan, const MappedReference&) {
        return std::vector<SeedValue>{{0, cone, "cone with one crease edge"},
                                      {edge_point(plan, 0, 0, 2), edge, "crease edge to a dart {3,3,1,1}"}};
    });
}

// (c) A cone on a crease curve (s = 2) becomes a corner: it stays where it is, and its two crease edges, whose
// other ends are regular crease vertices, get {5,3}. OpenSubdiv (no cones) sees a regular crease vertex there.
TEST(Hoppe94VsOpenSubdiv, ConeOnCreaseBecomesCorner) {
    TestMesh mesh = torus_with_crease_loops({0});
    jitter(mesh, 22, 0.01f);
    const int cone = torus_vertex(8, 0, 0);
    mesh.cone_vertices.push_back(cone);
    expect_seed_values_and_opensubdiv_elsewhere(mesh, 1, [&](const Plan& plan, const MappedReference&) {
        std::vector<SeedValue> values{{cone, point(mesh.positions, cone), "cone on a crease: corner, fixed"}};
        for (int neighbour : {torus_vertex(8, 1, 0), torus_vertex(8, 11, 0)}) {
            values.push_back({edge_point(plan, 0, neighbour, cone),
                              (1.0 / 8) * (5 * point(mesh.positions, neighbour) + 3 * point(mesh.positions, cone)),
                              "{5,3} next to a cone turned corner"});
        }
        return values;
    });
}

// --- Random crease sets: the seed's classification, derived here by hand -------------------------------------

enum class SeedClass { Smooth, Dart, RegularCrease, IrregularCrease, Corner };

// docs/rules.md, "Vertex classes": s = crease edges at the vertex (boundary edges count); 0 smooth, 1 dart, 2 crease,
// >= 3 or tagged corner. A crease vertex is regular when interior with valence 6 and three faces on each side of its
// crease, or on the boundary with valence 4 (three faces) and its crease edges the boundary edges.
// For manifold meshes only.
std::vector<SeedClass> classify_by_hand(const TestMesh& mesh, const std::set<std::pair<int, int>>& creases) {
    const int n = mesh.num_vertices();
    std::vector<std::map<int, int>> next(n);  // around v: for face (v, x, y) counter-clockwise, next[v][x] = y
    std::vector<int> faces(n, 0);
    for (int t = 0; t < mesh.num_triangles(); ++t)
        for (int k = 0; k < 3; ++k) {
            const int v = mesh.triangles[3 * t + k];
            next[v][mesh.triangles[3 * t + (k + 1) % 3]] = mesh.triangles[3 * t + (k + 2) % 3];
            ++faces[v];
        }
    std::set<int> corners;
    for (std::size_t k = 0; k < mesh.corner_vertices.size(); ++k)
        if (mesh.corner_sharpness[k] > 0) corners.insert(mesh.corner_vertices[k]);
    std::vector<SeedClass> type(n);
    for (int v = 0; v < n; ++v) {
        std::set<int> neighbours;
        for (const auto& [x, y] : next[v]) {
            neighbours.insert(x);
            neighbours.insert(y);
        }
        std::vector<int> crease_neighbours;
        for (int u : neighbours)
            if (creases.count({std::min(u, v), std::max(u, v)})) crease_neighbours.push_back(u);
        const int valence = int(neighbours.size());
        const bool boundary = faces[v] < valence;
        const int s = int(crease_neighbours.size());
        if (corners.count(v) || s >= 3) {
            type[v] = SeedClass::Corner;
        } else if (s == 0) {
            type[v] = SeedClass::Smooth;
        } else if (s == 1) {
            type[v] = SeedClass::Dart;
        } else if (boundary) {
            // s == 2 with two boundary edges at v: the creases are the boundary edges.
            type[v] = valence == 4 ? SeedClass::RegularCrease : SeedClass::IrregularCrease;
        } else {
            int faces_one_side = 0;
            for (int u = crease_neighbours[0]; u != crease_neighbours[1]; u = next[v].at(u)) ++faces_one_side;
            type[v] = (valence == 6 && faces_one_side == 3) ? SeedClass::RegularCrease : SeedClass::IrregularCrease;
        }
    }
    return type;
}

// On random sets of sharp creases and corners, open and closed, every level-1 vertex is OpenSubdiv's except the
// edge points of crease edges with a dart end ({3,3,1,1}) or between a regular crease vertex and an irregular one
// or a corner ({5,3,0,0}, the 5 on the regular end), which have the seed's value.
TEST(Hoppe94VsOpenSubdiv, RandomCreaseSetsLevel1) {
    struct Random {
        std::string name;
        TestMesh mesh;
    };
    std::vector<Random> meshes;
    for (unsigned seed : {1u, 2u, 3u}) {
        TestMesh m = icosphere(2);
        jitter(m, 400 + seed, 0.01f);
        add_random_creases(m, 400 + seed, 0.2, false);
        add_random_corners(m, 500 + seed, 3, false);
        meshes.push_back({"icosphere320 seed " + std::to_string(seed), m});
    }
    {
        TestMesh m = grid(7, 6);
        jitter(m, 410, 0.01f);
        add_random_creases(m, 410, 0.25, false);
        meshes.push_back({"grid7x6", m});
    }
    {
        TestMesh m = hemisphere(2);
        jitter(m, 411, 0.01f);
        add_random_creases(m, 411, 0.2, false);
        meshes.push_back({"hemisphere", m});
    }
    int fivethree = 0, dart = 0;
    for (const Random& r : meshes) {
        SCOPED_TRACE(r.name);
        const TestMesh& mesh = r.mesh;
        std::set<std::pair<int, int>> creases;
        for (std::size_t k = 0; k < mesh.crease_sharpness.size(); ++k)
            creases.insert(std::minmax(mesh.crease_edges[2 * k], mesh.crease_edges[2 * k + 1]));
        std::map<std::pair<int, int>, int> faces_per_edge;
        for (int t = 0; t < mesh.num_triangles(); ++t)
            for (int k = 0; k < 3; ++k)
                ++faces_per_edge[std::minmax(mesh.triangles[3 * t + k], mesh.triangles[3 * t + (k + 1) % 3])];
        for (const auto& [edge, faces] : faces_per_edge)
            if (faces == 1) creases.insert(edge);  // boundary edges are creases
        const std::vector<SeedClass> type = classify_by_hand(mesh, creases);

        expect_seed_values_and_opensubdiv_elsewhere(mesh, 1, [&](const Plan& plan, const MappedReference&) {
            std::vector<SeedValue> values;
            for (const auto& [a, b] : creases) {
                const Vec3 pa = point(mesh.positions, a), pb = point(mesh.positions, b);
                if (type[a] == SeedClass::Dart || type[b] == SeedClass::Dart) {
                    const std::vector<int> cd = opposite_vertices(mesh, a, b);
                    if (cd.size() != 2) continue;  // a boundary edge cannot have a dart end
                    values.push_back(
                        {edge_point(plan, 0, a, b),
                         (1.0 / 8) * (3 * pa + 3 * pb + point(mesh.positions, cd[0]) + point(mesh.positions, cd[1])),
                         "dart-ended crease edge " + std::to_string(a) + "-" + std::to_string(b)});
                    ++dart;
                    continue;
                }
                auto irregular_or_corner = [&](int v) {
                    return type[v] == SeedClass::IrregularCrease || type[v] == SeedClass::Corner;
                };
                int regular = -1, other = -1;
                if (type[a] == SeedClass::RegularCrease && irregular_or_corner(b)) regular = a, other = b;
                if (type[b] == SeedClass::RegularCrease && irregular_or_corner(a)) regular = b, other = a;
                if (regular < 0) continue;
                values.push_back(
                    {edge_point(plan, 0, a, b),
                     (1.0 / 8) * (5 * point(mesh.positions, regular) + 3 * point(mesh.positions, other)),
                     "{5,3} edge, regular " + std::to_string(regular) + ", other " + std::to_string(other)});
                ++fivethree;
            }
            return values;
        });
    }
    // The random sets must really contain both kinds of difference, or this test proves less than it says.
    EXPECT_GT(fivethree, 10);
    EXPECT_GT(dart, 10);
}

}  // namespace
}  // namespace loopsub::testing
