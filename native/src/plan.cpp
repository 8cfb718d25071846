// Building a Plan: all topology work for N levels, done once: the base level's sharpness from the tags, then per
// level the classification of the vertices next to a feature, their masks, the sharpness decay into the child level,
// the child's connectivity and the stencil tables. (Checks of the input: validation.cpp; the per-frame work:
// evaluate.cpp.)
#include <algorithm>
#include <cstring>
#include <limits>
#include <string>

#include "budget.h"
#include "common.h"
#include "kernels.h"
#include "level_state.h"
#include "parallel.h"
#include "plan_data.h"
#include "rule_set.h"
#include "rules.h"
#include "validation.h"

namespace loopsub {

using detail::fail;
using detail::Index;
using detail::LevelCounts;
using detail::Topology;
using detail::describe_bytes;
using detail::estimate_for_counts;
using detail::kSaturated;
using detail::add;
using detail::mul;

namespace {

// LevelTables::Auto: past this size of stored tables of the level before the last, tables are derived instead. The
// size is counted as when that level's faces were built too (24 bytes per edge and face); a stored plan no longer
// builds them, but the count is kept so that Auto switches where it is documented (a result of about 20 M triangles).
constexpr std::uint64_t kDeriveAboveBytes = std::uint64_t(128) << 20;

Index find_edge(const Topology& t, Index a, Index b) {
    for (Index k = t.vertex_edge_offsets[a]; k < t.vertex_edge_offsets[a + 1]; ++k)
        if (t.other_end(t.vertex_edges[k], a) == b) return t.vertex_edges[k];
    return -1;
}

}  // namespace

using detail::Feature;
using detail::LevelState;

LevelState PlanImpl::base_level(const MeshView& mesh) {
    LevelState level;
    level.topology = detail::build_base_topology(mesh.triangles, mesh.num_triangles, mesh.num_vertices, options.threads);
    const Topology& t = level.topology;

    std::vector<float> edge_tag(t.num_edges(), 0.0f);
    for (int k = 0; k < mesh.num_crease_edges; ++k) {
        const Index a = mesh.crease_edges[2 * k], b = mesh.crease_edges[2 * k + 1];
        const Index e = a == b ? -1 : find_edge(t, a, b);
        if (e < 0)
            fail("crease edge " + std::to_string(k) + " (" + std::to_string(a) + ", " + std::to_string(b) +
                 ") is not an edge of the mesh");
        edge_tag[e] = mesh.crease_sharpness[k];  // a repeated tag overrides, as in OpenSubdiv
    }
    if (mesh.num_holes > 0) {
        holes.assign(mesh.num_triangles, 0);
        for (int k = 0; k < mesh.num_holes; ++k) holes[mesh.hole_triangles[k]] = 1;
    }
    if (options.boundary == Boundary::None) {
        // Far's prepareComponentTagsAndSharpness: a vertex on a boundary edge that its tags do not make infinitely
        // sharp takes its faces out of the surface.
        std::vector<std::uint8_t> excluding(t.num_vertices, 0);
        for (int e = 0; e < t.num_edges(); ++e)
            if (t.edge_face_count(e) == 1 && !detail::is_infinite(rules->edge_sharpness_from_tag(edge_tag[e])))
                excluding[t.edge_vertices[2 * e]] = excluding[t.edge_vertices[2 * e + 1]] = 1;
        for (int f = 0; f < t.num_faces(); ++f)
            for (int k = 0; k < 3; ++k)
                if (excluding[t.face_vertices[3 * f + k]]) {
                    holes.resize(t.num_faces(), 0);
                    holes[f] = 1;
                }
    }
    std::vector<float> vertex_tag(t.num_vertices, 0.0f);
    for (int k = 0; k < mesh.num_corners; ++k) vertex_tag[mesh.corner_vertices[k]] = mesh.corner_sharpness[k];
    if (rules->has_cones()) {
        cones.assign(mesh.cone_vertices, mesh.cone_vertices + mesh.num_cones);
        std::sort(cones.begin(), cones.end());
        cones.erase(std::unique(cones.begin(), cones.end()), cones.end());
    }

    // Boundary and non-manifold edges are infinitely sharp; so are non-manifold vertices (unless they sit on
    // exactly two edges with more than two faces: a non-manifold crease; OpenSubdiv 3.5 does not count edges
    // that are non-manifold by their winding alone) and, when corners are kept, boundary vertices with a single
    // face. Both rule sets share this (Far's prepareComponentTagsAndSharpness for OpenSubdiv).
    const std::vector<std::uint8_t> non_manifold_edge = detail::non_manifold_edges(t);
    const std::vector<std::uint8_t> non_manifold_vertex = detail::non_manifold_vertices(t, non_manifold_edge, options.threads);
    // Most edges and vertices are untagged and regular: they are passed over without a call to the rules (a zero tag
    // is smooth under every rule set), which was most of these loops' 40 us on a plan of 5,120 triangles.
    for (int e = 0; e < t.num_edges(); ++e) {
        const float tag = edge_tag[e];
        const bool forced_sharp = t.edge_face_count(e) < 2 || non_manifold_edge[e];
        if (tag == 0.0f && !forced_sharp) continue;
        const float sharpness = forced_sharp ? kInfiniteSharpness : rules->edge_sharpness_from_tag(tag);
        if (sharpness > 0.0f || tag != 0.0f) level.edges.push_back({Index(e), sharpness, tag, {t.edge_vertices[2 * e], t.edge_vertices[2 * e + 1]}});
    }
    const bool corners_kept = options.boundary == Boundary::EdgesAndCorners;
    for (int v = 0; v < t.num_vertices; ++v) {
        const float tag = vertex_tag[v];
        if (tag == 0.0f && !non_manifold_vertex[v] && !(corners_kept && t.valence(v) == 2)) continue;
        float sharpness = rules->vertex_sharpness_from_tag(tag);
        int faces = 0, fins = 0;
        for (Index k = t.vertex_edge_offsets[v]; k < t.vertex_edge_offsets[v + 1]; ++k) {
            const int edge_faces = t.edge_face_count(t.vertex_edges[k]);
            faces += edge_faces;
            fins += edge_faces > 2;
        }
        const bool single_face_corner = t.valence(v) == 2 && faces == 2;
        if (single_face_corner && corners_kept) sharpness = kInfiniteSharpness;
        else if (non_manifold_vertex[v] && fins != 2) sharpness = kInfiniteSharpness;
        if (sharpness > 0.0f || tag != 0.0f) level.vertices.push_back({Index(v), sharpness, tag});
    }
    return level;
}

namespace {

// Regular crease vertex (RULES.md section 1): interior with valence 6 and three faces on each side of its
// crease, or on the boundary with valence 4 and its two crease edges the boundary edges.
bool is_regular_crease(const detail::VertexNeighbourhood& around, const std::vector<Index>& edges, Index v,
                       Index crease_a, Index crease_b) {
    bool boundary = false;
    for (Index e : edges) {
        const int faces = around.edge_face_count(e);
        if (faces > 2) return false;
        boundary |= faces == 1;
    }
    const std::size_t valence = edges.size();
    if (boundary) return valence == 4 && around.edge_face_count(crease_a) == 1 && around.edge_face_count(crease_b) == 1;
    return valence == 6 && around.faces_between(v, crease_a, crease_b) == 3;
}

}  // namespace

namespace detail {

VertexType classify_vertex(SdcRule rule, const FeatureVertex& vertex, const VertexNeighbourhood& around) {
    switch (rule) {
        case SdcRule::Smooth: return vertex.tagged_cone ? VertexType::Cone : VertexType::Smooth;
        case SdcRule::Dart: return vertex.tagged_cone ? VertexType::Cone : VertexType::Dart;
        case SdcRule::Crease:
            if (vertex.tagged_cone) return VertexType::Corner;
            return is_regular_crease(around, vertex.edges, vertex.vertex, vertex.crease[0], vertex.crease[1])
                       ? VertexType::RegularCrease
                       : VertexType::IrregularCrease;
        case SdcRule::Corner: break;
    }
    return VertexType::Corner;
}

}  // namespace detail

void PlanImpl::plan_level(LevelState& level, const Topology& parent, LevelState& child, int child_level) {
    // With the limit surface, the last level is planned like the others, its limit pass standing in for a child.
    const int final_level = options.levels + (options.limit_surface ? 1 : 0);
    const bool last_child = child_level == final_level, grandchild_last = child_level + 1 == final_level;
    Topology& t = level.topology;  // empty but for num_vertices where the level is not built
    const detail::VertexNeighbourhood around(t, level.own_neighbourhood ? nullptr : &parent, &level_num_vertices, base_for_walks);
    const int nv = t.num_vertices, ne = around.num_edges();

    detail::LevelStencils& s = stencils.emplace_back();
    s.num_vertices = nv;
    s.num_edges = ne;
    const int max_valence = around.max_valence();
    max_summed_terms = std::max(max_summed_terms, std::max(max_valence, 2));  // a ring, or an edge's two ends
    detail::set_smooth_masks(s, max_valence, detail::smooth_vertex_mask);

    // Only vertices next to a feature (or cones) can differ from the smooth pass. Child features: the halves of
    // each edge get their sharpness at their own end vertex (Chaikin looks at the other edges there), old vertices
    // decay; edges inside faces and vertices on edges start smooth.
    detail::LargeVector<VertexType>& types = level_vertex_types.emplace_back(nv, VertexType::Smooth);
    // The last level is refined no further, but its classes are reported too (what the result is tagged with): an
    // old vertex's from its child sharpness, a midpoint's from its two halves, over this level's neighbourhoods. Only
    // those next to a feature are kept here (PlanImpl::last_level_types).
    // Each thread collects its share of the vertices' child features, special masks and last classes; joined in order after.
    struct PartFeatures {
        std::vector<Feature> edges, vertices;
        std::vector<detail::SpecialVertex> specials;
        std::vector<std::pair<Index, VertexType>> last_types;
        std::vector<float> child_sharpness;  // scratch
    };
    const int parts = std::max(1, options.threads);
    std::vector<PartFeatures> by_part(parts);
    // The halves of feature edge i (of level.edges) that stay features go to slots 2i and 2i + 1: the child's edge
    // features in order without a sort (which was a sixth of what creases add to a plan). Index -1: none.
    std::vector<Feature> halves_of_features(2 * level.edges.size(), Feature{-1, 0.0f, 0.0f});
    detail::for_each_feature_vertex(level, cones, around, [&](const detail::FeatureVertex& vertex, int part) {
        PartFeatures& out = by_part[part];
        std::vector<float>& child_sharpness = out.child_sharpness;
        const Index v = vertex.vertex;
        const int valence = int(vertex.edges.size());
        child_sharpness.resize(valence);
        int child_sharp_edges = 0;
        Index child_crease[2] = {-1, -1};
        for (int k = 0; k < valence; ++k) {
            const Index e = vertex.edges[k];
            const float decayed = rules->child_edge_sharpness(vertex.sharpness[k], vertex.sharpness.data(), valence);
            child_sharpness[k] = decayed;
            if (detail::is_sharp(decayed) && child_sharp_edges++ < 2) child_crease[child_sharp_edges - 1] = e;
            const float child_tag = rules->child_tag(vertex.tags[k], decayed);
            if (!(decayed > 0.0f || child_tag != 0.0f)) continue;
            const Index half_index = around.child_edge_at(e, v), m = nv + e;  // half 2e = (a, m), 2e + 1 = (m, b)
            const Feature half{half_index, decayed, child_tag, {half_index & 1 ? m : v, half_index & 1 ? v : m}};
            if (const Feature* feature = (*vertex.edge_features)[k])
                halves_of_features[2 * std::size_t(feature - level.edges.data()) + std::size_t(half.index & 1)] = half;
            else
                out.edges.push_back(half);
        }
        const float vertex_sharpness = vertex.own_sharpness();
        const float child_vertex_sharpness = rules->child_vertex_sharpness(vertex_sharpness);
        const float child_vertex_tag = rules->child_tag(vertex.own_tag(), child_vertex_sharpness);
        if (child_vertex_sharpness > 0.0f || child_vertex_tag != 0.0f) out.vertices.push_back({v, child_vertex_sharpness, child_vertex_tag});

        const detail::SdcRule rule = detail::sdc_vertex_rule(vertex_sharpness, vertex.sharp_edges);
        types[v] = detail::classify_vertex(rule, vertex, around);
        if (last_child) {
            const detail::FeatureVertex as_child{v, vertex.edges, child_sharpness, vertex.tags, child_sharp_edges,
                                                 {child_crease[0], child_crease[1]}, vertex.tagged_cone};
            out.last_types.push_back(
                {v, detail::classify_vertex(detail::sdc_vertex_rule(child_vertex_sharpness, child_sharp_edges), as_child, around)});
        }
        const detail::VertexMask smooth = detail::smooth_vertex_mask(valence);
        Index ends[2];
        const detail::VertexMask mask = rules->vertex_mask(
            {types[v], rule, valence, vertex_sharpness, child_vertex_sharpness, vertex.sharpness.data(),
             child_sharpness.data(), child_sharp_edges, {vertex.crease[0], vertex.crease[1]}, {child_crease[0], child_crease[1]}},
            ends);
        if (mask.self != smooth.self || mask.ring != smooth.ring || mask.crease != 0.0) {
            const bool has_ends = mask.crease != 0.0;
            out.specials.push_back({v, has_ends ? around.other_end(ends[0], v) : v, has_ends ? around.other_end(ends[1], v) : v,
                                    float(mask.self), float(mask.ring), float(mask.crease), float(mask.crease)});
        }
    }, parts);
    // Whether half k of feature edge i (slot 2i + k) is sharp: a slot with no half holds sharpness 0.
    auto sharp_half = [&halves_of_features](std::size_t slot) { return detail::is_sharp(halves_of_features[slot].sharpness); };
    std::size_t joined[4] = {halves_of_features.size(), 0, 0, 0};  // upper bounds: the joins then move nothing twice
    for (const PartFeatures& out : by_part) {
        joined[0] += out.edges.size(), joined[1] += out.vertices.size();
        joined[2] += out.specials.size(), joined[3] += out.last_types.size();
    }
    child.edges.reserve(joined[0]);
    child.vertices.reserve(joined[1]);
    s.special_vertices.reserve(joined[2]);
    last_level_types.reserve(joined[3] + (last_child ? level.edges.size() : 0));
    for (const Feature& half : halves_of_features)
        if (half.index >= 0) child.edges.push_back(half);
    bool unsorted = false;  // halves of edges that were no feature (a rule set that sharpens them)
    for (const PartFeatures& out : by_part) {
        unsorted |= !out.edges.empty();
        child.edges.insert(child.edges.end(), out.edges.begin(), out.edges.end());
        child.vertices.insert(child.vertices.end(), out.vertices.begin(), out.vertices.end());
        s.special_vertices.insert(s.special_vertices.end(), out.specials.begin(), out.specials.end());
        last_level_types.insert(last_level_types.end(), out.last_types.begin(), out.last_types.end());
    }
    if (unsorted) std::sort(child.edges.begin(), child.edges.end());  // vertices were visited in order: child.vertices is sorted
    if (last_child) {
        // A midpoint's only edges that can be sharp are its two halves; it is regular where its edge has at most
        // two faces (valence 6 with three faces on each side, or a boundary of valence 4).
        for (std::size_t i = 0; i < level.edges.size(); ++i) {
            const Feature& f = level.edges[i];
            const int sharp_halves = sharp_half(2 * i) + sharp_half(2 * i + 1);
            if (sharp_halves == 0) continue;
            const VertexType type = sharp_halves == 1                            ? VertexType::Dart
                                    : around.edge_face_count(f.index) <= 2 ? VertexType::RegularCrease
                                                                           : VertexType::IrregularCrease;
            last_level_types.push_back({nv + f.index, type});
        }
    }

    // The last level needs only its triangles. The one before it needs its stencils, but not its edge faces and
    // vertex edges (a third of its memory traffic): the few vertices it classifies take them from this level. Where
    // nothing else is refined (skip_level_before_last), the level before the last is not built at all: its child's
    // triangles come from this level through the numbering, as its stencils do. With derived tables
    // (Options::level_tables) the other levels keep their connectivity only.
    if (skip_level_before_last && grandchild_last) {
        child.topology.num_vertices = nv + ne;
    } else if (skip_level_before_last && last_child) {
        child.topology.num_vertices = nv + ne;
        child.topology.face_vertices.resize(48 * std::size_t(parent.num_faces()));
        if (derive_tables) {  // else written beside this level's tables (fill_tables_from_parent, below)
            detail::run_levels(std::max(1, options.threads), 1, [&](int, int part, int parts) {
                const auto [f0, f1] = detail::part_of(parent.num_faces(), part, parts);
                detail::write_grandchild_faces(parent, f0, f1, child.topology.face_vertices.data());
            });
        }
    } else {
        child.topology = detail::refine_topology(t, last_child        ? detail::Refined::FacesOnly
                                                    : grandchild_last ? detail::Refined::ForStencils
                                                    : derive_tables   ? detail::Refined::Connectivity
                                                                      : detail::Refined::Full,
                                                 options.threads);
    }
    child.own_neighbourhood = !grandchild_last;
    level_num_vertices.push_back(child.topology.num_vertices);

    // Edge points: the endpoints, and the vertices opposite the edge in its first two faces (a missing face
    // repeats an endpoint: such an edge is sharp, and its mask gives them no weight).
    for (std::size_t i = 0; i < level.edges.size(); ++i) {
        const Feature& feature = level.edges[i];
        const Index e = feature.index;
        const float sharpness = feature.sharpness;
        if (!detail::is_sharp(sharpness)) continue;
        const Index a = feature.ends[0], b = feature.ends[1];
        const bool halves_sharp = sharp_half(2 * i) && sharp_half(2 * i + 1);
        const detail::EdgeMask mask = rules->edge_mask({sharpness, types[a], types[b], around.edge_face_count(e), halves_sharp});
        if (!(mask == detail::smooth_edge_mask())) s.special_edges.push_back({e, float(mask.a), float(mask.b), float(mask.wings)});
    }

    // Hand over what the stencils keep rather than copy it; a level planned further keeps its offsets until its child
    // is planned (its neighbourhoods may be derived from this level), then build hands them over; with derived tables
    // the level after the base keeps the base whole, so the base's stencils copy them. Derived tables (levels past the
    // base) are not stored; those of a level not built are filled from its parent.
    if (skip_level_before_last && last_child && !derive_tables) {
        detail::fill_tables_from_parent(parent, s, child.topology.face_vertices.data(), options.threads);
    } else if (!derive_tables || child_level == 1) {
        if (last_child) s.ring_offsets = std::move(t.vertex_edge_offsets);
        else if (derive_tables) s.ring_offsets = t.vertex_edge_offsets;
        s.ring = std::move(t.vertex_vertices);
        s.edge_c = std::move(t.edge_opposite_c);
        s.edge_d = std::move(t.edge_opposite_d);
    }
    if (child_level >= 2 && !derive_tables) {  // a split level, its rings as FanFn reads them
        s.fan_first_midpoint = parent.num_vertices;
        s.fan_midpoints = nv - parent.num_vertices;
    }
}

void PlanImpl::drop_holes() {
    // Triangle t of the last level descends from input triangle t / 4^levels.
    const int shift = 2 * options.levels;
    const std::size_t count = output_triangles.size() / 3;
    std::vector<Index> renumbered(count, -1);
    for (std::size_t t = 0; t < count; ++t) {
        if (holes[t >> shift]) continue;
        renumbered[t] = Index(kept_triangles.size());
        kept_triangles.push_back(Index(t));
    }
    auto compact = [&](detail::LargeVector<Index>& corners) {
        for (std::size_t k = 0; k < kept_triangles.size(); ++k)
            for (int c = 0; c < 3; ++c) corners[3 * k + c] = corners[3 * std::size_t(kept_triangles[k]) + c];
        corners.resize(3 * kept_triangles.size());
    };
    compact(output_triangles);
    for (detail::FaceVaryingPlan& layer : face_varying) compact(layer.output_corner_values);
    if (limit) {
        std::vector<std::pair<Index, Index>> kept;
        for (const auto& [corner, side] : limit->corner_sides)
            if (renumbered[corner / 3] >= 0) kept.push_back({3 * renumbered[corner / 3] + corner % 3, side});
        limit->corner_sides = std::move(kept);
    }
}

void PlanImpl::collect_output_tags(const LevelState& last) {
    for (const Feature& f : last.edges) {
        if (f.sharpness > 0.0f) {
            output_sharp_edges.push_back(f.ends[0]);
            output_sharp_edges.push_back(f.ends[1]);
            output_sharp_edge_sharpness.push_back(f.sharpness);
        }
        if (f.tag <= 0.0f) continue;
        output_crease_edges.push_back(f.ends[0]);
        output_crease_edges.push_back(f.ends[1]);
        output_crease_sharpness.push_back(f.tag);
    }
    for (const Feature& f : last.vertices) {
        if (f.tag <= 0.0f) continue;
        output_corner_vertices.push_back(f.index);
        output_corner_sharpness.push_back(f.tag);
    }
}

namespace {

// A level done with (its child planned): its edge list becomes its stencils' edge ends, and its offsets their ring
// offsets where plan_level left them to it (a copy of 41k offsets was 9 us of a plan's serial part).
void hand_over_edges_and_offsets(Topology& level, detail::LevelStencils& s) {
    s.edge_ends = std::move(level.edge_vertices);
    if (s.ring_offsets.empty()) s.ring_offsets = std::move(level.vertex_edge_offsets);
}

}  // namespace

void PlanImpl::build(const MeshView& mesh) {
    const auto start = detail::Clock::now();
    detail::validate_options(options);  // first: the team below starts `threads` threads
    const detail::TeamScope team(options.threads);  // a kept team, or one whose threads start while the base level is built
    detail::validate_mesh(mesh);
    rules = detail::make_rule_set(options);
    kernel = detail::resolve_kernel(options.kernel);
    num_input_vertices = mesh.num_vertices;
    num_input_triangles = mesh.num_triangles;
    level_num_vertices.push_back(mesh.num_vertices);

    LevelState level = base_level(mesh);
    const LevelCounts counts{std::uint64_t(mesh.num_vertices), std::uint64_t(level.topology.num_edges()),
                             std::uint64_t(mesh.num_triangles)};
    LevelCounts last = counts;
    for (int l = 0; l < options.levels; ++l) last = last.child();
    const std::uint64_t needed = estimate_for_counts(counts, options.levels, 3);
    const std::uint64_t index_limit = std::uint64_t(std::numeric_limits<Index>::max());
    const std::string request = "subdividing " + std::to_string(mesh.num_triangles) + " triangles " +
                                std::to_string(options.levels) + " times gives " +
                                (last.faces == kSaturated ? std::string("more than 2^64") : std::to_string(last.faces)) + " triangles";
    if (needed > options.memory_limit_bytes)
        throw MemoryLimitError(request + " and would need about " + describe_bytes(needed) + ", more than the limit of " +
                                   describe_bytes(options.memory_limit_bytes),
                               needed);
    if (mul(3, last.faces) > index_limit || mul(2, last.edges) > index_limit)
        throw MemoryLimitError(request + ", more than 32-bit indices can address (about " + describe_bytes(needed) + " would be needed)",
                               needed);

    std::vector<detail::FaceVaryingBuilder> layers;
    for (int k = 0; k < mesh.num_face_varying; ++k) layers.emplace_back(mesh, k, options, level);
    // Options::level_tables. Auto: an evaluation from stored tables is faster (docs/benchmark.md), so a plan keeps
    // them up to where its memory, and its build time, matter more.
    LevelCounts last_but_one = counts;
    for (int l = 1; l < options.levels; ++l) last_but_one = last_but_one.child();
    const std::uint64_t stored_tables = mul(24, add(last_but_one.edges, last_but_one.faces));  // ring, edges, faces
    skip_level_before_last = options.levels >= 2 && !options.limit_surface;
    derive_tables = skip_level_before_last && layers.empty() && (options.level_tables == LevelTables::Derived ||
                                               (options.level_tables == LevelTables::Auto && stored_tables > kDeriveAboveBytes));
    Topology parent;  // the level before `level`: the next-to-last level derives its neighbourhoods from it
    for (int l = 0; l < options.levels; ++l) {
        LevelState child;
        plan_level(level, parent, child, l + 1);
        const bool last = l + 1 == options.levels;
        for (detail::FaceVaryingBuilder& layer : layers)
            layer.plan_level(level, skip_level_before_last && last ? &parent : nullptr, stencils[l], child, last);
        // A level's edge list serves its child's neighbourhoods, then the stencils as the edge points' ends; with
        // derived tables, a level's stencils keep the whole level before (the base's stencils its own edge list).
        if (derive_tables && l > 0) {
            if (l == 1) stencils[0].edge_ends = parent.edge_vertices;
            stencils[l].derived_from = std::make_unique<Topology>(std::move(parent));
        } else if (l > 0) {
            hand_over_edges_and_offsets(parent, stencils[l - 1]);
        }
        if (stencils[l].interior) {  // the last level's stencils read the faces of the level before its parent
            stencils[l].interior->face_vertices = std::move(parent.face_vertices);
            stencils[l].interior->face_edges = std::move(parent.face_edges);
        }
        if (l == 1) {  // the base, done with: its faces stay for the walks around its vertices on later levels
            if (stencils[1].derived_from) base_for_walks = stencils[1].derived_from.get();
            else if (!stencils[1].interior) base_for_walks = &(kept_base = std::move(parent));
        }
        parent = std::move(level.topology);
        level = std::move(child);
    }
    if (options.limit_surface) plan_limit(level, parent);
    for (detail::FaceVaryingBuilder& layer : layers) {
        if (options.limit_surface) layer.plan_limit(limit->positions);
        face_varying.push_back(layer.finish());
    }
    if (options.levels > 0 && !skip_level_before_last) hand_over_edges_and_offsets(parent, stencils.back());
    output_triangles = std::move(level.topology.face_vertices);
    if (!holes.empty()) drop_holes();
    level_edges.resize(options.levels);
    level_edges_ready = std::vector<std::once_flag>(options.levels);
    level_vertex_types_copies.resize(std::size_t(options.levels) + 1);
    level_vertex_types_ready = std::vector<std::once_flag>(std::size_t(options.levels) + 1);
    collect_output_tags(level);
    rules.reset();
    base_for_walks = nullptr;
    kept_base = Topology();
    if (needed > 4 * detail::BlockPool::kPoolBytes) detail::BlockPool::instance().release_all(detail::LargeAllocator<char>::free_large);
    topology_ms = detail::ms_since(start);
}

Plan::Plan(const MeshView& mesh, const Options& options) : impl_(std::make_unique<PlanImpl>()) {
    impl_->options = options;
    impl_->build(mesh);
}
Plan::~Plan() = default;
Plan::Plan(Plan&&) noexcept = default;
Plan& Plan::operator=(Plan&&) noexcept = default;

const Options& Plan::options() const { return impl_->options; }
int Plan::levels() const { return impl_->options.levels; }
int Plan::num_input_vertices() const { return impl_->num_input_vertices; }
int Plan::num_output_vertices() const { return impl_->level_num_vertices.back(); }
int Plan::num_output_triangles() const { return int(impl_->output_triangles.size() / 3); }
const std::int32_t* Plan::output_triangles() const { return impl_->output_triangles.data(); }
const std::int32_t* Plan::output_parent_triangles() const {
    const PlanImpl& p = *impl_;
    std::call_once(p.output_parents_ready, [&p] {
        // Child triangle 4f + k of a level has parent f, so a level-L triangle descends from input triangle t / 4^L.
        p.output_parents.resize(p.output_triangles.size() / 3);
        const bool holes = !p.holes.empty();
        for (std::size_t t = 0; t < p.output_parents.size(); ++t)
            p.output_parents[t] = Index(std::size_t(holes ? p.kept_triangles[t] : Index(t)) >> (2 * p.options.levels));
    });
    return p.output_parents.data();
}
const std::vector<std::int32_t>& Plan::output_crease_edges() const { return impl_->output_crease_edges; }
const std::vector<float>& Plan::output_crease_sharpness() const { return impl_->output_crease_sharpness; }
const std::vector<std::int32_t>& Plan::output_corner_vertices() const { return impl_->output_corner_vertices; }
const std::vector<float>& Plan::output_corner_sharpness() const { return impl_->output_corner_sharpness; }
const std::vector<std::int32_t>& Plan::output_sharp_edges() const { return impl_->output_sharp_edges; }
const std::vector<float>& Plan::output_sharp_edge_sharpness() const { return impl_->output_sharp_edge_sharpness; }
Kernel Plan::kernel() const { return impl_->kernel; }
double Plan::topology_ms() const { return impl_->topology_ms; }
double Plan::last_evaluate_ms() const { return impl_->evaluate_ms; }

const std::vector<std::int32_t>& Plan::level_edges(int level) const {
    if (level < 0 || level >= levels()) throw std::out_of_range("level_edges: level " + std::to_string(level) + " is not in 0.." + std::to_string(levels() - 1));
    const PlanImpl& p = *impl_;
    std::call_once(p.level_edges_ready[level], [&p, level] {
        const detail::LevelStencils& s = p.stencils[level];
        std::vector<Index>& edges = p.level_edges[level];
        if (!s.derived_from && !s.interior) {
            edges.assign(s.edge_ends.begin(), s.edge_ends.end());
            return;
        }
        edges.resize(2 * std::size_t(s.num_edges));
        for (Index e = 0; e < s.num_edges; ++e) s.edge_ends_of(e, &edges[2 * std::size_t(e)]);
    });
    return p.level_edges[level];
}
int Plan::level_num_vertices(int level) const {
    if (level < 0 || level > levels()) throw std::out_of_range("level_num_vertices: level " + std::to_string(level) + " is not in 0.." + std::to_string(levels()));
    return impl_->level_num_vertices[level];
}
const std::vector<VertexType>& Plan::level_vertex_types(int level) const {
    const PlanImpl& p = *impl_;
    const int last = p.options.levels > 0 || p.options.limit_surface ? p.options.levels : -1;
    if (level < 0 || level > last) throw std::out_of_range("level_vertex_types: level " + std::to_string(level) + " is not in 0.." + std::to_string(last));
    std::call_once(p.level_vertex_types_ready[level], [&p, level] {
        std::vector<VertexType>& copy = p.level_vertex_types_copies[level];
        if (level < int(p.level_vertex_types.size())) {
            copy.assign(p.level_vertex_types[level].begin(), p.level_vertex_types[level].end());
            return;
        }
        copy.assign(std::size_t(p.level_num_vertices.back()), VertexType::Smooth);
        for (const auto& [v, type] : p.last_level_types) copy[std::size_t(v)] = type;
    });
    return p.level_vertex_types_copies[level];
}

std::uint64_t Plan::estimate_bytes(int num_vertices, int num_triangles, int levels, int num_channels) {
    // Before the edges are known, a closed manifold's count stands in: three halves per triangle.
    const LevelCounts counts{std::uint64_t(std::max(num_vertices, 0)), std::uint64_t(std::max(num_triangles, 0)) * 3 / 2,
                             std::uint64_t(std::max(num_triangles, 0))};
    return estimate_for_counts(counts, levels, num_channels);
}


}  // namespace loopsub
