// The limit surface: where the last level's vertices land when subdivision goes on forever, and the surface's
// normals there. Planned once (PlanBuilder::plan_limit: the limit masks as one more vertex-only pass for the kernels,
// the rings put in counter-clockwise order, the sides of every crease), evaluated per frame (the limit kernels,
// kernels.h's LimitFn, after the refinement in Plan::evaluate).
//
// Normals follow the seed's attribute table: smooth edges have continuous normals at the limit, crease edges
// discontinuous ones. A vertex whose fan is a disk of smooth edges (smooth, dart and cone vertices) has one normal,
// t1 x t2 of OpenSubdiv's smooth tangent masks. Elsewhere each corner takes the normal of its side: the faces
// between two sharp edges, with the sharp edges as that side's boundary (OpenSubdiv's boundary tangent masks).
//
// Where semi-sharp features outlast the last level, the surface refines on until they are spent: such a vertex's ring
// is refined in closed form at plan time (spend, RuleSet::refine_until_spent), and the masks that apply once they are
// spent are pulled back to masks over the last level's ring (pull_back_spent). Only infinitely sharp edges part sides.
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <iterator>
#include <optional>
#include <utility>

#include "plan/level_state.h"
#include "base/parallel.h"
#include "plan/plan_builder.h"
#include "topology/triangle_corners.h"

namespace loopsub {

using detail::Index;
using detail::LevelState;
using detail::Topology;
using detail::VertexNeighbourhood;

namespace {

// The limit kernels sum a tangent over offsets between last-level points, each up to 2/3 of the float maximum (evaluate
// accepts values up to a third of it, and limit points are weighted means of them). Scaled by a power of two so that
// its weights' magnitudes sum to at most one, a tangent never overflows; the normal is the same to the last bit, as
// a power of two scales t1 x t2 and its length exactly.
void scale_to_at_most_unit_sum(std::vector<float>& weights) {
    double sum = 0.0;
    for (float w : weights) sum += std::fabs(w);
    int exponent = 0;
    std::frexp(sum, &exponent);  // sum <= 2^exponent
    if (exponent > 0)
        for (float& w : weights) w = std::ldexp(w, -exponent);
}

// The places of the set bytes among bytes [0, count), in order: eight at a time, as nearly all are zero (the vertices
// by sides among a level's).
std::vector<Index> set_bytes(const std::uint8_t* bytes, Index count) {
    std::vector<Index> set;
    Index i = 0;
    for (; i + 8 <= count; i += 8) {
        std::uint64_t eight;
        std::memcpy(&eight, bytes + i, sizeof eight);
        if (eight == 0) continue;
        for (Index k = i; k < i + 8; ++k)
            if (bytes[k]) set.push_back(k);
    }
    for (; i < count; ++i)
        if (bytes[i]) set.push_back(i);
    return set;
}

#ifndef NDEBUG
// Whether plan_limit's reads around every feature vertex of the last level and its neighbours (their edges, fans,
// faces' edges, edges' ends, wings and face counts, and the faces between two feature edges) are the same through
// `around` as through the level before the last, built whole from the grandparent.
bool reads_alike_near_features(const Topology& last_level, const Topology& grandparent,
                               const VertexNeighbourhood& around, const LevelState& last,
                               const std::vector<Index>& cones) {
    const Topology whole = refine_topology(grandparent, detail::Refined::Connectivity);
    const VertexNeighbourhood through_whole(last_level, &whole);
    std::vector<Index> a, b, edges;
    std::vector<detail::FanCorner> fans[2];
    std::vector<std::uint8_t> checked(std::size_t(last_level.num_vertices), 0);  // each vertex once
    auto alike_at = [&](Index v) {
        if (checked[std::size_t(v)]) return true;
        checked[std::size_t(v)] = 1;
        around.edges(v, a), through_whole.edges(v, b);
        if (a != b) return false;
        edges = a;
        for (const Index e : edges) {
            Index ends[2][2], wings[2][2];
            around.edge_ends(e, ends[0]), through_whole.edge_ends(e, ends[1]);
            around.wings(e, wings[0][0], wings[0][1]), through_whole.wings(e, wings[1][0], wings[1][1]);
            if (!std::equal(ends[0], ends[0] + 2, ends[1]) || !std::equal(wings[0], wings[0] + 2, wings[1]) ||
                around.edge_face_count(e) != through_whole.edge_face_count(e))
                return false;
            // Only feature edges are asked for the faces between them (classify_vertex).
            for (const Index to : edges)
                if (to != e && find_feature(last.edges, e) && find_feature(last.edges, to) &&
                    through_whole.edge_face_count(e) == 2 && through_whole.edge_face_count(to) == 2 &&
                    around.faces_between(v, e, to) != through_whole.faces_between(v, e, to))
                    return false;
        }
        around.fan(v, fans[0]), through_whole.fan(v, fans[1]);
        if (fans[0] != fans[1]) return false;
        for (const detail::FanCorner& corner : fans[1]) {
            Index face_edges[2][3], face_vertices[2][3];
            const Index face = corner.corner / 3;
            around.face_edges(face, face_edges[0]), through_whole.face_edges(face, face_edges[1]);
            around.face_vertices(face, face_vertices[0]), through_whole.face_vertices(face, face_vertices[1]);
            if (!std::equal(face_edges[0], face_edges[0] + 3, face_edges[1]) ||
                !std::equal(face_vertices[0], face_vertices[0] + 3, face_vertices[1]))
                return false;
        }
        return true;
    };
    auto alike_around = [&](Index v) {
        if (!alike_at(v)) return false;
        std::vector<Index> around_v;
        through_whole.edges(v, around_v);
        return std::all_of(around_v.begin(), around_v.end(),
                           [&](Index e) { return alike_at(through_whole.other_end(e, v)); });
    };
    for (const detail::Feature& edge : last.edges)
        if (!alike_around(edge.ends[0]) || !alike_around(edge.ends[1])) return false;
    for (const detail::Feature& vertex : last.vertices)
        if (!alike_around(vertex.index)) return false;
    return std::all_of(cones.begin(), cones.end(),
                       [&](Index v) { return v >= last_level.num_vertices || alike_around(v); });
}
#endif

}  // namespace

// A closed surface without features (limit_from_grandparent_), while the level before the last is planned: the rings
// of the last level's old vertices of its grandparent are that grandparent's edges in counter-clockwise order, each
// for its half at the vertex; the rest is left to the frames (write_ordered_grandchild_rings), which read the
// grandparent's sides of each edge (edge_sides) and halves at each corner from here.
void detail::PlanBuilder::plan_limit_rings(Topology& grandparent) {
    const Topology& g = grandparent;
    plan_.limit = std::make_unique<LimitTables>();
    LimitTables& lt = *plan_.limit;
    LevelStencils& s = lt.positions;
    lt.from_grandparent = std::make_unique<LimitTables::FromGrandparent>();
    LimitTables::FromGrandparent& from = *lt.from_grandparent;
    const Index nv = g.num_vertices, child_vertices = nv + g.num_edges();
    s.ring_offsets = g.vertex_edge_offsets;
    s.ring.resize(std::size_t(g.vertex_edge_offsets[nv]));
    from.edge_sides.resize(2 * kEdgeSideSize * std::size_t(g.num_edges()));
    from.corner_halves.resize(g.face_edges.size());
    TransientVector<Index> next_at(2 * std::size_t(g.num_edges()));
    run_levels(
        std::max(1, options_.threads), 3,
        [&](int step, int part, int parts) {
            if (step == 0) {
                // Where every edge has two faces that wind against each other, the faces write every entry; else -1
                // stands for a boundary edge's missing face and for the half no face follows.
                if (closed_) return;
                const auto [h0, h1] = part_of(int(next_at.size()), part, parts);
                for (int side = h0 | 1; side < h1; side += 2) from.edge_sides[kEdgeSideSize * std::size_t(side)] = -1;
                return std::fill(next_at.begin() + h0, next_at.begin() + h1, Index(-1));
            }
            if (step == 1) {
                const auto [f0, f1] = part_of(g.num_faces(), part, parts);
                return write_grandparent_sides(g, f0, f1, from.edge_sides.data(), from.corner_halves.data(),
                                               next_at.data());
            }
            const auto [v0, v1] = part_of(nv, part, parts);
            write_ordered_old_vertex_halves(g, next_at.data(), v0, v1, child_vertices,
                                            s.ring.data() + g.vertex_edge_offsets[v0]);
        },
        kPiecesPerThread);
    // Every edge's first face runs along it from its first end: a boundary edge's one face writes its first side.
    assert([&] {
        for (std::size_t side = 0; side < from.edge_sides.size(); side += 2 * kEdgeSideSize)
            if (from.edge_sides[side] < 0) return false;
        return true;
    }());
    from.grandparent.num_vertices = nv;
    from.grandparent.edge_vertices = g.edge_vertices.data();  // the same array once it is its tables' (retire_parent)
    from.grandparent.num_edges = g.num_edges();
    from.grandparent.num_faces = g.num_faces();
    from.grandparent.edge_sides = from.edge_sides.data();
    from.grandparent.corner_halves = from.corner_halves.data();
    from.max_valence = std::max(g.max_valence, 6);
}

namespace detail {

// A feature vertex of the last level whose limit mask waits for every class to be known (a Hoppe94 crease vertex's
// limit depends on its crease neighbours' classes).
struct LimitClassified {
    Index vertex;
    SdcRule rule;
    int valence;
    Index crease[2];
    float crease_sharpness[2];
};

// A corner of a vertex whose normals are its sides' (by_side): the sides chain them across the smooth edges they
// share.
struct LimitCorner : FanCorner {
    Index vertex;
};

namespace {

// The smooth masks of the limit pass and the smooth tangents by valence, scaled (scale_to_at_most_unit_sum), with the
// regular vertex's three distinct tangent weights apart.
void smooth_limit_tables(LimitTables& lt, int max_valence) {
    LevelStencils& s = lt.positions;
    set_smooth_masks(s, max_valence, smooth_limit_mask);
    lt.smooth_t1.resize(max_valence + 1);
    lt.smooth_t2.resize(max_valence + 1);
    for (int n = 0; n <= max_valence; ++n) {
        smooth_tangent_weights(n, lt.smooth_t1[n], lt.smooth_t2[n]);
        scale_to_at_most_unit_sum(lt.smooth_t1[n]), scale_to_at_most_unit_sum(lt.smooth_t2[n]);
    }
    if (max_valence >= 6) {
        const std::vector<float>&t1 = lt.smooth_t1[6], &t2 = lt.smooth_t2[6];
        assert(t1[3] == -t1[0] && t1[2] == -t1[1] && t1[4] == -t1[1] && t1[5] == t1[1]);
        assert(t2[0] == 0.0f && t2[3] == 0.0f && t2[2] == t2[1] && t2[4] == -t2[1] && t2[5] == -t2[1]);
        lt.regular_tangents[0] = t1[0], lt.regular_tangents[1] = t1[1], lt.regular_tangents[2] = t2[1];
    }
}

// A level known through its parent (its faces only): its counter-clockwise rings written from the split's numbering,
// in parts on the plan's threads (write_ordered_child_rings).
void write_child_limit_rings(const Topology& parent, Index nv, LimitTables& lt, int threads) {
    LevelStencils& s = lt.positions;
    s.ring_offsets.resize(std::size_t(nv) + 1);
    s.ring.resize(std::size_t(child_ring_offset(parent, nv)));
    // Old vertices and midpoints shared out each on their own: an old vertex's ring costs more.
    run_levels(std::max(1, threads), 1, [&](int, int part, int parts) {
        const Index old = parent.num_vertices;
        const auto [o0, o1] = part_of(old, part, parts);
        const auto [m0, m1] = part_of(nv - old, part, parts);
        for (const auto& [v0, v1] : {std::pair<Index, Index>(o0, o1), std::pair<Index, Index>(old + m0, old + m1)}) {
            for (Index v = v0; v < v1; ++v) s.ring_offsets[v] = child_ring_offset(parent, v);
            write_ordered_child_rings(parent, v0, v1, lt.by_side.data(), s.ring.data() + child_ring_offset(parent, v0));
        }
        if (part + 1 == parts) s.ring_offsets[nv] = child_ring_offset(parent, nv);
    });
}

// A level of its own (the base): its rings put in counter-clockwise order from its triangles, each corner's edges to
// a and b naming their slots in v's ring (slot_at: an edge's slot at each end), so that no ring is searched. A fan
// that closes into no disk is marked by sides.
void order_own_limit_rings(Topology& t, const VertexNeighbourhood& around, LimitTables& lt) {
    LevelStencils& s = lt.positions;
    const Index nv = t.num_vertices;
    LargeVector<Index> slot_at(2 * std::size_t(t.num_edges()));
    auto end_of = [&t](Index e, Index v) {
        return 2 * std::size_t(e) + std::size_t(t.edge_vertices[2 * std::size_t(e) + 1] == v);
    };
    std::vector<Index> edges;
    for (Index v = 0, slot = 0; v < nv; ++v) {
        around.edges(v, edges);
        for (const Index e : edges) slot_at[end_of(e, v)] = slot++;
    }
    s.ring_offsets = t.vertex_edge_offsets;  // a copy: the sides below find their corners through the level
    s.ring = std::move(t.vertex_vertices);
    LargeVector<Index> follower(s.ring.size(), -1);
    for (std::size_t c = 0; c < t.face_vertices.size(); ++c) {
        const Index v = t.face_vertices[c];
        if (lt.by_side[v]) continue;
        const std::size_t face = c - c % 3;
        const int k = int(c % 3);
        follower[slot_at[end_of(t.face_edges[face + k], v)]] = slot_at[end_of(t.face_edges[face + prev_corner(k)], v)];
    }
    std::vector<Index> ordered;
    for (int v = 0; v < nv; ++v) {
        const Index first = s.ring_offsets[v], last = s.ring_offsets[v + 1];
        if (lt.by_side[v] || first == last) continue;
        ordered.assign(1, s.ring[first]);
        Index k = first;
        // A chain that comes back to its first slot early, or ends, is no disk; one that runs into a loop elsewhere
        // never reaches the first slot again, which the check below sees.
        while (ordered.size() < std::size_t(last - first)) {
            k = follower[k];
            if (k < 0 || k == first) break;
            ordered.push_back(s.ring[k]);
        }
        // A fan that does not close into one disk (left smooth only by tags that say nothing of it) is handled
        // by sides like a crease's.
        const bool disk = ordered.size() == std::size_t(last - first) && k >= 0 && follower[k] == first;
        if (disk) std::copy(ordered.begin(), ordered.end(), s.ring.begin() + first);
        else lt.by_side[v] = 1;
    }
}

// Each vertex's sides on their own: a part's vertices (their corners in vertex order, each vertex's in order), its
// rows counted from its own first.
struct SidesPart {
    std::vector<LimitTables::Side> sides;
    std::vector<Index> side_points;
    std::vector<std::pair<Index, Index>> corner_sides;
    int rows = 0;
};

// The sides of one vertex's fan (`fan`, n corners): chains of corners across the edges that are not infinitely sharp
// (`infinite`: its infinitely sharp edges, [infinite, infinite_end)), each a side with a normal row of its own unless
// it is the vertex's only side.
void add_sides_of_fan(const LimitCorner* fan, int n, const std::pair<Index, Index>* infinite,
                      const std::pair<Index, Index>* infinite_end, const LargeVector<VertexType>& types, Index nv,
                      SidesPart& out, std::vector<int>& next, std::vector<int>& previous,
                      std::vector<std::uint8_t>& placed) {
    next.assign(n, -1);
    previous.assign(n, -1);
    for (int i = 0; i < n; ++i) {
        // Semi-sharp edges are smooth at the limit (their vertices were spent): only infinitely sharp ones part sides.
        const Index edge = fan[i].edge_b;
        if (std::any_of(infinite, infinite_end, [edge](const auto& at) { return at.second == edge; })) continue;
        for (int j = 0; j < n; ++j) {
            if (j != i && previous[j] < 0 && fan[j].edge_a == fan[i].edge_b && fan[j].a == fan[i].b) {
                next[i] = j, previous[j] = i;
                break;
            }
        }
    }
    placed.assign(n, 0);
    const std::size_t first_side = out.sides.size(), first_corner = out.corner_sides.size();
    auto add_side = [&](int start, bool closed) {
        const Index row = nv + out.rows++;
        LimitTables::Side& entry = out.sides.emplace_back();
        entry.vertex = fan[start].vertex;
        entry.first = Index(out.side_points.size());
        entry.closed = closed;
        entry.corner = types[fan[start].vertex] == VertexType::Corner;
        entry.own = -1;
        entry.row = row;
        int faces = 0, i = start, end_face = start;
        do {
            placed[i] = 1;
            out.side_points.push_back(fan[i].a);
            out.corner_sides.push_back({fan[i].corner, row});
            ++faces;
            end_face = i;
            i = next[i];
        } while (i >= 0 && i != start);
        if (!closed) out.side_points.push_back(fan[end_face].b);
        entry.faces = faces;
    };
    for (int i = 0; i < n; ++i)
        if (previous[i] < 0) add_side(i, false);
    for (int i = 0; i < n; ++i)
        if (!placed[i]) add_side(i, true);
    if (out.sides.size() == first_side + 1) {  // the vertex's only side: its normal is the vertex's own
        out.sides.back().row = out.sides.back().vertex;
        --out.rows;
        out.corner_sides.resize(first_corner);
    }
}

// The sides of a piece's vertices (`at_sides`: their corners, by vertex), `infinite_at` the infinitely sharp edges at
// each vertex, by vertex.
SidesPart sides_of_corners(const std::vector<LimitCorner>& at_sides,
                           const std::vector<std::pair<Index, Index>>& infinite_at,
                           const LargeVector<VertexType>& types, Index nv) {
    SidesPart out;
    if (at_sides.empty()) return out;
    const std::size_t last = at_sides.size();
    auto infinite = std::lower_bound(infinite_at.begin(), infinite_at.end(), at_sides.front().vertex,
                                     [](const std::pair<Index, Index>& at, Index v) { return at.first < v; });
    std::vector<int> next, previous;
    std::vector<std::uint8_t> placed;
    for (std::size_t begin = 0; begin < last;) {
        std::size_t end = begin;
        while (end < last && at_sides[end].vertex == at_sides[begin].vertex) ++end;
        const LimitCorner* fan = &at_sides[begin];
        while (infinite != infinite_at.end() && infinite->first < fan->vertex) ++infinite;
        auto infinite_end = infinite;
        while (infinite_end != infinite_at.end() && infinite_end->first == fan->vertex) ++infinite_end;
        add_sides_of_fan(fan, int(end - begin), infinite_at.data() + (infinite - infinite_at.begin()),
                         infinite_at.data() + (infinite_end - infinite_at.begin()), types, nv, out, next, previous,
                         placed);
        begin = end;
    }
    return out;
}

// The pieces' sides joined in parts too: each piece's entries placed after the earlier pieces', its rows and points
// counted on.
void join_sides(const std::vector<SidesPart>& sides_by_part, int parts, Index nv, LimitTables& lt) {
    struct Placed {
        std::size_t sides = 0, side_points = 0, corner_sides = 0;
        Index rows = 0;
    };
    std::vector<Placed> placed(sides_by_part.size() + 1);
    for (std::size_t part = 0; part < sides_by_part.size(); ++part) {
        const SidesPart& from = sides_by_part[part];
        const Placed& before = placed[part];
        placed[part + 1] = {before.sides + from.sides.size(), before.side_points + from.side_points.size(),
                            before.corner_sides + from.corner_sides.size(), before.rows + from.rows};
    }
    lt.sides.resize(placed.back().sides);
    lt.side_points.resize(placed.back().side_points);
    lt.corner_sides.resize(placed.back().corner_sides);
    lt.num_side_rows = int(placed.back().rows);
    auto place_part = [&](int, int part, int) {
        const SidesPart& from = sides_by_part[std::size_t(part)];
        const Placed& at = placed[std::size_t(part)];
        for (std::size_t i = 0; i < from.sides.size(); ++i) {
            LimitTables::Side& side = lt.sides[at.sides + i] = from.sides[i];
            side.first += Index(at.side_points);
            if (side.row >= nv) side.row += at.rows;
        }
        std::copy(from.side_points.begin(), from.side_points.end(), lt.side_points.begin() + at.side_points);
        for (std::size_t i = 0; i < from.corner_sides.size(); ++i)
            lt.corner_sides[at.corner_sides + i] = {from.corner_sides[i].first, from.corner_sides[i].second + at.rows};
    };
    run_levels(parts, 1, place_part, int(sides_by_part.size()) / parts);
}

// The sides' tangent masks by their number of faces, scaled as the smooth ones.
void side_tangent_tables(LimitTables& lt) {
    int max_side_faces = 0;
    for (const auto& side : lt.sides) max_side_faces = std::max(max_side_faces, side.faces);
    lt.side_t1.resize(max_side_faces + 1);
    lt.side_t2.resize(max_side_faces + 1);
    for (int faces = 1; faces <= max_side_faces; ++faces) {
        side_tangent_weights(faces, lt.side_t1[faces], lt.side_t2[faces]);
        scale_to_at_most_unit_sum(lt.side_t1[faces]), scale_to_at_most_unit_sum(lt.side_t2[faces]);
    }
}

// From the grandparent: the vertices past the grandparent's that the SIMD kernels' regular pass does not finish, those
// with masks, tangents or sides of their own. Each list is in vertex order (the special masks but for spent
// vertices'): merged, not sorted.
void list_redone(LimitTables& lt, const std::vector<Index>& by_side) {
    const LevelStencils& s = lt.positions;
    std::vector<Index> specials, weighted, tangents;
    for (const SpecialVertex& special : s.special_vertices) specials.push_back(special.vertex);
    if (!std::is_sorted(specials.begin(), specials.end())) std::sort(specials.begin(), specials.end());
    for (const RingWeightedVertex& vertex : s.ring_weighted_vertices) weighted.push_back(vertex.vertex);
    for (const auto& [v, weights] : lt.own_vertex_tangents) tangents.push_back(v);
    std::vector<Index>& redone = lt.from_grandparent->redone;
    const std::vector<Index>* lists[] = {&specials, &weighted, &tangents, &by_side};
    for (const std::vector<Index>* list : lists) {
        const std::size_t middle = redone.size();
        redone.insert(redone.end(), list->begin(), list->end());
        std::inplace_merge(redone.begin(), redone.begin() + std::ptrdiff_t(middle), redone.end());
    }
    redone.erase(std::unique(redone.begin(), redone.end()), redone.end());
    redone.erase(redone.begin(),
                 std::lower_bound(redone.begin(), redone.end(), lt.from_grandparent->grandparent.num_vertices));
}

// OpenSubdiv's dart masks (dart_limit_masks) by valence, made on first use. Each runs counter-clockwise from the dart's
// sharp edge, its weight for the vertex first: read around a ring whose position `at` is the sharp edge's.
class DartMasks {
public:
    struct Masks {
        std::vector<double> position, t1, t2;
    };
    const Masks& of(int valence) {
        if (masks_.size() <= std::size_t(valence)) masks_.resize(std::size_t(valence) + 1);
        Masks& m = masks_[std::size_t(valence)];
        if (m.position.empty()) dart_limit_masks(valence, m.position, m.t1, m.t2);
        return m;
    }
    // The weight of ring position k.
    static double at_ring(const std::vector<double>& mask, int at, int k) {
        const int valence = int(mask.size()) - 1;
        return mask[std::size_t(1 + (k - at + valence) % valence)];
    }
    // The weights of ring positions 0 to valence - 1.
    static void ring_weights(const std::vector<double>& mask, int at, std::vector<float>& out) {
        out.resize(mask.size() - 1);
        for (int k = 0; k < int(out.size()); ++k) out[std::size_t(k)] = float(at_ring(mask, at, k));
    }

private:
    std::vector<Masks> masks_;
};

}  // namespace

// Each feature vertex's infinitely sharp edges, which part its sides, in vertex order: read off its visit rather than
// searched among the level's features corner by corner.
struct alignas(64) PlanBuilder::LimitVisit {  // a cache line apart: each part pushes to its own
    std::vector<LimitClassified> classified;
    std::vector<std::pair<Index, Index>> infinite_at;
    std::vector<Spent> spent;  // by vertex
    std::vector<Index> far_edges;
    std::vector<float> far_sharpness;
    std::vector<Index> by_side;
    std::vector<LimitCorner> at_sides;
    std::vector<FanCorner> fan;
};

}  // namespace detail

void detail::PlanBuilder::plan_limit(LevelState& level, const Topology& parent) {
    Topology& t = level.topology;
    const int nv = t.num_vertices;
    if (!plan_.limit) plan_.limit = std::make_unique<LimitTables>();
    LimitTables& lt = *plan_.limit;
    LevelStencils& s = lt.positions;
    s.num_vertices = nv;
    s.num_edges = 0;
    const int max_valence = lt.from_grandparent ? lt.from_grandparent->max_valence : t.max_valence;
    plan_.max_summed_terms = std::max(plan_.max_summed_terms, std::max(max_valence, 2));
    smooth_limit_tables(lt, max_valence);
    if (lt.from_grandparent && level.edges.empty() && level.vertices.empty() && cones_.empty()) {
        lt.by_side.assign(std::size_t(nv), 0);  // every vertex smooth, in one disk
        return;
    }

    const int parts = std::max(1, options_.threads);
    std::vector<LimitVisit> visited(static_cast<std::size_t>(feature_vertex_parts(parts)));
    LargeVector<VertexType>& types = plan_.level_vertex_types.emplace_back();
    types.resize(std::size_t(nv));
    lt.by_side.resize(std::size_t(nv));
    run_levels(parts, 1, [&](int, int part, int count) {  // a megabyte or two, in parts too
        const auto [v0, v1] = part_of(nv, part, count);
        std::fill(types.begin() + v0, types.begin() + v1, VertexType::Smooth);
        std::fill(lt.by_side.begin() + v0, lt.by_side.begin() + v1, std::uint8_t(0));
    });
    // From the grandparent (`parent` then), the last level is read through the level before the last, itself read
    // through the grandparent: neither is stored.
    const std::vector<int>& history = plan_.level_num_vertices;
    std::vector<int> history_before_last;
    std::optional<VertexNeighbourhood> before_last;
    if (lt.from_grandparent) {
        history_before_last.assign(history.begin(), history.end() - 1);
        before_last.emplace(history_before_last.back(), parent, &history_before_last, base_for_walks_);
    }
    const VertexNeighbourhood around =
        before_last ? VertexNeighbourhood(nv, *before_last, &history, base_for_walks_)
                    : VertexNeighbourhood(t, level.own_neighbourhood ? nullptr : &parent, &history, base_for_walks_);
    assert(!lt.from_grandparent || reads_alike_near_features(t, parent, around, level, cones_));
    // From the grandparent the rings below part no fan: every vertex by sides is a feature vertex, whose corners its
    // visit gathers while its neighbourhood is at hand.
    const bool sides_in_visit = lt.from_grandparent != nullptr;
    visit_limit_vertices(level, around, sides_in_visit, types, visited);
    std::vector<std::pair<Index, Index>> infinite_at;
    std::vector<Spent> spent;  // by vertex
    for (LimitVisit& part : visited) {
        infinite_at.insert(infinite_at.end(), part.infinite_at.begin(), part.infinite_at.end());
        std::move(part.spent.begin(), part.spent.end(), std::back_inserter(spent));
    }
    const std::vector<std::pair<Index, Index>> darts = plan_limit_masks(visited, around, types, s);
    // Counter-clockwise rings for the smooth normals: in a triangle (v, a, b), b follows a around v. From the
    // grandparent the rings are the grandparent's (limit_ring): nothing to write.
    if (!lt.from_grandparent) {
        if (!level.own_neighbourhood) write_child_limit_rings(parent, nv, lt, options_.threads);
        else order_own_limit_rings(t, around, lt);
    }
    const std::vector<Index> by_side = plan_limit_sides(visited, sides_in_visit, around, infinite_at, types, nv);
    side_tangent_tables(lt);
    plan_darts(darts, lt);
    if (!spent.empty()) pull_back_spent(spent, lt);
    auto by_vertex = [](const auto& a, const auto& b) { return a.first < b.first; };
    std::sort(lt.own_vertex_tangents.begin(), lt.own_vertex_tangents.end(), by_vertex);
    std::sort(s.ring_weighted_vertices.begin(), s.ring_weighted_vertices.end(),
              [](const RingWeightedVertex& a, const RingWeightedVertex& b) { return a.vertex < b.vertex; });
    if (lt.from_grandparent) list_redone(lt, by_side);
}

// The last level's feature vertices visited on the plan's threads, each part in vertex order: their rules and classes,
// their infinitely sharp edges, those whose semi-sharp features outlast the level spent, the rest classified for
// their masks; and which vertices have their normals by sides (with their corners, from the grandparent).
void detail::PlanBuilder::visit_limit_vertices(const LevelState& level, const VertexNeighbourhood& around,
                                               bool sides_in_visit, LargeVector<VertexType>& types,
                                               std::vector<LimitVisit>& visited) {
    LimitTables& lt = *plan_.limit;
    // About six corners per such vertex, and about one such vertex per sharp edge along a crease: reserved, as vectors
    // of this size that grow are copied into fresh pages each time.
    if (sides_in_visit)
        for (LimitVisit& part : visited) part.at_sides.reserve(6 * level.edges.size() / visited.size() + 64);
    // The fan through `around`: the level's own triangles are far apart in memory.
    auto set_by_side = [&](LimitVisit& out, Index v, bool by_side) {
        lt.by_side[v] = by_side;
        if (by_side && sides_in_visit) {
            out.by_side.push_back(v);
            around.fan(v, out.fan);
            for (const FanCorner& c : out.fan) out.at_sides.push_back({c, v});
        }
    };
    auto visit = [&](const FeatureVertex& vertex, int part) {
        LimitVisit& out = visited[std::size_t(part)];
        const SdcRule rule = sdc_vertex_rule(vertex.own_sharpness(), vertex.num_sharp_edges);
        for (std::size_t k = 0; k < vertex.edges.size(); ++k)
            if (is_infinite(vertex.sharpness[k])) out.infinite_at.push_back({vertex.vertex, vertex.edges[k]});
        types[vertex.vertex] = classify_vertex(rule, vertex, around);
        // A vertex in no triangle has no ring to refine: it stays where it is, whatever its sharpness.
        const bool outlasting = is_semi_sharp(vertex.own_sharpness()) ||
                                std::any_of(vertex.sharpness.begin(), vertex.sharpness.end(), is_semi_sharp);
        if (outlasting && !vertex.edges.empty()) {
            out.spent.push_back(spend(level, around, vertex, out.far_edges, out.far_sharpness));
            return set_by_side(out, vertex.vertex, normal_per_side(out.spent.back().ring.rule));
        }
        auto sharpness_of = [&vertex](Index e) {
            const auto at = std::find(vertex.edges.begin(), vertex.edges.end(), e);
            return at == vertex.edges.end() ? 0.0f : vertex.sharpness[std::size_t(at - vertex.edges.begin())];
        };
        out.classified.push_back({vertex.vertex,
                                  rule,
                                  int(vertex.edges.size()),
                                  {vertex.crease[0], vertex.crease[1]},
                                  {sharpness_of(vertex.crease[0]), sharpness_of(vertex.crease[1])}});
        set_by_side(out, vertex.vertex, normal_per_side(rule));
    };
    // On the plan's threads, each part in vertex order, joined in part order.
    for_each_feature_vertex(level, cones_, around, visit, std::max(1, options_.threads));
}

// The limit masks of the classified vertices, now that every class is known, in the visit's parts, joined in their
// order; the darts whose sharp edge refines as a crease (OpenSubdiv's), with the far end of that edge.
std::vector<std::pair<detail::Index, detail::Index>> detail::PlanBuilder::plan_limit_masks(
    const std::vector<LimitVisit>& visited, const VertexNeighbourhood& around, const LargeVector<VertexType>& types,
    LevelStencils& s) const {
    struct Masks {
        std::vector<SpecialVertex> specials;
        std::vector<std::pair<Index, Index>> darts;
    };
    std::vector<Masks> masks(visited.size());
    auto masks_of = [&](int, int part, int) {
        Masks& out = masks[std::size_t(part)];
        for (const LimitClassified& c : visited[std::size_t(part)].classified) {
            const Index v = c.vertex;
            double vertex_weight[2] = {0.5, 0.5};
            Index ends[2] = {v, v};
            for (int k = 0; k < 2 && c.crease[k] >= 0; ++k) {
                const Index e = c.crease[k];
                Index edge_ends[2];
                around.edge_ends(e, edge_ends);
                const bool v_first = edge_ends[0] == v;
                const Index other = v_first ? edge_ends[1] : edge_ends[0];
                ends[k] = other;
                const EdgeMask edge =
                    rules_->edge_mask({c.crease_sharpness[k], v_first ? types[v] : types[other],
                                       v_first ? types[other] : types[v], around.edge_face_count(e), true});
                vertex_weight[k] = crease_end_weight(edge, v_first);
                if (c.rule == SdcRule::Dart && edge.wings == 0.0) out.darts.push_back({v, other});
            }
            const VertexSituation situation{
                types[v], c.rule, c.valence, 0.0f, 0.0f, nullptr, nullptr, 0, {c.crease[0], c.crease[1]}, {-1, -1}};
            const LimitMask mask = rules_->limit_mask(situation, vertex_weight[0], vertex_weight[1]);
            const LimitMask smooth = smooth_limit_mask(c.valence);
            if (mask.self != smooth.self || mask.ring != smooth.ring || mask.end_a != 0.0 || mask.end_b != 0.0)
                out.specials.push_back(
                    {v, ends[0], ends[1], float(mask.self), float(mask.ring), float(mask.end_a), float(mask.end_b)});
        }
    };
    const int parts = std::max(1, options_.threads);
    run_levels(parts, 1, masks_of, int(visited.size()) / parts);
    std::vector<std::pair<Index, Index>> darts;
    for (const Masks& part : masks) {
        s.special_vertices.insert(s.special_vertices.end(), part.specials.begin(), part.specials.end());
        darts.insert(darts.end(), part.darts.begin(), part.darts.end());
    }
    return darts;
}

// Sides: the corners at each vertex by sides, in vertex order, each vertex's corners in order, in pieces of whole
// vertices taken in turn (a vertex's sides cost what its fan makes them, and a second thread starts late): from the
// grandparent the visit's parts as they are, not joined. Each piece's sides on their own, then joined. Returns the
// vertices by sides.
std::vector<detail::Index> detail::PlanBuilder::plan_limit_sides(
    std::vector<LimitVisit>& visited, bool sides_in_visit, const VertexNeighbourhood& around,
    const std::vector<std::pair<Index, Index>>& infinite_at, const LargeVector<VertexType>& types, Index nv) {
    LimitTables& lt = *plan_.limit;
    const int parts = std::max(1, options_.threads);
    const int side_pieces = int(visited.size());
    std::vector<Index> by_side;
    std::vector<std::vector<LimitCorner>> corner_pieces(visited.size());
    if (sides_in_visit) {
        for (std::size_t part = 0; part < visited.size(); ++part) {
            by_side.insert(by_side.end(), visited[part].by_side.begin(), visited[part].by_side.end());
            corner_pieces[part] = std::move(visited[part].at_sides);
        }
    } else {
        by_side = set_bytes(lt.by_side.data(), nv);
        auto corners_of_part = [&](int, int part, int count) {
            std::vector<LimitCorner>
                out;  // handed over at the end: parts that pushed to neighbouring vectors shared a line
            std::vector<FanCorner> fan;
            const auto [first, last] = part_of(by_side.size(), part, count);
            for (std::size_t i = first; i < last; ++i) {
                around.fan(by_side[i], fan);
                for (const FanCorner& c : fan) out.push_back({c, by_side[i]});
            }
            corner_pieces[std::size_t(part)] = std::move(out);
        };
        run_levels(parts, 1, corners_of_part, side_pieces / parts);
    }
    std::vector<SidesPart> sides_by_part(static_cast<std::size_t>(side_pieces));
    auto sides_of_part = [&](int, int part, int) {
        sides_by_part[std::size_t(part)] = sides_of_corners(corner_pieces[std::size_t(part)], infinite_at, types, nv);
    };
    run_levels(parts, 1, sides_of_part, side_pieces / parts);
    join_sides(sides_by_part, parts, nv, lt);
    return by_side;
}

// Darts whose sharp edge refines as a crease (OpenSubdiv's): their limit point and tangents of their own
// (rules.h, dart_limit_masks) over their counter-clockwise ring, as weights of their own.
void detail::PlanBuilder::plan_darts(const std::vector<std::pair<Index, Index>>& darts, LimitTables& lt) const {
    LevelStencils& s = lt.positions;
    DartMasks masks;
    for (const auto& [v, sharp_end] : darts) {
        Index buffer[6];
        const LimitRing found = limit_ring(lt, v, buffer);
        const Index* ring = found.ring;
        const int n = found.count;
        const int at = int(std::find(ring, ring + n, sharp_end) - ring);
        if (at == n || lt.by_side[v]) continue;  // no disk fan to order: its sides' normals
        const DartMasks::Masks& m = masks.of(n);
        std::vector<float> weights;
        DartMasks::ring_weights(m.position, at, weights);
        s.ring_weighted_vertices.push_back({v, Index(s.ring_weights.size()), float(m.position[0])});
        s.ring_weights.insert(s.ring_weights.end(), weights.begin(), weights.end());
        lt.own_vertex_tangents.push_back({v, Index(lt.own_t1.size())});
        for (int tangent = 0; tangent < 2; ++tangent) {
            DartMasks::ring_weights(tangent == 0 ? m.t1 : m.t2, at, weights);
            scale_to_at_most_unit_sum(weights);
            std::vector<float>& to = tangent == 0 ? lt.own_t1 : lt.own_t2;
            to.insert(to.end(), weights.begin(), weights.end());
        }
    }
}

// A vertex whose semi-sharp features outlast the last level: its ring refined on until they are spent (the rules'
// refine_until_spent), read through the winged-edge neighbourhood of the last level.
detail::PlanBuilder::Spent detail::PlanBuilder::spend(const LevelState& level, const VertexNeighbourhood& around,
                                                      const FeatureVertex& vertex, std::vector<Index>& far_edges,
                                                      std::vector<float>& far_sharpness) const {
    const Index v = vertex.vertex;
    const int n = int(vertex.edges.size());
    Spent out;
    out.vertex = v;
    out.neighbours.resize(n);
    for (int k = 0; k < n; ++k) out.neighbours[k] = around.other_end(vertex.edges[k], v);
    std::vector<float> far(n);
    std::vector<int> faces(n);
    std::vector<std::int32_t> wings(2 * std::size_t(n));
    for (int k = 0; k < n; ++k) {
        const Index e = vertex.edges[k];
        faces[k] = around.edge_face_count(e);
        // A missing face's wing repeats an end, weighted 0 as the edge is sharp.
        Index c, d;
        around.wings(e, c, d);
        wings[2 * k] = std::max(0, out.slot(c));
        wings[2 * k + 1] = std::max(0, out.slot(d));
        // The half at the other end decays by the edges there (Chaikin).
        const float sharpness = vertex.sharpness[k];
        far_sharpness.assign(1, sharpness);
        if (is_semi_sharp(sharpness) && rules_->decay_reads_other_edges()) {
            around.edges(out.neighbours[k], far_edges);
            far_sharpness.clear();
            for (Index f : far_edges) far_sharpness.push_back(level.edge_sharpness(f));
        }
        far[k] = rules_->child_edge_sharpness(sharpness, far_sharpness.data(), int(far_sharpness.size()));
    }
    out.ring = rules_->refine_until_spent(
        {n, vertex.own_sharpness(), vertex.sharpness.data(), far.data(), faces.data(), wings.data()});
    if (out.ring.rule == SdcRule::Dart) {
        const int k = out.ring.crease[0];
        out.dart =
            rules_->edge_mask({kInfiniteSharpness, VertexType::Dart, VertexType::Smooth, faces[k], true}).wings == 0.0;
    }
    return out;
}

// The masks that apply where the semi-sharp features are spent, pulled back to the last level through the spent
// ring's refinement: limit positions as masks over the ring (ring_weighted_vertices), tangents as weights of their own
// over a vertex's ring or a side's points. The limit pass and the normals then cost what they cost elsewhere.
void detail::PlanBuilder::pull_back_spent(const std::vector<Spent>& spent, LimitTables& lt) const {
    LevelStencils& s = lt.positions;
    std::vector<double> mask, pulled;
    auto pull_back = [&](const Spent& x) {
        const int size = int(x.neighbours.size()) + 1;
        pulled.assign(size, 0.0);
        for (int i = 0; i < size; ++i)
            for (int j = 0; j < size; ++j) pulled[j] += mask[i] * x.ring.refinement[std::size_t(i) * size + j];
    };
    // The pulled-back weights of `points` (a ring's or a side's points), taken out of `pulled`. Next to an interior
    // vertex of valence 2, two edges of a refined level join the same two vertices (the edges inside the two faces
    // at it): x then has two slots on one vertex, which the ring lists twice, and their weights, summed, are shared
    // by its places. The two faces there are alike (swapping them changes nothing around them), so the two slots
    // hold the same point on every level of the spent ring: only their sum is defined, and slot(), which finds the
    // first, serves for the wings and the masks.
    std::vector<double> taken;
    auto take = [&](const Spent& x, const Index* points, int count, std::vector<float>& weights) {
        taken.assign(std::size_t(count), 0.0);
        for (std::size_t j = 0; j < pulled.size(); ++j) {
            const Index at = j == 0 ? x.vertex : x.neighbours[j - 1];
            const int places = int(std::count(points, points + count, at));
            for (int i = 0; i < count && places > 0; ++i)
                if (points[i] == at) taken[std::size_t(i)] += pulled[j] / places;
            if (places > 0) pulled[j] = 0.0;
        }
        weights.assign(taken.begin(), taken.end());
    };
    // Tangent weights sum to zero: the vertex's is what its points' leave, and only the points' are kept.
    auto own_tangents = [&](const Spent& x, const Index* points, int count, const float* w1, const float* w2) {
        const Index first = Index(lt.own_t1.size());
        std::vector<float> weights;
        for (int tangent = 0; tangent < 2; ++tangent) {
            const float* w = tangent == 0 ? w1 : w2;
            mask.assign(x.neighbours.size() + 1, 0.0);
            for (int i = 0; i < count; ++i) mask[x.slot(points[i])] += w[i], mask[0] -= w[i];
            pull_back(x);
            take(x, points, count, weights);
            // A side's points refine among themselves (its sharp edges' wings weigh nothing), so nothing of a side's
            // tangent falls on the ring's other points.
            assert(std::all_of(pulled.begin() + 1, pulled.end(), [](double w) { return std::fabs(w) < 1e-9; }));
            scale_to_at_most_unit_sum(weights);
            std::vector<float>& to = tangent == 0 ? lt.own_t1 : lt.own_t2;
            to.insert(to.end(), weights.begin(), weights.end());
        }
        return first;
    };
    DartMasks darts;
    std::vector<float> dart_t1, dart_t2;
    for (const Spent& x : spent) {
        const Index v = x.vertex;
        const int n = int(x.neighbours.size());
        Index buffer[6];
        const LimitRing found = limit_ring(lt, v, buffer);
        const Index* ring = found.ring;
        assert(found.count == n);
        // Spent into a dart whose fan is a disk: plan_darts' masks, from the sharp edge at ring place `at`.
        const int at = x.dart ? int(std::find(ring, ring + n, x.neighbours[std::size_t(x.ring.crease[0])]) - ring) : n;
        const DartMasks::Masks* dart = at < n && !lt.by_side[v] ? &darts.of(n) : nullptr;
        if (dart) {
            mask.assign(n + 1, 0.0);
            mask[0] = dart->position[0];
            for (int k = 0; k < n; ++k) mask[x.slot(ring[k])] += DartMasks::at_ring(dart->position, at, k);
        } else {
            const LimitMask limit = rules_->limit_mask({VertexType::Smooth,
                                                        x.ring.rule,
                                                        n,
                                                        0.0f,
                                                        0.0f,
                                                        nullptr,
                                                        nullptr,
                                                        0,
                                                        {x.ring.crease[0], x.ring.crease[1]},
                                                        {-1, -1}},
                                                       0.5, 0.5);
            mask.assign(n + 1, limit.ring);
            mask[0] = limit.self;
            if (x.ring.crease[0] >= 0) mask[1 + x.ring.crease[0]] += limit.end_a;
            if (x.ring.crease[1] >= 0) mask[1 + x.ring.crease[1]] += limit.end_b;
        }
        pull_back(x);
        s.ring_weighted_vertices.push_back({v, Index(s.ring_weights.size()), float(pulled[0])});
        std::vector<float> weights;
        take(x, ring, n, weights);
        s.ring_weights.insert(s.ring_weights.end(), weights.begin(), weights.end());
        // Smooth or a dart once spent, its ring counter-clockwise: one normal.
        if (lt.by_side[v]) continue;
        if (!dart) {
            lt.own_vertex_tangents.push_back(
                {v, own_tangents(x, ring, n, lt.smooth_t1[n].data(), lt.smooth_t2[n].data())});
            continue;
        }
        DartMasks::ring_weights(dart->t1, at, dart_t1), DartMasks::ring_weights(dart->t2, at, dart_t2);
        lt.own_vertex_tangents.push_back({v, own_tangents(x, ring, n, dart_t1.data(), dart_t2.data())});
    }
    for (LimitTables::Side& side : lt.sides) {
        const auto found = std::lower_bound(spent.begin(), spent.end(), side.vertex,
                                            [](const Spent& x, Index v) { return x.vertex < v; });
        if (found == spent.end() || found->vertex != side.vertex) continue;
        const Index* points = &lt.side_points[side.first];
        side.own = side.closed ? own_tangents(*found, points, side.faces, lt.smooth_t1[side.faces].data(),
                                              lt.smooth_t2[side.faces].data())
                               : own_tangents(*found, points, side.faces + 1, lt.side_t1[side.faces].data() + 1,
                                              lt.side_t2[side.faces].data() + 1);
    }
}

}  // namespace loopsub
