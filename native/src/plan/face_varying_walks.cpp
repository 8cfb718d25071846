// The walks around a face-varying value through the layer's current level (its own arrays, or its parent's where it
// is not built): its edges, those inside its span, its seam neighbours, its neighbour on a given vertex.
#include <vector>

#include "plan/face_varying.h"

namespace loopsub::detail {

const std::vector<Index>& FaceVaryingBuilder::edges_at(Index x, Walk& walk) const {
    layer().edges(x, walk.edges);
    return walk.edges;
}

void FaceVaryingBuilder::inner_edges(Index x, std::vector<Index>& edges, Walk& walk) const {
    const VertexNeighbourhood layer = this->layer();
    edges.clear();
    for (Index e : edges_at(x, walk))
        if (layer.edge_face_count(e) == 2) edges.push_back(edge_of_[e]);
}

bool FaceVaryingBuilder::seam_ends(Index x, Index ends[2], Walk& walk) const {
    const VertexNeighbourhood layer = this->layer();
    int found = 0;
    for (Index e : edges_at(x, walk)) {
        if (layer.edge_face_count(e) != 1) continue;
        if (found < 2) ends[found] = layer.other_end(e, x);
        ++found;
    }
    return found == 2;
}

SpecialVertex FaceVaryingBuilder::on_layer(Index x, const SpecialVertex& m, Walk& walk) const {
    const Index a = m.w_crease_a != 0.0f ? neighbour_at_vertex(x, m.crease_a, walk) : x;
    const Index b = m.w_crease_b != 0.0f ? neighbour_at_vertex(x, m.crease_b, walk) : x;
    return {x, a < 0 ? x : a, b < 0 ? x : b, m.w_self, m.w_ring, m.w_crease_a, m.w_crease_b};
}

Index FaceVaryingBuilder::neighbour_at_vertex(Index x, Index vertex, Walk& walk) const {
    const VertexNeighbourhood layer = this->layer();
    for (Index e : edges_at(x, walk)) {
        const Index other = layer.other_end(e, x);
        if (vertex_of_[other] == vertex) return other;
    }
    return -1;
}

}  // namespace loopsub::detail
