// Checks of what a caller hands the core: the mesh and tags (once, when a plan is built) and the values evaluated
// every frame. Each failure is an InputError that says what and where, and carries it as an InputProblem. The checks
// themselves are base/input_checks.h's and, for those that need the mesh's edges, the templates here: a plan throws
// the first problem they report, diagnose() (diagnose.cpp) lists them all.
#pragma once

#include <algorithm>
#include <cstddef>

#include "base/input_checks.h"
#include "loopsub/loopsub.h"
#include "topology/topology.h"

namespace loopsub::detail {

void validate_options(const Options& options);  // levels, threads, crease threshold
// What any reading of a mesh needs: no negative count, no null array of a positive count (plain InputErrors: the
// call is at fault, not the data).
void validate_view(const MeshView& mesh);
// validate_view, then check_mesh, throwing the first problem.
void validate_mesh(const MeshView& mesh);

// Each crease tag's edges: tag(k, e) for crease k on edge e (every edge of `t`, the base level of `mesh`, between
// its two vertices: two where the mesh's triangle_edges give them), report(NotAnEdge) for one that names no edge.
template <typename Report, typename Tag>
bool check_crease_edges(const Topology& t, const MeshView& mesh, Report&& report, Tag&& tag) {
    for (int k = 0; k < mesh.num_crease_edges; ++k) {
        const Index a = mesh.crease_edges[2 * k], b = mesh.crease_edges[2 * k + 1];
        bool found = false;
        if (a != b)
            for (Index i = t.vertex_edge_offsets[a]; i < t.vertex_edge_offsets[a + 1]; ++i)
                if (t.other_end(t.vertex_edges[i], a) == b) tag(k, t.vertex_edges[i]), found = true;
        if (found) continue;
        Problem p;
        p.kind = Kind::NotAnEdge, p.element = Element::CreaseEdge, p.index = k, p.refers_to = a, p.other = b;
        if (!report(p)) return false;
    }
    return true;
}

// The notes RunsTheSameWay, one per edge that two of its faces run along the same way.
template <typename Report>
bool check_windings(const Topology& t, Report&& report) {
    auto note = [&](Index face, int side, Index other) {
        Problem p;
        p.kind = Kind::RunsTheSameWay, p.element = Element::Triangle, p.index = face, p.corner = side, p.other = other;
        return report(p);
    };
    // An edge's first face runs along it from its first end; an edge of two faces whose second face does so too
    // (place byte 0b11, as non_manifold_edges reads it) is one. Edges of more faces are counted per direction.
    const std::size_t corners = t.face_edge_places.size();
    for (std::size_t c = 0; c < corners; ++c) {
        const Index e = t.face_edges[c];
        if (t.face_edge_places[c] == (1 << 1 | 1) && t.edge_face_count(e) == 2 &&
            !note(Index(c / 3), int(c % 3), t.edge_faces[t.edge_face_offsets[e]]))
            return false;
    }
    for (int e = 0; e < (t.max_edge_face_count > 2 ? t.num_edges() : 0); ++e) {
        if (t.edge_face_count(e) <= 2) continue;
        const Index a = t.edge_vertices[2 * e];
        Index forward[2] = {-1, -1}, backward[2] = {-1, -1};  // the first two faces each way
        int sides[2][2] = {};
        for (Index k = t.edge_face_offsets[e]; k < t.edge_face_offsets[e + 1]; ++k) {
            const Index f = t.edge_faces[k];
            const int side =
                int(std::find(&t.face_edges[3 * std::size_t(f)], &t.face_edges[3 * std::size_t(f)] + 3, e) -
                    &t.face_edges[3 * std::size_t(f)]);
            Index* way = t.face_vertices[3 * std::size_t(f) + std::size_t(side)] == a ? forward : backward;
            const int slot = way[0] < 0 ? 0 : way[1] < 0 ? 1 : 2;
            if (slot < 2) way[slot] = f, sides[way == forward ? 0 : 1][slot] = side;
        }
        if (forward[1] >= 0 && !note(forward[1], sides[0][1], forward[0])) return false;
        if (forward[1] < 0 && backward[1] >= 0 && !note(backward[1], sides[1][1], backward[0])) return false;
    }
    return true;
}

// Per-vertex values (or a face-varying layer's, element FaceVaryingValue of `layer`): finite, and within +-largest
// (the bound that keeps a kernel's sums finite).
void validate_vertex_values(ChannelsView<const float> in, int num_vertices, float largest, int summed_terms,
                            Element element = Element::Vertex, int layer = -1);

// Face-varying values per corner: finite.
void validate_face_varying_values(const float* in, std::size_t num_triangles, int num_channels);

}  // namespace loopsub::detail
