// Invariants of Loop subdivision that hold under both rule sets, checked from the output alone (counts, topology,
// orientation), plus the documented output order and the round trip of the output's crease tags.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
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

enum class Kind { ClosedManifold, OpenManifold, NonManifold };

struct InvariantCase {
    std::string name;
    std::function<TestMesh()> make;
    Kind kind;
    Rules rules;
    int levels;
};
// gtest prints a parameter with this (instead of its bytes) when a case fails.
void PrintTo(const InvariantCase& c, std::ostream* os) { *os << c.name; }

using Edge = std::pair<std::int32_t, std::int32_t>;

Edge undirected(std::int32_t a, std::int32_t b) { return {std::min(a, b), std::max(a, b)}; }

// Faces per undirected edge, and uses per directed edge.
struct EdgeCounts {
    std::map<Edge, int> faces;
    std::map<Edge, int> directed;
};

EdgeCounts count_edges(const std::int32_t* triangles, int num_triangles) {
    EdgeCounts counts;
    for (int t = 0; t < num_triangles; ++t)
        for (int k = 0; k < 3; ++k) {
            const std::int32_t a = triangles[3 * t + k], b = triangles[3 * t + (k + 1) % 3];
            ++counts.faces[undirected(a, b)];
            ++counts.directed[{a, b}];
        }
    return counts;
}

Options options_for(const InvariantCase& c, const TestMesh& mesh) {
    Options options;
    options.rules = c.rules;
    options.levels = c.levels;
    options.boundary = mesh.boundary;
    options.crease_method = mesh.crease_method;
    return options;
}

std::vector<InvariantCase> invariant_cases() {
    struct NamedMesh {
        std::string name;
        std::function<TestMesh()> make;
        Kind kind;
    };
    const std::vector<NamedMesh> meshes = {
        {"icosphere80",
         [] {
             TestMesh m = icosphere(1);
             jitter(m, 71, 0.01f);
             return m;
         },
         Kind::ClosedManifold},
        {"torus8x6_creased",
         [] {
             TestMesh m = torus(8, 6);
             for (int i = 0; i < 8; ++i) m.add_crease(torus_vertex(6, i, 0), torus_vertex(6, (i + 1) % 8, 0), 3.5f);
             m.add_corner(torus_vertex(6, 3, 0), kInfiniteSharpness);
             return m;
         },
         Kind::ClosedManifold},
        {"cube_sharp_edges",
         [] {
             TestMesh m = cube();
             for (const auto& e : unique_edges(m.triangles))
                 if (__builtin_popcount(unsigned(e[0] ^ e[1])) == 1) m.add_crease(e[0], e[1], kInfiniteSharpness);
             return m;
         },
         Kind::ClosedManifold},
        {"bipyramid7_cone",
         [] {
             TestMesh m = bipyramid(7);
             m.cone_vertices.push_back(0);  // Hoppe94 only; OpenSubdiv ignores cones
             return m;
         },
         Kind::ClosedManifold},
        {"grid5x4",
         [] {
             TestMesh m = grid(5, 4);
             add_random_creases(m, 72, 0.2, true);
             return m;
         },
         Kind::OpenManifold},
        {"hemisphere80_edges_and_corners",
         [] {
             TestMesh m = hemisphere(1);
             m.boundary = Boundary::EdgesAndCorners;
             return m;
         },
         Kind::OpenManifold},
        {"open_cylinder6x2", [] { return open_cylinder(6, 2); }, Kind::OpenManifold},
        {"fin_on_grid", [] { return fin_on_grid(); }, Kind::NonManifold},
        {"bowtie3", [] { return bowtie(3); }, Kind::NonManifold},
    };
    std::vector<InvariantCase> cases;
    for (const NamedMesh& m : meshes)
        for (Rules rules : {Rules::Hoppe94, Rules::OpenSubdiv})
            for (int levels = 1; levels <= 3; ++levels)
                cases.push_back(
                    {m.name + (rules == Rules::Hoppe94 ? "_hoppe94" : "_opensubdiv") + "_L" + std::to_string(levels),
                     m.make, m.kind, rules, levels});
    return cases;
}

class Invariants : public ::testing::TestWithParam<InvariantCase> {
protected:
    void SetUp() override {
        mesh_ = GetParam().make();
        plan_ = std::make_unique<Plan>(mesh_.view(), options_for(GetParam(), mesh_));
        positions_ = evaluate_positions(*plan_, mesh_);
    }
    TestMesh mesh_;
    std::unique_ptr<Plan> plan_;
    std::vector<float> positions_;
};

// Every input triangle becomes 4^L output triangles, listed together: output triangle t descends from input
// triangle t / 4^L (each level puts the four children of face f at 4f .. 4f+3).
TEST_P(Invariants, FourToTheLevelChildrenPerTriangle) {
    const Plan& plan = *plan_;
    const int per_triangle = 1 << (2 * GetParam().levels);
    ASSERT_EQ(plan.num_output_triangles(), mesh_.num_triangles() * per_triangle);
    const std::int32_t* parents = plan.output_parent_triangles();
    int wrong = 0;
    for (int t = 0; t < plan.num_output_triangles(); ++t) {
        if (parents[t] != t / per_triangle && wrong++ < 5)
            ADD_FAILURE() << "output triangle " << t << " has parent " << parents[t] << ", expected "
                          << t / per_triangle;
    }
}

// Vertex and edge counts follow V' = V + E, E' = 2E + 3F, F' = 4F, so V - E + F never changes; every output
// vertex is used by some triangle; every output index is in range.
TEST_P(Invariants, CountsAndEulerCharacteristic) {
    const Plan& plan = *plan_;
    long long v = mesh_.num_vertices(), e = long(unique_edges(mesh_.triangles).size()), f = mesh_.num_triangles();
    const long long euler = v - e + f;
    for (int level = 0; level < GetParam().levels; ++level) {
        EXPECT_EQ(plan.level_num_vertices(level), v) << "level " << level;
        EXPECT_EQ(long(plan.level_edges(level).size() / 2), e) << "level " << level;
        v += e;
        e = 2 * e + 3 * f;
        f *= 4;
    }
    ASSERT_EQ(plan.num_output_vertices(), v);
    ASSERT_EQ(plan.num_output_triangles(), f);
    const std::int32_t* tris = plan.output_triangles();
    std::vector<char> used(v, 0);
    for (long long i = 0; i < 3 * f; ++i) {
        ASSERT_GE(tris[i], 0);
        ASSERT_LT(tris[i], v);
        used[tris[i]] = 1;
    }
    EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0) << "output vertices that no triangle uses";
    const EdgeCounts counts = count_edges(tris, int(f));
    EXPECT_EQ((long long)counts.faces.size(), e);
    EXPECT_EQ(v - (long long)counts.faces.size() + f, euler);
}

// Plan::output_edges: every distinct edge of the output triangles once (non-manifold ones included), each
// triangle's edge k joining its corners k and k + 1, the halves of edge e of the level before at 2e and 2e + 1; asked
// for the triangles too, the same edges and the output triangles as they are.
TEST_P(Invariants, OutputEdgesAreTheTrianglesEdgesNumberedBySplit) {
    const Plan& plan = *plan_;
    const int num_edges = plan.num_output_edges();
    std::vector<std::int32_t> ends(2 * std::size_t(num_edges)), sides(3 * std::size_t(plan.num_output_triangles()));
    plan.output_edges(ends.data(), sides.data());
    std::vector<std::int32_t> ends_again(ends.size(), -1), sides_again(sides.size(), -1), copied(sides.size(), -1);
    plan.output_edges(ends_again.data(), sides_again.data(), copied.data());
    EXPECT_EQ(ends_again, ends);
    EXPECT_EQ(sides_again, sides);
    EXPECT_EQ(copied, std::vector<std::int32_t>(plan.output_triangles(), plan.output_triangles() + sides.size()));
    std::vector<std::array<std::int32_t, 2>> listed;
    for (int e = 0; e < num_edges; ++e)
        listed.push_back({std::min(ends[2 * e], ends[2 * e + 1]), std::max(ends[2 * e], ends[2 * e + 1])});
    std::vector<std::array<std::int32_t, 2>> sorted = listed;
    std::sort(sorted.begin(), sorted.end());
    const std::vector<std::int32_t> triangles(plan.output_triangles(), plan.output_triangles() + sides.size());
    ASSERT_EQ(sorted, unique_edges(triangles));
    for (std::size_t t = 0; t < sides.size() / 3; ++t) {
        for (int k = 0; k < 3; ++k) {
            const std::int32_t a = triangles[3 * t + k], b = triangles[3 * t + (k + 1) % 3];
            ASSERT_EQ(listed[std::size_t(sides[3 * t + k])],
                      (std::array<std::int32_t, 2>{std::min(a, b), std::max(a, b)}))
                << "triangle " << t << ", edge " << k;
        }
    }
    const std::vector<std::int32_t>& before = plan.level_edges(GetParam().levels - 1);
    const std::int32_t first_midpoint = plan.level_num_vertices(GetParam().levels - 1);
    for (std::size_t e = 0; e < before.size() / 2; ++e) {
        const std::int32_t midpoint = first_midpoint + std::int32_t(e);
        ASSERT_EQ(ends[4 * e], before[2 * e]);
        ASSERT_EQ(ends[4 * e + 1], midpoint);
        ASSERT_EQ(ends[4 * e + 2], midpoint);
        ASSERT_EQ(ends[4 * e + 3], before[2 * e + 1]);
    }
}

// Plan::output_edge_parents: the input edge each output edge lies on, against where each vertex lies, worked out
// level by level from the level's edges (an input vertex, a point of an input edge, or inside an input triangle): an
// edge lies on the input edge whose closure holds both its ends. The caller's numbers are the input edges' places
// among their sorted pairs; a side numbered -1 (a diagonal) loses to another side's number, and an edge given only
// -1 lies on no edge.
TEST_P(Invariants, OutputEdgeParentsNameTheInputEdgeEachLiesOn) {
    const Plan& plan = *plan_;
    const std::vector<std::array<std::int32_t, 2>> input_edges = unique_edges(mesh_.triangles);
    auto number_of = [&](std::int32_t a, std::int32_t b) {
        const std::array<std::int32_t, 2> pair{std::min(a, b), std::max(a, b)};
        const auto found = std::lower_bound(input_edges.begin(), input_edges.end(), pair);
        return found != input_edges.end() && *found == pair ? std::int32_t(found - input_edges.begin()) : -1;
    };
    // Every seventh edge unnumbered on all its sides, a third of the others on their first side, a third on their
    // last.
    std::vector<std::int32_t> side_numbers(mesh_.triangles.size()), sides_of(input_edges.size(), 0);
    for (std::size_t c = 0; c < side_numbers.size(); ++c) {
        side_numbers[c] = number_of(mesh_.triangles[c], mesh_.triangles[c - c % 3 + (c + 1) % 3]);
        ++sides_of[std::size_t(side_numbers[c])];
    }
    std::vector<std::int32_t> side_edges(side_numbers.size()), given(input_edges.size(), 0);
    std::vector<std::int32_t> expected_numbers(input_edges.size(), -1);  // the greatest of each edge's sides
    for (std::size_t c = 0; c < side_edges.size(); ++c) {
        const std::int32_t number = side_numbers[c];
        const std::int32_t place = given[std::size_t(number)]++;
        const bool dropped = number % 7 == 3 || (number % 3 == 1 && place == 0) ||
                             (number % 3 == 2 && place + 1 == sides_of[std::size_t(number)]);
        side_edges[c] = dropped ? -1 : number;
        expected_numbers[std::size_t(number)] = std::max(expected_numbers[std::size_t(number)], side_edges[c]);
    }

    struct Place {
        int kind;  // 0: input vertex id, 1: on input edge id, 2: inside a triangle
        std::int32_t id;
    };
    auto on_closure = [&](const Place& p, std::int32_t edge) {
        return (p.kind == 1 && p.id == edge) || (p.kind == 0 && (input_edges[std::size_t(edge)][0] == p.id ||
                                                                 input_edges[std::size_t(edge)][1] == p.id));
    };
    auto edge_between = [&](const Place& a, const Place& b) -> std::int32_t {
        if (a.kind == 0 && b.kind == 0) return number_of(a.id, b.id);
        if (a.kind == 1 && on_closure(b, a.id)) return a.id;
        if (b.kind == 1 && on_closure(a, b.id)) return b.id;
        return -1;
    };
    std::vector<Place> places(std::size_t(mesh_.num_vertices()));
    for (std::size_t v = 0; v < places.size(); ++v) places[v] = {0, std::int32_t(v)};
    for (int level = 0; level < GetParam().levels; ++level) {
        const std::vector<std::int32_t>& edges = plan.level_edges(level);
        for (std::size_t e = 0; e < edges.size() / 2; ++e) {
            const std::int32_t on =
                edge_between(places[std::size_t(edges[2 * e])], places[std::size_t(edges[2 * e + 1])]);
            places.push_back(on >= 0 ? Place{1, on} : Place{2, -1});
        }
        ASSERT_EQ(int(places.size()), plan.level_num_vertices(level + 1));
    }

    const int num_edges = plan.num_output_edges();
    std::vector<std::int32_t> ends(2 * std::size_t(num_edges)), sides(3 * std::size_t(plan.num_output_triangles()));
    plan.output_edges(ends.data(), sides.data());
    std::vector<std::int32_t> parents(std::size_t(num_edges), -7);
    plan.output_edge_parents(side_edges.data(), parents.data());
    int on_input_edges = 0;
    for (int e = 0; e < num_edges; ++e) {
        const std::int32_t on = edge_between(places[std::size_t(ends[2 * e])], places[std::size_t(ends[2 * e + 1])]);
        on_input_edges += on >= 0;
        ASSERT_EQ(parents[std::size_t(e)], on >= 0 ? expected_numbers[std::size_t(on)] : -1) << "output edge " << e;
    }
    EXPECT_EQ(on_input_edges, int(input_edges.size()) << GetParam().levels);
}

// A closed manifold stays one: every edge in exactly two faces, which traverse it in opposite directions (so the
// orientation is consistent), and the faces around each vertex form a single fan. An open manifold keeps the same
// property inside, and its boundary edges double per level.
class ManifoldInvariants : public Invariants {};

TEST_P(ManifoldInvariants, ManifoldnessAndConsistentOrientation) {
    const Plan& plan = *plan_;
    const EdgeCounts counts = count_edges(plan.output_triangles(), plan.num_output_triangles());
    int boundary_edges = 0, bad = 0;
    for (const auto& [edge, faces] : counts.faces) {
        boundary_edges += faces == 1;
        const bool ok = GetParam().kind == Kind::ClosedManifold ? faces == 2 : (faces == 1 || faces == 2);
        if (!ok && bad++ < 5)
            ADD_FAILURE() << "edge " << edge.first << "-" << edge.second << " has " << faces << " faces";
    }
    for (const auto& [edge, uses] : counts.directed)
        if (uses != 1 && bad++ < 10)
            ADD_FAILURE() << "directed edge " << edge.first << "->" << edge.second << " used " << uses
                          << " times: neighbouring faces do not traverse it in opposite directions";
    int input_boundary = 0;
    for (const auto& [edge, faces] : count_edges(mesh_.triangles.data(), mesh_.num_triangles()).faces)
        input_boundary += faces == 1;
    EXPECT_EQ(boundary_edges, input_boundary << GetParam().levels);

    // One fan per vertex: following "next face around v" through shared edges visits all of v's faces.
    std::vector<std::vector<int>> faces_of(plan.num_output_vertices());
    const std::int32_t* tris = plan.output_triangles();
    for (int t = 0; t < plan.num_output_triangles(); ++t)
        for (int k = 0; k < 3; ++k) faces_of[tris[3 * t + k]].push_back(t);
    std::map<Edge, int> face_of_directed;
    for (int t = 0; t < plan.num_output_triangles(); ++t)
        for (int k = 0; k < 3; ++k) face_of_directed[{tris[3 * t + k], tris[3 * t + (k + 1) % 3]}] = t;
    int split_vertices = 0;
    for (int v = 0; v < plan.num_output_vertices(); ++v) {
        if (faces_of[v].empty()) continue;
        // Walk both ways from the first face: across the edge leaving v (v->next is shared with the face that has
        // next->v), then across the edge entering v, until the fan closes or reaches the boundary.
        const int first = faces_of[v][0];
        std::set<int> seen{first};
        for (int direction = 0; direction < 2; ++direction) {
            int t = first;
            while (true) {
                const std::int32_t* tri = &tris[3 * t];
                const int k = int(std::find(tri, tri + 3, v) - tri);
                const Edge across = direction == 0 ? Edge{tri[(k + 1) % 3], v} : Edge{v, tri[(k + 2) % 3]};
                auto it = face_of_directed.find(across);
                if (it == face_of_directed.end()) break;
                t = it->second;
                if (!seen.insert(t).second) break;
            }
        }
        if (seen.size() != faces_of[v].size() && split_vertices++ < 5)
            ADD_FAILURE() << "the faces around vertex " << v << " do not form one fan (" << seen.size() << " of "
                          << faces_of[v].size() << " reached)";
    }
}

// The documented order at every level: the children of face f = (a, b, c) are 4f .. 4f+3, the corner children
// first in corner order, (a, ab, ca), (b, bc, ab), (c, ca, bc) up to rotation, and the middle (ab, bc, ca) last,
// where xy is the new vertex of edge x-y (level vertices + its index in level_edges). This also proves the winding
// is kept. Rebuilt from the last level down to the input triangles.
TEST_P(Invariants, ChildTrianglesFollowTheDocumentedOrderAndWinding) {
    const Plan& plan = *plan_;
    const std::int32_t* out = plan.output_triangles();
    std::vector<std::int32_t> level_tris(out, out + 3 * plan.num_output_triangles());
    for (int level = GetParam().levels - 1; level >= 0; --level) {
        const int nv = plan.level_num_vertices(level);
        std::map<Edge, int> edge_vertex;
        const std::vector<std::int32_t>& edges = plan.level_edges(level);
        for (std::size_t k = 0; 2 * k < edges.size(); ++k)
            edge_vertex[undirected(edges[2 * k], edges[2 * k + 1])] = nv + int(k);
        const int num_parents = int(level_tris.size() / 12);
        std::vector<std::int32_t> parents(3 * std::size_t(num_parents));
        int bad = 0;
        for (int f = 0; f < num_parents; ++f) {
            // The parent's corners are the old vertices (index < nv) of its corner children, in order.
            std::int32_t p[3];
            for (int k = 0; k < 3; ++k) {
                const std::int32_t* child = &level_tris[3 * (4 * f + k)];
                const std::int32_t* old = std::find_if(child, child + 3, [nv](std::int32_t v) { return v < nv; });
                p[k] = old == child + 3 ? -1 : *old;
            }
            auto mid = [&](int x, int y) {
                auto it = edge_vertex.find(undirected(x, y));
                return it == edge_vertex.end() ? -1 : it->second;
            };
            const int ab = mid(p[0], p[1]), bc = mid(p[1], p[2]), ca = mid(p[2], p[0]);
            const std::array<std::int32_t, 3> expected[4] = {
                canonical_triangle(p[0], ab, ca), canonical_triangle(p[1], bc, ab), canonical_triangle(p[2], ca, bc),
                canonical_triangle(ab, bc, ca)};
            for (int k = 0; k < 4; ++k) {
                const std::int32_t* child = &level_tris[3 * (4 * f + k)];
                if (canonical_triangle(child[0], child[1], child[2]) != expected[k] && bad++ < 5)
                    ADD_FAILURE() << "level " << level + 1 << " triangle " << 4 * f + k << " (" << child[0] << ", "
                                  << child[1] << ", " << child[2] << ") is not child " << k << " of (" << p[0] << ", "
                                  << p[1] << ", " << p[2] << ")";
            }
            std::copy(p, p + 3, &parents[3 * f]);
        }
        ASSERT_EQ(bad, 0);
        level_tris = std::move(parents);
    }
    EXPECT_EQ(level_tris, mesh_.triangles) << "the rebuilt level 0 is not the input";
}

// Geometric winding: each output triangle's normal points to the same side as its input triangle's (the limit
// surface stays within 90 degrees of the coarse faces on these meshes).
TEST_P(ManifoldInvariants, ChildNormalsPointLikeTheirParents) {
    const Plan& plan = *plan_;
    auto normal = [](const std::vector<float>& p, const std::int32_t* t) {
        double u[3], w[3];
        for (int k = 0; k < 3; ++k) {
            u[k] = double(p[3 * t[1] + k]) - p[3 * t[0] + k];
            w[k] = double(p[3 * t[2] + k]) - p[3 * t[0] + k];
        }
        return std::array<double, 3>{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    };
    int flipped = 0;
    for (int t = 0; t < plan.num_output_triangles(); ++t) {
        const auto child = normal(positions_, &plan.output_triangles()[3 * t]);
        const auto parent = normal(mesh_.positions, &mesh_.triangles[3 * plan.output_parent_triangles()[t]]);
        if (child[0] * parent[0] + child[1] * parent[1] + child[2] * parent[2] <= 0 && flipped++ < 5)
            ADD_FAILURE() << "output triangle " << t << " faces away from its parent "
                          << plan.output_parent_triangles()[t];
    }
}

std::vector<InvariantCase> manifold_cases() {
    std::vector<InvariantCase> cases = invariant_cases();
    cases.erase(
        std::remove_if(cases.begin(), cases.end(), [](const InvariantCase& c) { return c.kind == Kind::NonManifold; }),
        cases.end());
    return cases;
}

INSTANTIATE_TEST_SUITE_P(BothRules, Invariants, ::testing::ValuesIn(invariant_cases()), case_name<InvariantCase>);
// Manifoldness and face orientation only mean something on manifold input (a fin folds over by design).
INSTANTIATE_TEST_SUITE_P(BothRules, ManifoldInvariants, ::testing::ValuesIn(manifold_cases()),
                         case_name<InvariantCase>);

// --- Feeding the output back in ------------------------------------------------------------------------------

struct FeedBackCase {
    std::string name;
    std::function<TestMesh()> make;
    Rules rules;
    float crease_threshold;
};
// gtest prints a parameter with this (instead of its bytes) when a case fails.
void PrintTo(const FeedBackCase& c, std::ostream* os) { *os << c.name; }

// A plan's output as a mesh to feed back in: its positions (evaluated from `mesh`), triangles, output crease and corner
// tags, and `mesh`'s boundary and crease method.
TestMesh fed_back(Plan& plan, const TestMesh& mesh) {
    TestMesh out;
    out.positions = evaluate_positions(plan, mesh);
    out.triangles.assign(plan.output_triangles(), plan.output_triangles() + 3 * plan.num_output_triangles());
    out.crease_edges = plan.output_crease_edges();
    out.crease_sharpness = plan.output_crease_sharpness();
    out.corner_vertices = plan.output_corner_vertices();
    out.corner_sharpness = plan.output_corner_sharpness();
    out.boundary = mesh.boundary;
    out.crease_method = mesh.crease_method;
    return out;
}

// Level-1 output (positions, triangles, output crease and corner tags) refined once more equals two levels at
// once: same vertices (level-1 vertices keep their indices; the new ones are matched through their edge), same
// triangles, same positions, same tags.
class FeedBack : public ::testing::TestWithParam<FeedBackCase> {};

TEST_P(FeedBack, OneLevelTwiceEqualsTwoLevels) {
    const FeedBackCase& c = GetParam();
    const TestMesh mesh = c.make();
    Options options;
    options.rules = c.rules;
    options.boundary = mesh.boundary;
    options.crease_method = mesh.crease_method;
    options.crease_threshold = c.crease_threshold;

    options.levels = 2;
    Plan both(mesh.view(), options);
    const std::vector<float> both_positions = evaluate_positions(both, mesh);

    options.levels = 1;
    Plan first(mesh.view(), options);
    const TestMesh level1 = fed_back(first, mesh);
    ASSERT_FALSE(level1.crease_sharpness.empty()) << "test set-up: the case must carry crease tags to level 1";
    Plan second(level1.view(), options);
    const std::vector<float> second_positions = evaluate_positions(second, level1);

    ASSERT_EQ(second.num_output_vertices(), both.num_output_vertices());
    ASSERT_EQ(second.num_output_triangles(), both.num_output_triangles());
    // second's vertex v -> both's vertex.
    const int n1 = both.level_num_vertices(1);
    ASSERT_EQ(second.level_num_vertices(0), n1);
    std::map<Edge, int> both_edge_vertex;
    const std::vector<std::int32_t>& both_edges = both.level_edges(1);
    for (std::size_t k = 0; 2 * k < both_edges.size(); ++k)
        both_edge_vertex[undirected(both_edges[2 * k], both_edges[2 * k + 1])] = n1 + int(k);
    std::vector<int> to_both(second.num_output_vertices());
    for (int v = 0; v < n1; ++v) to_both[v] = v;
    const std::vector<std::int32_t>& second_edges = second.level_edges(0);
    ASSERT_EQ(second_edges.size(), both_edges.size());
    for (std::size_t k = 0; 2 * k < second_edges.size(); ++k) {
        auto it = both_edge_vertex.find(undirected(second_edges[2 * k], second_edges[2 * k + 1]));
        ASSERT_NE(it, both_edge_vertex.end())
            << "level-1 edge " << second_edges[2 * k] << "-" << second_edges[2 * k + 1];
        to_both[n1 + k] = it->second;
    }

    const double tolerance = 1e-6 * bounding_box_diagonal(mesh.positions);
    int bad = 0;
    for (int v = 0; v < second.num_output_vertices(); ++v) {
        const int w = to_both[v];
        double d2 = 0;
        for (int k = 0; k < 3; ++k) {
            const double d = double(second_positions[3 * v + k]) - both_positions[3 * w + k];
            d2 += d * d;
        }
        if (!(std::sqrt(d2) <= tolerance) && bad++ < 5)
            ADD_FAILURE() << "vertex " << w << " (two levels) differs after feeding level 1 back: distance "
                          << std::sqrt(d2);
    }

    std::multiset<std::array<std::int32_t, 3>> both_tris, second_tris;
    for (int t = 0; t < both.num_output_triangles(); ++t) {
        const std::int32_t* a = &both.output_triangles()[3 * t];
        const std::int32_t* b = &second.output_triangles()[3 * t];
        both_tris.insert(canonical_triangle(a[0], a[1], a[2]));
        second_tris.insert(canonical_triangle(to_both[b[0]], to_both[b[1]], to_both[b[2]]));
    }
    EXPECT_TRUE(both_tris == second_tris) << "the triangles differ";

    std::map<Edge, float> both_tags, second_tags;
    for (std::size_t k = 0; k < both.output_crease_sharpness().size(); ++k)
        both_tags[undirected(both.output_crease_edges()[2 * k], both.output_crease_edges()[2 * k + 1])] =
            both.output_crease_sharpness()[k];
    for (std::size_t k = 0; k < second.output_crease_sharpness().size(); ++k)
        second_tags[undirected(to_both[second.output_crease_edges()[2 * k]],
                               to_both[second.output_crease_edges()[2 * k + 1]])] = second.output_crease_sharpness()[k];
    EXPECT_EQ(both_tags, second_tags) << "output crease tags differ";
    std::map<int, float> both_corners, second_corners;
    for (std::size_t k = 0; k < both.output_corner_vertices().size(); ++k)
        both_corners[both.output_corner_vertices()[k]] = both.output_corner_sharpness()[k];
    for (std::size_t k = 0; k < second.output_corner_vertices().size(); ++k)
        second_corners[to_both[second.output_corner_vertices()[k]]] = second.output_corner_sharpness()[k];
    EXPECT_EQ(both_corners, second_corners) << "output corner tags differ";
}

std::vector<FeedBackCase> feed_back_cases() {
    std::vector<FeedBackCase> cases;
    for (CreaseMethod method : {CreaseMethod::Uniform, CreaseMethod::Chaikin}) {
        cases.push_back(
            {std::string("opensubdiv_semisharp_") + (method == CreaseMethod::Chaikin ? "chaikin" : "uniform"),
             [method] {
                 TestMesh m = icosphere(2);
                 jitter(m, 81, 0.01f);
                 add_random_creases(m, 81, 0.25, true);
                 add_random_corners(m, 82, 6, true);
                 m.crease_method = method;
                 return m;
             },
             Rules::OpenSubdiv, 0.0f});
    }
    cases.push_back({"opensubdiv_grid_edges_and_corners",
                     [] {
                         TestMesh m = grid(5, 4);
                         m.boundary = Boundary::EdgesAndCorners;
                         add_random_creases(m, 83, 0.3, true);
                         return m;
                     },
                     Rules::OpenSubdiv, 0.0f});
    // Hoppe94: darts, irregular and regular crease vertices, corners (tagged and by count), boundary.
    cases.push_back({"hoppe94_grid_creases_and_corners",
                     [] {
                         TestMesh m = grid(6, 6);
                         add_random_creases(m, 84, 0.2, false);
                         add_random_corners(m, 85, 3, false);
                         return m;
                     },
                     Rules::Hoppe94, 0.0f});
    // Hoppe94 with a threshold: tags below it must stay below it (carried over, not dropped or raised).
    cases.push_back({"hoppe94_threshold",
                     [] {
                         TestMesh m = icosphere(2);
                         add_random_creases(m, 86, 0.3, true);
                         return m;
                     },
                     Rules::Hoppe94, 1.5f});
    return cases;
}

INSTANTIATE_TEST_SUITE_P(BothRules, FeedBack, ::testing::ValuesIn(feed_back_cases()),
                         [](const ::testing::TestParamInfo<FeedBackCase>& info) { return info.param.name; });

// A refined level fed back in with its edges (MeshView::triangle_edges, from Plan::output_edges) goes on to the same
// surface, where two of its edges share their ends: next to an interior vertex of valence 2. Two levels of two levels
// are four levels, corner for corner (both number their faces by the splits: face 16 f + 4 i + j of either is child j
// of child i of level-2 face f). Read by their ends, the pairs were one edge of four faces, sharp.
TEST(RefinedLevel, FedBackWithItsEdgesGoesOnToTheSameSurface) {
    const PillowOnIcosahedron pillow = pillow_on_icosahedron();
    TestMesh mesh = pillow.mesh;
    mesh.add_crease(pillow.v, pillow.apex, 3.5f);
    Options options;
    options.levels = 4;
    Plan four(mesh.view(), options);
    const std::vector<float> four_positions = evaluate_positions(four, mesh);

    options.levels = 2;
    Plan two(mesh.view(), options);
    const TestMesh level2 = fed_back(two, mesh);
    std::vector<std::int32_t> edge_vertices(2 * std::size_t(two.num_output_edges())),
        triangle_edges(level2.triangles.size());
    two.output_edges(edge_vertices.data(), triangle_edges.data());
    ASSERT_FALSE(level2.crease_sharpness.empty()) << "test set-up: the crease must outlast level 2";
    MeshView view = level2.view();
    view.triangle_edges = triangle_edges.data();
    Plan again(view, options);
    const std::vector<float> again_positions = evaluate_positions(again, level2);

    ASSERT_EQ(again.num_output_triangles(), four.num_output_triangles());
    const double tolerance = 1e-6 * bounding_box_diagonal(mesh.positions);
    double worst = 0.0;
    for (std::size_t c = 0; c < 3 * std::size_t(four.num_output_triangles()); ++c) {
        const std::int32_t a = again.output_triangles()[c], b = four.output_triangles()[c];
        double d2 = 0.0;
        for (std::size_t k = 0; k < 3; ++k)
            d2 += std::pow(double(again_positions[3 * std::size_t(a) + k]) - four_positions[3 * std::size_t(b) + k], 2);
        worst = std::max(worst, std::sqrt(d2));
    }
    EXPECT_LE(worst, tolerance);
}

}  // namespace
}  // namespace loopsub::testing
