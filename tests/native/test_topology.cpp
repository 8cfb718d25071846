// The connectivity a level carries for passes in face order (Topology::face_edge_places) and what those passes
// write (the halves' wings): each checked against the same thing found by looking faces up edge by edge, on closed, open and non-manifold
// meshes through three refinements, split between threads or not.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "mesh_gen.h"
#include "topology.h"

namespace {

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
    for (std::size_t c = 0; c < expected.size(); ++c) ASSERT_EQ(int(t.face_edge_places[c]), int(expected[c])) << "corner " << c;

    // The halves' wings: in edge order (child_edges, what derived tables use) and in face order, in two parts.
    const int halves = 2 * t.num_edges();
    std::vector<Index> ends(2 * std::size_t(halves)), c(halves), d(halves), face_c(halves, -1), face_d(halves, -1);
    loopsub::detail::child_edges(t, 0, halves, ends.data(), c.data(), d.data());
    const int faces_split = t.num_faces() / 3, edges_split = 2 * t.num_edges() / 3;
    loopsub::detail::write_half_wings(t, 0, faces_split, 0, edges_split, face_c.data(), face_d.data());
    loopsub::detail::write_half_wings(t, faces_split, t.num_faces(), edges_split, t.num_edges(), face_c.data(), face_d.data());
    EXPECT_EQ(face_c, c);
    EXPECT_EQ(face_d, d);
    std::vector<Index> half_ends(ends.size(), -1);
    loopsub::detail::write_half_ends(t, 0, t.num_edges(), half_ends.data());
    EXPECT_EQ(half_ends, ends);
}

TEST(Topology, FaceOrderAgreesWithLookups) {
    using namespace loopsub::testing;
    const std::pair<const char*, TestMesh> meshes[] = {{"icosphere", icosphere(2)},  {"grid", grid(5, 4)},
                                                       {"fin on grid", fin_on_grid()}, {"bowtie", bowtie(5)},
                                                       {"open fan", open_fan(5)},      {"open cylinder", open_cylinder(6, 3)}};
    for (const auto& [name, mesh] : meshes) {
        Topology t = loopsub::detail::build_base_topology(mesh.triangles.data(), mesh.num_triangles(), mesh.num_vertices());
        expect_face_order_agrees(t, std::string(name) + ", base");
        for (int level = 1; level <= 3; ++level) {
            t = loopsub::detail::refine_topology(t, loopsub::detail::Refined::Full, level % 2 + 1);
            expect_face_order_agrees(t, std::string(name) + ", level " + std::to_string(level));
        }
    }
}

}  // namespace
