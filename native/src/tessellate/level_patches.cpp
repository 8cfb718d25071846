#include "tessellate/level_patches.h"

#include <algorithm>

namespace loopsub::detail {

namespace {

bool infinitely_sharp(float sharpness) { return sharpness >= kInfiniteSharpness; }

}  // namespace

std::vector<std::uint64_t> sorted_edge_keys(const std::int32_t* triangles, int num_triangles) {
    std::vector<std::uint64_t> keys;
    keys.reserve(3 * std::size_t(num_triangles));
    for (std::size_t c = 0; c < 3 * std::size_t(num_triangles); ++c)
        keys.push_back(edge_key(triangles[c], triangles[c - c % 3 + (c + 1) % 3]));
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    return keys;
}

SortedEdges sorted_edges(const std::int32_t* triangles, int num_triangles) {
    const std::size_t corners = 3 * std::size_t(num_triangles);
    std::vector<std::pair<std::uint64_t, std::int32_t>> by_key(corners);
    for (std::size_t c = 0; c < corners; ++c)
        by_key[c] = {edge_key(triangles[c], triangles[c - c % 3 + (c + 1) % 3]), std::int32_t(c)};
    std::sort(by_key.begin(), by_key.end());
    SortedEdges edges;
    edges.corner_edges.resize(corners);
    for (std::size_t i = 0; i < corners; ++i) {
        if (i == 0 || by_key[i].first != by_key[i - 1].first) edges.keys.push_back(by_key[i].first);
        edges.corner_edges[std::size_t(by_key[i].second)] = std::int32_t(edges.keys.size() - 1);
    }
    return edges;
}

LevelPatches::LevelPatches(const Plan& plan, const std::int32_t* triangles_given, int num_triangles_given)
    : plan_(plan),
      triangles_(triangles_given != nullptr ? triangles_given : plan.output_triangles()),
      has_edges_(triangles_given == nullptr && plan.levels() > 0),
      types_(plan.level_vertex_types(plan.levels()).data()) {
    const int num_triangles = triangles_given != nullptr ? num_triangles_given : plan.num_output_triangles(),
              num_vertices = plan.num_output_vertices();
    const std::int32_t* triangles = triangles_;
    const VertexType* types = types_;
    const std::vector<std::int32_t>& sharp_edges = plan.output_sharp_edges();
    const std::vector<std::int32_t>& sharp_vertices = plan.output_corner_vertices();
    const float* sharp_edge_sharpness = plan.output_sharp_edge_sharpness().data();
    const int num_sharp_edges = int(sharp_edges.size() / 2), num_sharp_vertices = int(sharp_vertices.size());
    offsets_.assign(std::size_t(num_vertices) + 1, 0);
    const std::size_t num_corners = 3 * std::size_t(num_triangles);
    for (std::size_t c = 0; c < num_corners; ++c) ++offsets_[std::size_t(triangles[c]) + 1];
    for (std::size_t v = 0; v < std::size_t(num_vertices); ++v) offsets_[v + 1] += offsets_[v];
    corners_.resize(num_corners);
    std::vector<std::int32_t> cursor(offsets_.begin(), offsets_.end() - 1);
    for (std::size_t c = 0; c < num_corners; ++c) corners_[std::size_t(cursor[std::size_t(triangles[c])]++)] = int(c);
    sharp_.reserve(std::size_t(num_sharp_edges));
    for (int e = 0; e < num_sharp_edges; ++e)
        sharp_[edge_key(sharp_edges[2 * e], sharp_edges[2 * e + 1])] = sharp_edge_sharpness[e];
    has_sharpness_.assign(std::size_t(num_vertices), false);
    for (int k = 0; k < num_sharp_vertices; ++k) has_sharpness_[std::size_t(sharp_vertices[k])] = true;
    smooth_.assign(std::size_t(num_vertices), true);
    for (int e = 0; e < 2 * num_sharp_edges; ++e) smooth_[std::size_t(sharp_edges[e])] = false;
    for (int v = 0; v < num_vertices; ++v)
        if (types[v] != VertexType::Smooth || has_sharpness_[std::size_t(v)] || corners_end(v) - corners_begin(v) != 6)
            smooth_[std::size_t(v)] = false;
    corner_rank_.assign(num_corners, 0);
    ordered_.assign(std::size_t(num_vertices), Order::NotYet);
}

float LevelPatches::sharpness(int a, int b) const {
    const auto found = sharp_.find(edge_key(a, b));
    return found == sharp_.end() ? 0.0f : found->second;
}

const std::int32_t* LevelPatches::triangle_edges() const {
    if (!has_edges_) return nullptr;
    if (triangle_edges_.empty()) {
        std::vector<std::int32_t> edge_vertices(2 * std::size_t(plan_.num_output_edges()));
        triangle_edges_.resize(3 * std::size_t(plan_.num_output_triangles()));
        plan_.output_edges(edge_vertices.data(), triangle_edges_.data());
    }
    return triangle_edges_.data();
}

int LevelPatches::next_corner(int corner, bool counter_clockwise) const {
    const int f = corner / 3, i = corner % 3, v = triangles_[corner];
    // Counter-clockwise the next face shares the edge to the corner's previous vertex, and has it next.
    const int shared = triangles_[3 * f + (counter_clockwise ? (i + 2) % 3 : (i + 1) % 3)];
    int found = -1, candidates = 0;
    for (const std::int32_t* c = corners_begin(v); c != corners_end(v); ++c) {
        const int g = *c / 3, j = *c % 3;
        if (triangles_[3 * g + (counter_clockwise ? (j + 1) % 3 : (j + 2) % 3)] != shared) continue;
        found = *c, ++candidates;
    }
    if (candidates < 2) return found;
    // Several faces run along v and `shared` that way: a non-manifold edge, or two edges with these ends (input
    // levels have none); the face across this edge by the split's numbering, if one is.
    const std::int32_t* edges = triangle_edges();
    if (!edges) return -1;
    // The edge from the corner's previous vertex to it (counter-clockwise), or from it to its next.
    const std::int32_t edge = edges[3 * std::size_t(f) + std::size_t(counter_clockwise ? (i + 2) % 3 : i)];
    found = -1, candidates = 0;
    for (const std::int32_t* c = corners_begin(v); c != corners_end(v); ++c) {
        const int g = *c / 3, j = *c % 3;
        if (g == f || triangles_[3 * g + (counter_clockwise ? (j + 1) % 3 : (j + 2) % 3)] != shared) continue;
        if (edges[3 * std::size_t(g) + std::size_t(counter_clockwise ? j : (j + 2) % 3)] != edge) continue;
        found = *c, ++candidates;
    }
    return candidates == 1 ? found : -1;
}

// ring: the six neighbours counter-clockwise from the corner's next vertex. The six faces around a vertex share its
// walk: the first puts the vertex's corners in counter-clockwise order (only where a face asks: a plan's level may be
// far larger than what is sampled of it).
bool LevelPatches::smooth_corner(int corner, std::int32_t ring[6]) const {
    const int v = triangles_[corner];
    if (!smooth_[std::size_t(v)]) return false;
    Order& order = ordered_[std::size_t(v)];
    if (order == Order::NotYet) {
        std::int32_t ordered[6];
        int c = corner, k = 0;
        for (; k < 6 && c >= 0 && (k == 0 || c != corner); ++k) ordered[k] = c, c = next_corner(c, true);
        order = k == 6 && c == corner ? Order::CounterClockwise : Order::NoDisk;  // not a fan of three, twice
        if (order == Order::CounterClockwise)
            for (k = 0; k < 6; ++k)
                corners_[std::size_t(offsets_[std::size_t(v)] + k)] = ordered[k],
                                                                corner_rank_[std::size_t(ordered[k])] = std::uint8_t(k);
    }
    if (order == Order::NoDisk) return false;
    const std::int32_t* around = corners_begin(v);
    const int rank = corner_rank_[std::size_t(corner)];
    for (int k = 0; k < 6; ++k) {
        const int c = around[(rank + k) % 6];
        ring[k] = triangles_[3 * (c / 3) + (c % 3 + 1) % 3];
    }
    return true;
}

// fan: the neighbours met going round from the corner's face's edge to the crease (counter-clockwise from its next
// vertex, or clockwise from its previous one) through three faces; the first and last edge infinitely sharp.
bool LevelPatches::crease_corner(int corner, bool counter_clockwise, std::int32_t fan[4]) const {
    const int v = triangles_[corner];
    if (types_[v] != VertexType::RegularCrease || has_sharpness_[std::size_t(v)]) return false;
    const int ahead = counter_clockwise ? 2 : 1;  // the vertex the walk moves to within a face
    int c = corner;
    fan[0] = triangles_[3 * (c / 3) + (c % 3 + 3 - ahead) % 3];
    for (int k = 1; k < 4; ++k) {
        if (k > 1 && (c = next_corner(c, counter_clockwise)) < 0) return false;
        fan[k] = triangles_[3 * (c / 3) + (c % 3 + ahead) % 3];
    }
    return infinitely_sharp(sharpness(v, fan[0])) && sharpness(v, fan[1]) == 0.0f && sharpness(v, fan[2]) == 0.0f &&
           infinitely_sharp(sharpness(v, fan[3]));
}

// A regular crease vertex at `corner` whose face is the middle one of its three on this side: the walk back (clockwise)
// from the face's previous vertex to the crease, and on (counter-clockwise) from its next one; both end on an
// infinitely sharp edge, the face's own edges at the vertex are smooth.
bool LevelPatches::crease_vertex(int corner, std::int32_t back[4], std::int32_t on[4]) const {
    const int v = triangles_[corner];
    if (types_[v] != VertexType::RegularCrease || has_sharpness_[std::size_t(v)]) return false;
    const int f = corner / 3, i = corner % 3;
    const std::int32_t next = triangles_[3 * f + (i + 1) % 3], previous = triangles_[3 * f + (i + 2) % 3];
    if (sharpness(v, next) != 0.0f || sharpness(v, previous) != 0.0f) return false;
    const int before = next_corner(corner, false), after = next_corner(corner, true);
    if (before < 0 || after < 0) return false;
    back[0] = next, back[1] = triangles_[3 * (before / 3) + (before % 3 + 1) % 3];
    on[0] = previous, on[1] = triangles_[3 * (after / 3) + (after % 3 + 2) % 3];
    return infinitely_sharp(sharpness(v, back[1])) && infinitely_sharp(sharpness(v, on[1]));
}

bool LevelPatches::find_patch(int face, Patch& out) const {
    const std::int32_t* f = triangles_ + 3 * face;
    std::int32_t ring[3][6];
    if (smooth_corner(3 * face, ring[0]) && smooth_corner(3 * face + 1, ring[1]) &&
        smooth_corner(3 * face + 2, ring[2]) && ring[0][5] == ring[1][2] && ring[1][5] == ring[2][2] &&
        ring[2][5] == ring[0][2]) {
        const std::int32_t gathered[kBoxSplinePoints] = {ring[0][4], ring[0][3], ring[0][5], f[0],
                                                         ring[0][2], ring[1][3], f[1],       f[2],
                                                         ring[2][4], ring[1][4], ring[1][5], ring[2][3]};
        std::copy(gathered, gathered + kBoxSplinePoints, out.points);
        out.rotation = 0, out.shape = PatchShape::Smooth;
        return true;
    }
    for (int j = 0; j < 3; ++j) {  // a crease on the face's edge j, from f[j] to f[j + 1]
        const int r = (j + 2) % 3;
        std::int32_t fan1[4], fan2[4];
        if (!infinitely_sharp(sharpness(f[j], f[(j + 1) % 3])) || !smooth_corner(3 * face + r, ring[0]) ||
            !crease_corner(3 * face + j, true, fan1) || !crease_corner(3 * face + (j + 1) % 3, false, fan2) ||
            fan1[2] != ring[0][5] || fan2[2] != ring[0][2])
            continue;
        const std::int32_t gathered[kBoxSplinePoints] = {
            ring[0][4], ring[0][3], ring[0][5], f[r], ring[0][2], fan1[3], f[j], f[(j + 1) % 3], fan2[3], -1, -1, -1};
        std::copy(gathered, gathered + kBoxSplinePoints, out.points);
        out.rotation = r, out.shape = PatchShape::CreaseEdge;
        return true;
    }
    for (int r = 0; r < 3; ++r) {  // a crease through corner r, whose middle face on this side f is
        const int c0 = 3 * face + r, c1 = 3 * face + (r + 1) % 3, c2 = 3 * face + (r + 2) % 3;
        std::int32_t fan_back[4], fan_on[4];
        if (!smooth_corner(c1, ring[1]) || !smooth_corner(c2, ring[2]) || ring[1][5] != ring[2][2] ||
            !crease_vertex(c0, fan_back, fan_on) || fan_back[1] != ring[1][2] || fan_on[1] != ring[2][5])
            continue;
        const std::int32_t gathered[kBoxSplinePoints] = {-1,         -1,         ring[1][2],     f[r],
                                                         ring[2][5], ring[1][3], f[(r + 1) % 3], f[(r + 2) % 3],
                                                         ring[2][4], ring[1][4], ring[1][5],     ring[2][3]};
        std::copy(gathered, gathered + kBoxSplinePoints, out.points);
        out.rotation = r, out.shape = PatchShape::CreaseVertex;
        return true;
    }
    return false;
}

void patch_weights(const Patch& patch, double s, double t, PatchWeights& out) {
    // (v, w) are the barycentric coordinates of P6 and P7: the face's corners rotation + 1 and rotation + 2.
    const double barycentric[3] = {1.0 - s - t, s, t}, along_s[3] = {-1.0, 1.0, 0.0}, along_t[3] = {-1.0, 0.0, 1.0};
    const int cv = (patch.rotation + 1) % 3, cw = (patch.rotation + 2) % 3;
    double weights[kBoxSplinePoints], dv[kBoxSplinePoints], dw[kBoxSplinePoints];
    box_spline_weights(barycentric[cv], barycentric[cw], weights, dv, dw);
    for (int i = 0; i < kBoxSplinePoints; ++i) {
        out.position[i] = weights[i];
        out.ds[i] = dv[i] * along_s[cv] + dw[i] * along_s[cw];
        out.dt[i] = dv[i] * along_t[cv] + dw[i] * along_t[cw];
    }
    if (patch.shape == PatchShape::Smooth) return;
    // Beside a crease edge the phantoms P9 = P5 + P6 - P2, P10 = P6 + P7 - P3, P11 = P7 + P8 - P4; at a crease vertex
    // P0 = P2 + P3 - P6, P1 = P3 + P4 - P7: handed to the points they are made of.
    static constexpr int kEdge[3][4] = {{9, 5, 6, 2}, {10, 6, 7, 3}, {11, 7, 8, 4}};
    static constexpr int kVertex[2][4] = {{0, 2, 3, 6}, {1, 3, 4, 7}};
    const bool edge = patch.shape == PatchShape::CreaseEdge;
    for (int p = 0; p < (edge ? 3 : 2); ++p) {
        const int* row = edge ? kEdge[p] : kVertex[p];
        const int phantom = row[0];
        const int made_of[3] = {row[1], row[2], row[3]};
        for (int k = 0; k < 3; ++k) {
            const int q = made_of[k];
            const double sign = k == 2 ? -1.0 : 1.0;
            out.position[q] += sign * out.position[phantom];
            out.ds[q] += sign * out.ds[phantom];
            out.dt[q] += sign * out.dt[phantom];
        }
        out.position[phantom] = out.ds[phantom] = out.dt[phantom] = 0.0;
    }
}

}  // namespace loopsub::detail
