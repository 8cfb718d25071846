// The connectivity a level carries for passes in face order (Topology::face_edge_places) and what those passes
// write (the halves' wings): each checked against the same thing found by looking faces up edge by edge, on closed,
// open and non-manifold meshes through three refinements, split between threads or not. And the split's numbering
// that reading a level through its parent relies on (follows_split_numbering, VertexNeighbourhood's shortcuts).
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "mesh_gen.h"
#include "base/parallel.h"
#include "topology/topology.h"

namespace {

using loopsub::detail::FanCorner;
using loopsub::detail::Index;
using loopsub::detail::Topology;
using loopsub::testing::TestMesh;

// Corner k of face f: the face's place among edge k's faces (at most 2) and whether the corner is the edge's first
// vertex, found by searching.
std::vector<std::uint8_t> places_by_lookup(const Topology& t) {
    std::vector<std::uint8_t> places(t.face_edges.size(), 0xff);
    for (int e = 0; e < t.num_edges(); ++e) {
        int place = 0;
        for (Index k = t.edge_face_offsets[e]; k < t.edge_face_offsets[e + 1]; ++k) {
            const Index f = t.edge_faces[k];
            for (int corner = 0; corner < 3; ++corner) {
                if (t.face_edges[3 * f + corner] != e) continue;
                const bool first = t.face_vertices[3 * f + corner] == t.edge_vertices[2 * e];
                places[3 * std::size_t(f) + corner] = std::uint8_t((place < 2 ? place : 2) << 1 | int(first));
            }
            ++place;
        }
    }
    return places;
}

void expect_face_order_agrees(const Topology& t, const std::string& where) {
    SCOPED_TRACE(where);
    const std::vector<std::uint8_t> expected = places_by_lookup(t);
    ASSERT_EQ(t.face_edge_places.size(), expected.size());
    for (std::size_t c = 0; c < expected.size(); ++c)
        ASSERT_EQ(int(t.face_edge_places[c]), int(expected[c])) << "corner " << c;

    // The halves' wings: in edge order (child_edges, what derived tables use) and in face order, in two parts.
    const int halves = 2 * t.num_edges();
    std::vector<Index> ends(2 * std::size_t(halves)), c(halves), d(halves), face_c(halves, -1), face_d(halves, -1);
    loopsub::detail::child_edges(t, 0, halves, ends.data(), c.data(), d.data());
    const int faces_split = t.num_faces() / 3, edges_split = 2 * t.num_edges() / 3;
    loopsub::detail::write_half_wings(t, 0, faces_split, 0, edges_split, face_c.data(), face_d.data());
    loopsub::detail::write_half_wings(t, faces_split, t.num_faces(), edges_split, t.num_edges(), face_c.data(),
                                      face_d.data());
    EXPECT_EQ(face_c, c);
    EXPECT_EQ(face_d, d);
    std::vector<Index> half_ends(ends.size(), -1);
    loopsub::detail::write_half_ends(t, 0, t.num_edges(), half_ends.data());
    EXPECT_EQ(half_ends, ends);
}

TEST(Topology, FaceOrderAgreesWithLookups) {
    using namespace loopsub::testing;
    const std::pair<const char*, TestMesh> meshes[] = {
        {"icosphere", icosphere(2)}, {"grid", grid(5, 4)},      {"fin on grid", fin_on_grid()},
        {"bowtie", bowtie(5)},       {"open fan", open_fan(5)}, {"open cylinder", open_cylinder(6, 3)}};
    for (const auto& [name, mesh] : meshes) {
        Topology t =
            loopsub::detail::build_base_topology(mesh.triangles.data(), mesh.num_triangles(), mesh.num_vertices());
        expect_face_order_agrees(t, std::string(name) + ", base");
        for (int level = 1; level <= 3; ++level) {
            t = loopsub::detail::refine_topology(t, loopsub::detail::Refined::Full, level % 2 + 1);
            expect_face_order_agrees(t, std::string(name) + ", level " + std::to_string(level));
        }
    }
}

// The base level's connectivity as its contract states it, built here the plain way (a map from each edge's ends to
// its number): edges numbered in order of first appearance, corner by corner; an edge's faces in face order; a
// vertex's edges in edge order with their other ends; the vertices opposite an edge in its first two faces.
void expect_base_matches_lookup(const TestMesh& mesh, int threads) {
    SCOPED_TRACE(mesh.name + ", " + std::to_string(threads) + " threads");
    const loopsub::detail::TeamScope scope(threads);
    const Topology t =
        loopsub::detail::build_base_topology(mesh.triangles.data(), mesh.num_triangles(), mesh.num_vertices(), threads);
    std::map<std::pair<Index, Index>, Index> numbers;
    std::vector<Index> face_edges, edge_vertices;
    std::vector<std::vector<Index>> edge_faces, vertex_edges(mesh.num_vertices()), vertex_vertices(mesh.num_vertices());
    for (std::size_t c = 0; c < mesh.triangles.size(); ++c) {
        const Index a = mesh.triangles[c], b = mesh.triangles[c % 3 == 2 ? c - 2 : c + 1];
        const auto [it, added] = numbers.emplace(std::minmax(a, b), Index(edge_faces.size()));
        if (added) {
            edge_vertices.insert(edge_vertices.end(), {a, b});
            edge_faces.emplace_back();
        }
        face_edges.push_back(it->second);
        edge_faces[it->second].push_back(Index(c / 3));
    }
    for (Index e = 0; e < Index(edge_faces.size()); ++e) {
        const Index a = edge_vertices[2 * e], b = edge_vertices[2 * e + 1];
        vertex_edges[a].push_back(e), vertex_vertices[a].push_back(b);
        vertex_edges[b].push_back(e), vertex_vertices[b].push_back(a);
    }
    ASSERT_EQ(std::vector<Index>(t.face_vertices.begin(), t.face_vertices.end()), mesh.triangles);
    ASSERT_EQ(std::vector<Index>(t.face_edges.begin(), t.face_edges.end()), face_edges);
    ASSERT_EQ(std::vector<Index>(t.edge_vertices.begin(), t.edge_vertices.end()), edge_vertices);
    int max_faces = 0, max_valence = 0;
    for (Index e = 0; e < t.num_edges(); ++e) {
        const std::vector<Index> faces(t.edge_faces.begin() + t.edge_face_offsets[e],
                                       t.edge_faces.begin() + t.edge_face_offsets[e + 1]);
        ASSERT_EQ(faces, edge_faces[e]) << "edge " << e;
        max_faces = std::max(max_faces, int(faces.size()));
        auto opposite = [&](Index f) {
            for (int k = 0; k < 3; ++k)
                if (face_edges[3 * f + k] == e) return mesh.triangles[3 * f + (k + 2) % 3];
            return Index(-1);
        };
        EXPECT_EQ(t.edge_wing_c[e], opposite(faces[0])) << "edge " << e;
        EXPECT_EQ(t.edge_wing_d[e], faces.size() > 1 ? opposite(faces[1]) : edge_vertices[2 * e + 1]) << "edge " << e;
    }
    // Non-manifold edges: more than two faces, or two whose corners run along the edge the same way.
    std::vector<int> direction(edge_faces.size(), 0);
    for (std::size_t c = 0; c < mesh.triangles.size(); ++c)
        direction[face_edges[c]] += mesh.triangles[c] == edge_vertices[2 * face_edges[c]] ? 1 : -1;
    std::vector<std::uint8_t> non_manifold;
    for (std::size_t e = 0; e < edge_faces.size(); ++e)
        non_manifold.push_back(edge_faces[e].size() > 2 || (edge_faces[e].size() == 2 && direction[e] != 0));
    EXPECT_EQ(loopsub::detail::non_manifold_edges(t), non_manifold);
    for (Index v = 0; v < t.num_vertices; ++v) {
        const auto first = t.vertex_edge_offsets[v], last = t.vertex_edge_offsets[v + 1];
        ASSERT_EQ(std::vector<Index>(t.vertex_edges.begin() + first, t.vertex_edges.begin() + last), vertex_edges[v])
            << "vertex " << v;
        ASSERT_EQ(std::vector<Index>(t.vertex_vertices.begin() + first, t.vertex_vertices.begin() + last),
                  vertex_vertices[v])
            << "vertex " << v;
        max_valence = std::max(max_valence, int(vertex_edges[v].size()));
    }
    EXPECT_EQ(t.max_edge_face_count, max_faces);
    EXPECT_EQ(t.max_valence, max_valence);
    EXPECT_EQ(std::vector<std::uint8_t>(t.face_edge_places.begin(), t.face_edge_places.end()), places_by_lookup(t));
}

// Small meshes are built in one part; from a few thousand triangles the build is split among the threads, which must
// not change a number. Fins (edges of three faces), boundaries, a vertex of valence 40 and a random soup included.
TEST(Topology, BaseLevelMatchesLookups) {
    using namespace loopsub::testing;
    TestMesh grid_with_fins = grid(40, 30);  // 2,400 triangles
    grid_with_fins.name = "grid with fins";
    for (int k = 0; k < 5; ++k) {
        const int a = grid_vertex(40, 3 + 7 * k, 2 + 5 * k), b = grid_vertex(40, 4 + 7 * k, 3 + 5 * k);
        grid_with_fins.positions.insert(grid_with_fins.positions.end(), {0.0f, 0.0f, 1.0f});
        grid_with_fins.triangles.insert(grid_with_fins.triangles.end(),
                                        {b, a, Index(grid_with_fins.num_vertices() - 1)});
    }
    // A soup: 3,000 triangles drawn at random over 300 vertices, so edges of many faces, faces repeated or flipped.
    TestMesh soup;
    soup.name = "random soup";
    soup.positions.assign(3 * 300, 0.0f);
    unsigned state = 12345;
    auto draw = [&state] { return Index((state = state * 1103515245u + 12345u) >> 16) % 300; };
    while (soup.num_triangles() < 3000) {
        const Index a = draw(), b = draw(), c = draw();
        if (a != b && b != c && c != a) soup.triangles.insert(soup.triangles.end(), {a, b, c});
    }
    for (const TestMesh& mesh :
         {icosphere(4), grid_with_fins, hemisphere(4), soup, open_fan(40), fin_on_grid(), bowtie(5)})
        for (int threads : {1, 2, 3}) expect_base_matches_lookup(mesh, threads);
}

// A refined level read as a mesh of its own with its edges given (a triangle's neighbourhood refined on its own,
// tessellate/local_refinement.h): next to an interior vertex of valence 2 (a pillow) it keeps the level's two edges
// that share their ends, which a reading by their ends joins into one edge of four faces; elsewhere it is that
// reading, array for array.
TEST(Topology, GivenEdgesKeepTwoEdgesWithTheSameEnds) {
    using namespace loopsub::testing;
    using loopsub::detail::build_base_topology;
    TestMesh pillow;
    pillow.name = "pillow";
    pillow.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    pillow.triangles = {0, 1, 2, 0, 2, 1};
    for (const TestMesh& mesh : {pillow, icosphere(2), fin_on_grid(), bowtie(5)}) {
        SCOPED_TRACE(mesh.name);
        const Topology base = build_base_topology(mesh.triangles.data(), mesh.num_triangles(), mesh.num_vertices());
        const Topology level = loopsub::detail::refine_topology(base, loopsub::detail::Refined::Full, 1);
        const Topology given = build_base_topology(level.face_vertices.data(), level.num_faces(), level.num_vertices, 1,
                                                   level.face_edges.data());
        const Topology by_ends =
            build_base_topology(level.face_vertices.data(), level.num_faces(), level.num_vertices, 1);
        ASSERT_EQ(given.num_edges(), level.num_edges());
        std::map<Index, Index> level_edge;  // of each edge of `given`
        for (std::size_t c = 0; c < given.face_edges.size(); ++c) {
            const auto [at, added] = level_edge.emplace(given.face_edges[c], level.face_edges[c]);
            ASSERT_EQ(at->second, level.face_edges[c]) << "corner " << c;
        }
        for (Index e = 0; e < given.num_edges(); ++e)
            EXPECT_EQ(given.edge_face_count(e), level.edge_face_count(level_edge[e])) << "edge " << e;
        if (mesh.name == "pillow") {
            EXPECT_EQ(by_ends.num_edges(), level.num_edges() - 3);  // the three pairs inside the faces, joined
            EXPECT_EQ(by_ends.max_edge_face_count, 4);
            EXPECT_EQ(given.max_edge_face_count, 2);
            continue;
        }
        auto same = [](const auto& x, const auto& y) { return std::equal(x.begin(), x.end(), y.begin(), y.end()); };
        EXPECT_TRUE(same(given.face_edges, by_ends.face_edges));
        EXPECT_TRUE(same(given.face_edge_places, by_ends.face_edge_places));
        EXPECT_TRUE(same(given.edge_vertices, by_ends.edge_vertices));
        EXPECT_TRUE(same(given.edge_face_offsets, by_ends.edge_face_offsets));
        EXPECT_TRUE(same(given.edge_faces, by_ends.edge_faces));
        EXPECT_TRUE(same(given.edge_wing_c, by_ends.edge_wing_c));
        EXPECT_TRUE(same(given.edge_wing_d, by_ends.edge_wing_d));
        EXPECT_TRUE(same(given.vertex_edge_offsets, by_ends.vertex_edge_offsets));
        EXPECT_TRUE(same(given.vertex_edges, by_ends.vertex_edges));
        EXPECT_TRUE(same(given.vertex_vertices, by_ends.vertex_vertices));
        EXPECT_EQ(given.max_valence, by_ends.max_valence);
        EXPECT_EQ(given.max_edge_face_count, by_ends.max_edge_face_count);
    }
}

// Every form of a split, on one thread or two, holds the numbering its derivations from the parent read
// (follows_split_numbering, which Debug builds assert after each split); and the check sees a child whose faces, edge
// ends, wings or rings are off.
TEST(Topology, SplitsFollowTheirNumbering) {
    using namespace loopsub::testing;
    using loopsub::detail::follows_split_numbering;
    using loopsub::detail::refine_topology;
    using loopsub::detail::Refined;
    for (const TestMesh& mesh : {icosphere(2), grid(4, 3), open_fan(7), fin_on_grid(), bowtie(5)}) {
        SCOPED_TRACE(mesh.name);
        Topology level =
            loopsub::detail::build_base_topology(mesh.triangles.data(), mesh.num_triangles(), mesh.num_vertices());
        for (int split = 1; split <= 2; ++split) {
            for (Refined form : {Refined::Full, Refined::Connectivity, Refined::FacesOnly})
                for (int threads : {1, 2})
                    EXPECT_TRUE(follows_split_numbering(level, refine_topology(level, form, threads)))
                        << "split " << split << ", form " << int(form) << ", threads " << threads;
            Topology child = refine_topology(level, Refined::Full, 1);
            Topology off = child;
            std::swap(off.face_vertices[0], off.face_vertices[1]);
            EXPECT_FALSE(follows_split_numbering(level, off));
            off = child;
            std::swap(off.edge_vertices[0], off.edge_vertices[1]);
            EXPECT_FALSE(follows_split_numbering(level, off));
            off = child;
            ++off.edge_wing_d.back();
            EXPECT_FALSE(follows_split_numbering(level, off));
            off = child;
            ++off.vertex_vertices.back();
            EXPECT_FALSE(follows_split_numbering(level, off));
            level = std::move(child);
        }
    }
}

// The mesh split three times (Refined::Full), and the levels' vertex counts, the base's first.
std::pair<std::vector<Topology>, std::vector<int>> split_three_times(const TestMesh& mesh) {
    std::vector<Topology> levels{
        loopsub::detail::build_base_topology(mesh.triangles.data(), mesh.num_triangles(), mesh.num_vertices())};
    std::vector<int> history{levels[0].num_vertices};
    for (int level = 1; level <= 3; ++level) {
        levels.push_back(loopsub::detail::refine_topology(levels.back(), loopsub::detail::Refined::Full, 1));
        history.push_back(levels.back().num_vertices);
    }
    return {std::move(levels), std::move(history)};
}

// A level known through a parent that is itself known through its own (the last level of a limit plan read through its
// grandparent) reads as the level itself: every face's corners and edges, every edge's ends, wings, faces and face
// count, every vertex's edges and fan, and the faces between a midpoint's halves and between edges at a base
// vertex. On closed, open and non-manifold meshes (a fin, a bowtie) and a loose vertex, three splits deep.
TEST(Topology, ALevelThroughItsGrandparentIsTheLevel) {
    using namespace loopsub::testing;
    using loopsub::detail::VertexNeighbourhood;
    TestMesh with_loose_vertex = grid(4, 3);
    with_loose_vertex.positions.insert(with_loose_vertex.positions.end(), {9.0f, 9.0f, 9.0f});
    for (const TestMesh& mesh : {icosphere(1), with_loose_vertex, open_fan(7), fin_on_grid(), bowtie(5)}) {
        SCOPED_TRACE(mesh.name);
        const auto [levels, history] = split_three_times(mesh);
        for (int level = 2; level <= 3; ++level) {
            SCOPED_TRACE("level " + std::to_string(level));
            const Topology& t = levels[std::size_t(level)];
            const std::vector<int> to_level(history.begin(), history.begin() + level + 1);
            const std::vector<int> to_parent(history.begin(), history.begin() + level);
            const VertexNeighbourhood parent(levels[std::size_t(level) - 1].num_vertices,
                                             levels[std::size_t(level) - 2], &to_parent, &levels[0]);
            const VertexNeighbourhood derived(t.num_vertices, parent, &to_level, &levels[0]);
            ASSERT_EQ(derived.num_edges(), t.num_edges());
            ASSERT_EQ(derived.num_faces(), t.num_faces());
            EXPECT_EQ(derived.max_valence(), t.max_valence);
            EXPECT_EQ(derived.max_edge_face_count(), t.max_edge_face_count);
            for (Index f = 0; f < t.num_faces(); ++f) {
                Index corners[3], edges[3], alone[2][3];
                derived.face(f, corners, edges);
                derived.face_vertices(f, alone[0]), derived.face_edges(f, alone[1]);
                for (int k = 0; k < 3; ++k) {
                    ASSERT_EQ(corners[k], t.face_vertices[3 * f + k]) << "face " << f;
                    ASSERT_EQ(edges[k], t.face_edges[3 * f + k]) << "face " << f;
                    ASSERT_EQ(alone[0][k], corners[k]) << "face " << f;
                    ASSERT_EQ(alone[1][k], edges[k]) << "face " << f;
                }
            }
            for (Index e = 0; e < t.num_edges(); ++e) {
                Index ends[2], c, d;
                derived.edge_ends(e, ends);
                derived.wings(e, c, d);
                ASSERT_EQ(ends[0], t.edge_vertices[2 * e]) << "edge " << e;
                ASSERT_EQ(ends[1], t.edge_vertices[2 * e + 1]) << "edge " << e;
                ASSERT_EQ(c, t.edge_wing_c[e]) << "edge " << e;
                ASSERT_EQ(d, t.edge_wing_d[e]) << "edge " << e;
                ASSERT_EQ(derived.edge_face_count(e), t.edge_face_count(e)) << "edge " << e;
                std::vector<Index> faces;
                derived.for_each_edge_face(e, [&faces](Index f) { faces.push_back(f); });
                EXPECT_EQ(faces, std::vector<Index>(t.edge_faces.begin() + t.edge_face_offsets[e],
                                                    t.edge_faces.begin() + t.edge_face_offsets[e + 1]))
                    << "edge " << e;
            }
            const VertexNeighbourhood built(t, nullptr, &to_level, &levels[0]);
            std::vector<Index> a, b;
            std::vector<FanCorner> fan, built_fan;
            for (Index v = 0; v < t.num_vertices; ++v) {
                derived.edges(v, a), built.edges(v, b);
                ASSERT_EQ(a, b) << "vertex " << v;
                derived.fan(v, fan), built.fan(v, built_fan);
                ASSERT_EQ(fan, built_fan) << "vertex " << v;
                // The stored level's fan is its arrays': every corner at v once, in order, with its face.
                std::vector<Index> corners;
                for (Index c = 0; c < 3 * t.num_faces(); ++c)
                    if (t.face_vertices[c] == v) corners.push_back(c);
                ASSERT_EQ(built_fan.size(), corners.size()) << "vertex " << v;
                for (std::size_t i = 0; i < corners.size(); ++i) {
                    const Index c = corners[i], face = c - c % 3, k = c % 3, before = face + (k + 2) % 3;
                    const FanCorner expected{c,
                                             t.face_vertices[face + (k + 1) % 3],
                                             t.face_vertices[before],
                                             t.face_edges[c],
                                             t.face_edges[before],
                                             t.edge_vertices[2 * t.face_edges[c]] == v,
                                             t.edge_vertices[2 * t.face_edges[before]] == v};
                    ASSERT_EQ(built_fan[i], expected) << "vertex " << v << ", corner " << c;
                }
                // The pairs a plan asks about: a midpoint's two halves, and any two edges of two faces at a base
                // vertex.
                const Index first = t.vertex_edge_offsets[v], count = t.valence(v);
                for (Index j = 0; j < count; ++j)
                    for (Index k = 0; k < count; ++k) {
                        const Index from = t.vertex_edges[first + j], to = t.vertex_edges[first + k];
                        const bool halves = v >= history[0] && j < 2 && k < 2;
                        if (from == to || (!halves && v >= history[0]) || t.edge_face_count(from) != 2 ||
                            t.edge_face_count(to) != 2)
                            continue;
                        ASSERT_EQ(derived.faces_between(v, from, to), loopsub::detail::faces_between(t, v, from, to))
                            << "vertex " << v << ", edges " << from << " and " << to;
                    }
            }
        }
    }
}

// The child's rings ordered from the numbering: around every vertex left a disk, each child triangle (v, a, b) has b
// right after a (cyclically); a vertex on a boundary or a non-manifold edge or vertex is set apart.
TEST(Topology, ChildRingsOrderedCounterClockwise) {
    using namespace loopsub::testing;
    using loopsub::detail::Index;
    for (const TestMesh& mesh : {icosphere(2), grid(4, 3), open_fan(7), fin_on_grid(), bowtie(5)}) {
        SCOPED_TRACE(mesh.name);
        Topology level =
            loopsub::detail::build_base_topology(mesh.triangles.data(), mesh.num_triangles(), mesh.num_vertices());
        for (int split = 1; split <= 2; ++split) {
            Topology child = loopsub::detail::refine_topology(level, loopsub::detail::Refined::Full, 1);
            std::vector<std::uint8_t> apart(std::size_t(child.num_vertices), 0);
            std::vector<Index> ring(child.vertex_vertices.size());
            // A vertex set apart beforehand (an old vertex, a midpoint) keeps refine_topology's order.
            const Index kept[2] = {0, level.num_vertices};
            for (Index v : kept) apart[v] = 1;
            const int half = child.num_vertices / 2;  // in two parts, as a plan's threads write them
            loopsub::detail::write_ordered_child_rings(level, 0, half, apart.data(), ring.data());
            loopsub::detail::write_ordered_child_rings(level, half, child.num_vertices, apart.data(),
                                                       ring.data() + child.vertex_edge_offsets[half]);
            int disks = 0;
            for (Index v = 0; v < child.num_vertices; ++v) {
                const Index first = child.vertex_edge_offsets[v], last = child.vertex_edge_offsets[v + 1];
                // The same neighbours, in some order.
                std::vector<Index> before(child.vertex_vertices.begin() + first, child.vertex_vertices.begin() + last);
                std::vector<Index> after(ring.begin() + first, ring.begin() + last);
                std::sort(before.begin(), before.end()), std::sort(after.begin(), after.end());
                ASSERT_EQ(before, after) << "vertex " << v;
                disks += !apart[v];
            }
            for (Index v : kept)
                EXPECT_TRUE(std::equal(ring.begin() + child.vertex_edge_offsets[v],
                                       ring.begin() + child.vertex_edge_offsets[v + 1],
                                       child.vertex_vertices.begin() + child.vertex_edge_offsets[v]))
                    << "vertex " << v << " set apart";
            for (std::size_t c = 0; c < child.face_vertices.size(); ++c) {
                const std::size_t face = c - c % 3;
                const Index v = child.face_vertices[c], a = child.face_vertices[face + (c + 1) % 3],
                            b = child.face_vertices[face + (c + 2) % 3];
                // A vertex of a boundary edge can be no disk.
                if (apart[v]) continue;
                const Index first = child.vertex_edge_offsets[v], n = child.vertex_edge_offsets[v + 1] - first;
                const Index at =
                    Index(std::find(ring.begin() + first, ring.begin() + first + n, a) - (ring.begin() + first));
                ASSERT_LT(at, n) << "corner " << c;
                ASSERT_EQ(ring[first + (at + 1) % n], b) << "split " << split << ", corner " << c << " of vertex " << v;
            }
            for (Index e = 0; e < child.num_edges(); ++e)
                if (child.edge_face_count(e) == 1) {
                    EXPECT_TRUE(apart[child.edge_vertices[2 * e]] && apart[child.edge_vertices[2 * e + 1]])
                        << "boundary edge " << e;
                }
            EXPECT_GT(disks, 0);
            level = std::move(child);
        }
    }
}

// The grandchild's rings read two splits on (write_ordered_grandchild_rings, what a limit plan of a manifold surface
// reads instead of building the level before the last) are write_ordered_child_rings' of the child built in full,
// entry for entry and offset for offset, from the base and from split levels: on closed surfaces of several valences,
// jittered or not, and open ones (a boundary's vertices are no disks and keep write_child_rings' order there too).
TEST(Topology, GrandchildRingsAreTheChildsOrderedRings) {
    using namespace loopsub::testing;
    TestMesh sphere = icosphere(1);
    jitter(sphere, 7, 0.05f);
    TestMesh pillow;  // two triangles on the same three vertices, facing apart: closed, every fan two faces
    pillow.name = "pillow";
    pillow.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    pillow.triangles = {0, 1, 2, 0, 2, 1};
    for (const TestMesh& mesh : {icosahedron(), sphere, torus(5, 7), bipyramid(9), cube(), bipyramid(3), pillow,
                                 grid(4, 3), open_cylinder(7, 2), hemisphere(1), open_fan(5)}) {
        SCOPED_TRACE(mesh.name);
        Topology grandparent =
            loopsub::detail::build_base_topology(mesh.triangles.data(), mesh.num_triangles(), mesh.num_vertices());
        for (int split = 0; split <= 1; ++split) {
            SCOPED_TRACE(split);
            const Topology parent = loopsub::detail::refine_topology(grandparent, loopsub::detail::Refined::Full, 1);
            const Index count = parent.num_vertices + parent.num_edges();
            std::vector<std::uint8_t> apart(std::size_t(count), 0);
            std::vector<Index> expected(std::size_t(loopsub::detail::child_ring_offset(parent, count)));
            loopsub::detail::write_ordered_child_rings(parent, 0, count, apart.data(), expected.data());
            ASSERT_LE(grandparent.max_edge_face_count, 2);
            std::vector<Index> sides(2 * loopsub::detail::kEdgeSideSize * std::size_t(grandparent.num_edges()), -1),
                halves(grandparent.face_edges.size()), next_at(2 * std::size_t(grandparent.num_edges()), -1);
            loopsub::detail::write_grandparent_sides(grandparent, 0, grandparent.num_faces(), sides.data(),
                                                     halves.data(), next_at.data());
            const loopsub::detail::Grandparent g{grandparent.num_vertices,
                                                 grandparent.num_edges(),
                                                 grandparent.num_faces(),
                                                 grandparent.edge_vertices.data(),
                                                 sides.data(),
                                                 halves.data()};
            const Index begin = grandparent.num_vertices, end = count;
            const Index first = loopsub::detail::child_ring_offset(parent, begin);
            // In chunks, as a frame writes them, which begin and end inside a pair of halves or a face's three.
            std::vector<Index> ring(6 * std::size_t(end - begin)), offsets(8);
            std::size_t written = 0;
            for (Index chunk = begin; chunk < end; chunk += 7) {
                const Index last = std::min(end, chunk + 7);
                loopsub::detail::write_ordered_grandchild_rings(g, chunk, last, offsets.data(), ring.data() + written);
                for (Index v = chunk; v < last; ++v)
                    ASSERT_EQ(Index(written) + offsets[std::size_t(v - chunk)],
                              loopsub::detail::child_ring_offset(parent, v) - first)
                        << "vertex " << v;
                written += std::size_t(offsets[std::size_t(last - chunk)]);
            }
            ASSERT_EQ(written, expected.size() - std::size_t(first));
            for (std::size_t k = 0; k < written; ++k)
                ASSERT_EQ(ring[k], expected[std::size_t(first) + k]) << "entry " << k;
            // The old vertices: the halves to their neighbours, which are the grandchild's midpoints of them.
            std::vector<Index> old(static_cast<std::size_t>(first));
            loopsub::detail::write_ordered_old_vertex_halves(grandparent, next_at.data(), 0, grandparent.num_vertices,
                                                             parent.num_vertices, old.data());
            for (std::size_t k = 0; k < old.size(); ++k) ASSERT_EQ(old[k], expected[k]) << "entry " << k;
            grandparent = loopsub::detail::refine_topology(grandparent, loopsub::detail::Refined::Full, 1);
        }
    }
}

// The mesh split three times (Refined::Full): per level past the base, `check` gets the levels so far, their vertex
// counts, and the level's VertexNeighbourhood on the level itself and derived from its parent, both given the base
// level for the walks around its vertices where `with_base`.
template <typename Check>
void for_each_split(const loopsub::testing::TestMesh& mesh, bool with_base, const Check& check) {
    const auto [all_levels, all_history] = split_three_times(mesh);
    for (int level = 1; level <= 3; ++level) {
        const std::vector<Topology> levels(all_levels.begin(), all_levels.begin() + level + 1);
        const std::vector<int> history(all_history.begin(), all_history.begin() + level + 1);
        const Topology* base = with_base ? &levels[0] : nullptr;
        const loopsub::detail::VertexNeighbourhood built(levels.back(), nullptr, &history, base);
        const loopsub::detail::VertexNeighbourhood derived(history.back(), levels[level - 1], &history, base);
        check(level, levels, history, built, derived);
    }
}

// A vertex made on an edge by a split sees three faces between the edge's halves, and between their descendants at it
// in later levels: VertexNeighbourhood answers that from the levels' vertex counts, without the walk around the
// vertex it must agree with, on built levels and on a level known through its parent.
TEST(Topology, FacesBetweenHalvesOfAVertexsEdgeWithoutAWalk) {
    using namespace loopsub::testing;
    for (const TestMesh& mesh : {icosphere(1), grid(4, 3), fin_on_grid(), open_cylinder(5, 2)}) {
        SCOPED_TRACE(mesh.name);
        for_each_split(
            mesh, false,
            [](int level, const std::vector<Topology>& levels, const std::vector<int>& history,
               const loopsub::detail::VertexNeighbourhood& built, const loopsub::detail::VertexNeighbourhood& derived) {
                const Topology& t = levels.back();
                int checked = 0;
                for (Index v = history[0]; v < t.num_vertices; ++v) {
                    // v is the midpoint of edge e of level `made - 1`; follow e's halves at v down to this level.
                    int made = 1;
                    while (v >= history[made]) ++made;
                    const Index e = v - history[made - 1];
                    Index halves[2] = {2 * e, 2 * e + 1};
                    for (int l = made; l < level; ++l)
                        for (Index& x : halves) x = levels[l].edge_vertices[2 * x] == v ? 2 * x : 2 * x + 1;
                    const int walked = loopsub::detail::faces_between(t, v, halves[0], halves[1]);
                    ASSERT_EQ(built.faces_between(v, halves[0], halves[1]), walked)
                        << "level " << level << ", vertex " << v;
                    ASSERT_EQ(derived.faces_between(v, halves[0], halves[1]), walked)
                        << "level " << level << ", vertex " << v;
                    ++checked;
                }
                EXPECT_GT(checked, 0);
            });
    }
}

// A level known through its parent gives each face's corners and edges as the level itself holds them (the limit plan
// reads the faces at its vertices next to tags so, not from the level's own far-apart arrays).
TEST(Topology, DerivedFacesAreTheLevels) {
    using namespace loopsub::testing;
    for (const TestMesh& mesh : {icosphere(1), grid(4, 3), fin_on_grid(), open_cylinder(5, 2), bowtie(5)}) {
        SCOPED_TRACE(mesh.name);
        for_each_split(
            mesh, false,
            [](int level, const std::vector<Topology>& levels, const std::vector<int>&,
               const loopsub::detail::VertexNeighbourhood& built, const loopsub::detail::VertexNeighbourhood& derived) {
                const Topology& t = levels.back();
                for (Index f = 0; f < t.num_faces(); ++f) {
                    Index corners[2][3], edges[2][3];
                    built.face_vertices(f, corners[0]), derived.face_vertices(f, corners[1]);
                    built.face_edges(f, edges[0]), derived.face_edges(f, edges[1]);
                    for (int k = 0; k < 3; ++k) {
                        ASSERT_EQ(corners[0][k], t.face_vertices[3 * f + k]) << "level " << level;
                        ASSERT_EQ(corners[1][k], t.face_vertices[3 * f + k]) << "level " << level;
                        ASSERT_EQ(edges[1][k], edges[0][k]) << "level " << level;
                    }
                }
            });
    }
}

// A base vertex keeps its fan through every split: VertexNeighbourhood, given the base, counts the faces between two of
// its edges on the base, and must agree with the walk around the vertex on the level itself, built or derived.
TEST(Topology, FacesBetweenAtABaseVertexAreTheBases) {
    using namespace loopsub::testing;
    for (const TestMesh& mesh : {icosphere(1), grid(4, 3), fin_on_grid(), open_cylinder(5, 2), bowtie(5)}) {
        SCOPED_TRACE(mesh.name);
        int checked = 0;
        for_each_split(mesh, true,
                       [&checked](int level, const std::vector<Topology>& levels, const std::vector<int>& history,
                                  const loopsub::detail::VertexNeighbourhood& built,
                                  const loopsub::detail::VertexNeighbourhood& derived) {
                           const Topology& t = levels.back();
                           for (Index v = 0; v < history[0]; ++v)
                               for (Index j = t.vertex_edge_offsets[v]; j < t.vertex_edge_offsets[v + 1]; ++j)
                                   for (Index k = t.vertex_edge_offsets[v]; k < t.vertex_edge_offsets[v + 1]; ++k) {
                                       const Index from = t.vertex_edges[j], to = t.vertex_edges[k];
                                       if (from == to || t.edge_face_count(from) != 2 || t.edge_face_count(to) != 2)
                                           continue;
                                       const int walked = loopsub::detail::faces_between(t, v, from, to);
                                       ASSERT_EQ(built.faces_between(v, from, to), walked)
                                           << "level " << level << ", vertex " << v;
                                       ASSERT_EQ(derived.faces_between(v, from, to), walked)
                                           << "level " << level << ", vertex " << v;
                                       ++checked;
                                   }
                       });
        EXPECT_GT(checked, 0);
    }
}

}  // namespace
