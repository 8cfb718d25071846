#include "plan/plan_builder.h"

#include <algorithm>
#include <cassert>
#include <limits>
#include <string>

#include "plan/budget.h"
#include "base/common.h"
#include "kernels/kernels.h"
#include "base/parallel.h"
#include "rules/rules.h"
#include "plan/validation.h"

namespace loopsub::detail {

namespace {

// LevelTables::Auto: past this size of stored tables of the level before the last, tables are derived instead. The
// size is counted as when that level's faces were built too (24 bytes per edge and face); a stored plan no longer
// builds them, but the count is kept so that Auto switches where it is documented (a result of about 20 M triangles).
constexpr std::uint64_t kDeriveAboveBytes = std::uint64_t(128) << 20;

// A level done with (its child planned): its edge list becomes its tables' edge ends, and its offsets their ring
// offsets where hand_over_tables left them to it (a level whose child derives its neighbourhoods from it keeps them);
// moved, not copied (docs/benchmark.md, "Measurements behind the code").
void hand_over_edges_and_offsets(Topology& level, LevelStencils& s) {
    s.edge_ends = std::move(level.edge_vertices);
    if (s.ring_offsets.empty()) s.ring_offsets = std::move(level.vertex_edge_offsets);
}

}  // namespace

VertexType classify_vertex(SdcRule rule, const FeatureVertex& vertex, const VertexNeighbourhood& around) {
    return hoppe94_vertex_type(rule, vertex.tagged_cone, [&] {
        CreaseFan fan{int(vertex.edges.size()), false, false, true, 0};
        for (Index e : vertex.edges) {
            const int faces = around.edge_face_count(e);
            fan.has_fin |= faces > 2;
            fan.on_boundary |= faces == 1;
        }
        fan.creases_on_boundary =
            around.edge_face_count(vertex.crease[0]) == 1 && around.edge_face_count(vertex.crease[1]) == 1;
        // The walk round the fan is defined where every edge has two faces.
        if (!fan.has_fin && !fan.on_boundary)
            fan.faces_on_one_side = around.faces_between(vertex.vertex, vertex.crease[0], vertex.crease[1]);
        return fan;
    });
}

// One level as plan_level's steps share it: the level being planned and its child.
struct PlanBuilder::Step {
    LevelState& level;           // its features; its connectivity where it is built (else num_vertices only)
    const Topology& parent;      // the level before it, through which `around` reads a level that is not built
    LevelState& child;           // receives the child level's features and connectivity
    int child_level;             // the child's number: 1 for the base's child
    bool last_child;             // the child is the last level and no limit pass follows: it needs its triangles only
    bool grandchild_last;        // likewise for the child's child
    VertexNeighbourhood around;  // this level's connectivity, wherever it is held
    int nv, ne;                  // this level's vertices and edges
    LevelStencils& tables;       // this level's, being filled
    LargeVector<VertexType>& types;  // this level's vertex classes
};

// Each thread's share of plan_feature_vertices, joined in vertex order after.
struct alignas(64) PlanBuilder::PartOutput {  // a cache line apart: each part pushes to its own
    std::vector<Feature> edges, vertices;     // child features
    std::vector<SpecialVertex> specials;
    std::vector<std::pair<Index, VertexType>> last_types;
    std::vector<float> child_sharpness;  // scratch of decay_into_child
};

// The halves of the level's feature edges that stay features: those of feature edge i (of level.edges) go to slots 2i
// and 2i + 1 (index -1: none), so that the child's edge features come out in order without a sort (docs/benchmark.md,
// "Measurements behind the code").
struct PlanBuilder::HalvesOfFeatures {
    std::vector<Feature> slots;
    // Whether half `half` (0 at the edge's first end) of the feature-th feature edge is sharp (an empty slot is not).
    bool sharp(std::size_t feature, int half) const {
        return is_sharp(slots[2 * feature + std::size_t(half)].sharpness);
    }
};

// What a feature vertex's child inherits: the sharpness of the halves of its edges at it and its own, decayed.
struct PlanBuilder::ChildOfVertex {
    const std::vector<float>& edge_sharpness;  // per edge of the vertex, in its order
    int num_sharp_edges;
    Index crease[2];  // the first two of the vertex's edges whose halves are sharp (-1: none)
    float vertex_sharpness;
};

std::unique_ptr<PlanImpl> PlanBuilder::build(const MeshView& mesh, const Options& options) {
    const auto start = Clock::now();
    validate_options(options);              // first: the team below starts `threads` threads
    const TeamScope team(options.threads);  // a kept team, or one whose threads start while the base level is built
    validate_mesh(mesh);
    auto plan = std::make_unique<PlanImpl>(options);
    PlanBuilder(mesh, *plan).run();
    plan->topology_ms = ms_since(start);
    return plan;
}

PlanBuilder::PlanBuilder(const MeshView& mesh, PlanImpl& plan)
    : mesh_(mesh), plan_(plan), options_(plan.options), rules_(make_rule_set(plan.options)) {
    plan_.kernel = resolve_kernel(options_.kernel);
    plan_.num_input_vertices = mesh.num_vertices;
    plan_.num_input_triangles = mesh.num_triangles;
    plan_.level_num_vertices.push_back(mesh.num_vertices);
}

void PlanBuilder::run() {
    LevelState level = base_level();
    const std::uint64_t needed = check_memory(level.topology);
    if (options_.levels > 0)
        plan_.input_triangle_edges.assign(level.topology.face_edges.begin(), level.topology.face_edges.end());
    std::vector<FaceVaryingBuilder> layers;
    for (int k = 0; k < mesh_.num_face_varying; ++k) layers.emplace_back(mesh_, k, options_, level);
    choose_table_forms(level, !layers.empty());
    Topology parent;  // the level before `level`: the next-to-last level derives its neighbourhoods from it
    for (int l = 0; l < options_.levels; ++l) {
        LevelState child;
        plan_level(level, parent, child, l + 1);
        const bool last = l + 1 == options_.levels;
        for (FaceVaryingBuilder& layer : layers)
            layer.plan_level(level, skip_level_before_last_ && last ? &parent : nullptr, plan_.stencils[l], child,
                             last);
        if (limit_from_grandparent_ && last) {
            plan_limit_rings(parent);
            // The last level's vertices next to tags are classified, and their sides found, through the level before
            // the last, itself read through the grandparent (`parent` here), before its arrays go to the tables.
            plan_limit(child, parent);
        }
        retire_parent(parent, l);
        parent = std::move(level.topology);
        level = std::move(child);
    }
    if (options_.limit_surface && !limit_from_grandparent_) plan_limit(level, parent);
    assert(!limit_from_grandparent_ || plan_.limit->from_grandparent->grandparent.edge_vertices ==
                                           plan_.stencils[plan_.stencils.size() - 2].edge_ends.data());
    for (FaceVaryingBuilder& layer : layers) {
        if (options_.limit_surface) layer.plan_limit(*plan_.limit, level, *rules_);
        plan_.face_varying.push_back(layer.finish());
    }
    if (options_.levels > 0 && !skip_level_before_last_) hand_over_edges_and_offsets(parent, plan_.stencils.back());
    plan_.output_triangles = std::move(level.topology.face_vertices);
    if (!plan_.holes.empty()) drop_holes();
    collect_output_tags(level);
    assert(std::all_of(plan_.stencils.begin(), plan_.stencils.end(), follows_table_layout));
    assert(!plan_.limit || plan_.limit->from_grandparent || follows_table_layout(plan_.limit->positions));
    kept_base_ = Topology();  // back to the pool before a large plan empties it
    if (needed > 4 * BlockPool::kPoolBytes) BlockPool::instance().release_all(free_block);
}

LevelState PlanBuilder::base_level() {
    LevelState level;
    level.topology = build_base_topology(mesh_.triangles, mesh_.num_triangles, mesh_.num_vertices, options_.threads,
                                         mesh_.triangle_edges);
    const Topology& t = level.topology;

    std::vector<float> edge_tag(t.num_edges(), 0.0f);
    check_crease_edges(t, mesh_, ThrowFirst{}, [&](int k, Index e) {
        edge_tag[e] = mesh_.crease_sharpness[k];  // a repeated tag overrides, as in OpenSubdiv
    });
    check_windings(t, [this](const InputProblem& note) {
        plan_.notes.push_back(note);
        return true;
    });
    if (mesh_.num_holes > 0) {
        plan_.holes.assign(mesh_.num_triangles, 0);
        for (int k = 0; k < mesh_.num_holes; ++k) plan_.holes[mesh_.hole_triangles[k]] = 1;
    }
    std::vector<float> vertex_tag(t.num_vertices, 0.0f);
    for (int k = 0; k < mesh_.num_corners; ++k) vertex_tag[mesh_.corner_vertices[k]] = mesh_.corner_sharpness[k];
    if (rules_->has_cones()) {
        cones_.assign(mesh_.cone_vertices, mesh_.cone_vertices + mesh_.num_cones);
        std::sort(cones_.begin(), cones_.end());
        cones_.erase(std::unique(cones_.begin(), cones_.end()), cones_.end());
    }

    // Features: what the tags make sharp, and what the topology makes sharp on top of them (the rules decide both).
    // Untagged regular edges and vertices stay off the lists, as most are, and cost no call of a virtual function
    // (docs/benchmark.md, "Measurements behind the code").
    const std::vector<std::uint8_t> non_manifold_edge = non_manifold_edges(t);
    const std::vector<std::uint8_t> non_manifold_vertex = non_manifold_vertices(t, non_manifold_edge, options_.threads);
    closed_ = t.max_edge_face_count == 2 && t.edge_face_offsets[t.num_edges()] == 2 * t.num_edges() &&
              std::none_of(non_manifold_edge.begin(), non_manifold_edge.end(), [](std::uint8_t flag) { return flag; });
    std::vector<std::uint8_t> leaves_surface;  // per vertex, where a boundary edge takes its faces out (Boundary::None)
    for (int e = 0; e < t.num_edges(); ++e) {
        const float tag = edge_tag[e];
        const int faces = t.edge_face_count(e);
        const Index a = t.edge_vertices[2 * e], b = t.edge_vertices[2 * e + 1];
        const float sharpness = rules_->base_edge_sharpness(tag, faces, non_manifold_edge[e] != 0);
        if (sharpness > 0.0f || tag != 0.0f) level.edges.push_back({Index(e), sharpness, tag, {a, b}});
        if (rules_->boundary_edge_removes_faces(tag, faces)) {
            leaves_surface.resize(t.num_vertices, 0);
            leaves_surface[a] = leaves_surface[b] = 1;
        }
    }
    for (int v = 0; v < t.num_vertices; ++v) {
        const float tag = vertex_tag[v];
        const float sharpness = rules_->base_vertex_sharpness(tag, non_manifold_vertex[v] != 0, t.valence(v), [&t, v] {
            int edge_faces = 0, fins = 0;
            for (Index k = t.vertex_edge_offsets[v]; k < t.vertex_edge_offsets[v + 1]; ++k) {
                const int faces = t.edge_face_count(t.vertex_edges[k]);
                edge_faces += faces;
                fins += faces > 2;
            }
            return std::pair<int, int>(edge_faces, fins);
        });
        if (sharpness > 0.0f || tag != 0.0f) level.vertices.push_back({Index(v), sharpness, tag});
    }
    if (!leaves_surface.empty()) {
        for (int f = 0; f < t.num_faces(); ++f)
            for (int k = 0; k < 3; ++k)
                if (leaves_surface[t.face_vertices[3 * f + k]]) {
                    plan_.holes.resize(t.num_faces(), 0);
                    plan_.holes[f] = 1;
                }
    }
    return level;
}

std::uint64_t PlanBuilder::check_memory(const Topology& base) const {
    const LevelCounts counts = base_counts(base);
    LevelCounts last = counts;
    for (int l = 0; l < options_.levels; ++l) last = last.child();
    const std::uint64_t needed = estimate_for_counts(counts, options_.levels, 3);
    const std::uint64_t index_limit = std::uint64_t(std::numeric_limits<Index>::max());
    const std::string request =
        "subdividing " + std::to_string(mesh_.num_triangles) + " triangles " + std::to_string(options_.levels) +
        " times gives " + (last.faces == kSaturated ? std::string("more than 2^64") : std::to_string(last.faces)) +
        " triangles";
    if (needed > options_.memory_limit_bytes)
        throw MemoryLimitError(request + " and would need about " + describe_bytes(needed) +
                                   ", more than the limit of " + describe_bytes(options_.memory_limit_bytes),
                               needed);
    if (mul(3, last.faces) > index_limit || mul(2, last.edges) > index_limit)
        throw MemoryLimitError(
            request + ", more than 32-bit indices can address (about " + describe_bytes(needed) + " would be needed)",
            needed);
    return needed;
}

void PlanBuilder::choose_table_forms(const LevelState& base_level, bool face_varying_layers) {
    const Topology& base = base_level.topology;
    // Every vertex a split makes off a boundary or a sharp edge has six neighbours in one disk, and the last level's
    // rings follow from its grandparent through the numbering. Stored tables store them. Its vertices next to tags
    // and boundaries are classified through the level before the last's connectivity (plan_limit); so are those next
    // to a non-manifold place (an edge of three faces or more, or whose faces wind against each other; a vertex of
    // several fans), which the rules make sharp, the only vertices whose rings the grandparent's faces do not give.
    limit_from_grandparent_ = options_.limit_surface && options_.levels >= 2 &&
                              options_.level_tables != LevelTables::Stored && plan_.holes.empty();
    // Without a limit surface to plan over two levels or more, or with one from the grandparent, the level before the
    // last is never built.
    skip_level_before_last_ = options_.levels >= 2 && (!options_.limit_surface || limit_from_grandparent_);
    // Options::level_tables. Auto: an evaluation from stored tables is faster (docs/benchmark.md), so a plan keeps
    // them up to where its memory, and its build time, matter more; a plan with face-varying layers keeps them.
    LevelCounts last_but_one = base_counts(base);
    for (int l = 1; l < options_.levels; ++l) last_but_one = last_but_one.child();
    const std::uint64_t stored_tables = mul(24, add(last_but_one.edges, last_but_one.faces));  // ring, edges, faces
    derive_tables_ = skip_level_before_last_ && !options_.limit_surface && !face_varying_layers &&
                     (options_.level_tables == LevelTables::Derived ||
                      (options_.level_tables == LevelTables::Auto && stored_tables > kDeriveAboveBytes));
}

LevelCounts PlanBuilder::base_counts(const Topology& base) const {
    return {std::uint64_t(mesh_.num_vertices), std::uint64_t(base.num_edges()), std::uint64_t(mesh_.num_triangles)};
}

void PlanBuilder::plan_level(LevelState& level, const Topology& parent, LevelState& child, int child_level) {
    // With the limit surface, the last level is planned like the others, its limit pass standing in for a child.
    // From the grandparent, the limit needs no level of its own.
    const int final_level = options_.levels + (options_.limit_surface && !limit_from_grandparent_ ? 1 : 0);
    const VertexNeighbourhood around(level.topology, level.own_neighbourhood ? nullptr : &parent,
                                     &plan_.level_num_vertices, base_for_walks_);
    LevelStencils& tables = start_tables(around, level.topology.num_vertices);
    LargeVector<VertexType>& types =
        plan_.level_vertex_types.emplace_back(level.topology.num_vertices, VertexType::Smooth);
    Step step{level,
              parent,
              child,
              child_level,
              child_level == final_level,
              child_level + 1 == final_level,
              around,
              level.topology.num_vertices,
              around.num_edges(),
              tables,
              types};
    HalvesOfFeatures halves{std::vector<Feature>(2 * level.edges.size(), Feature{-1, 0.0f, 0.0f})};
    plan_feature_vertices(step, halves);
    if (step.last_child) classify_last_midpoints(step, halves);
    refine_child(step);
    plan_edge_masks(step, halves);
    hand_over_tables(step);
    // Last: the neighbourhoods above read this list's end as this level's count (VertexNeighbourhood's history).
    plan_.level_num_vertices.push_back(child.topology.num_vertices);
}

LevelStencils& PlanBuilder::start_tables(const VertexNeighbourhood& around, int num_vertices) {
    LevelStencils& s = plan_.stencils.emplace_back();
    s.num_vertices = num_vertices;
    s.num_edges = around.num_edges();
    const int max_valence = around.max_valence();
    plan_.max_summed_terms =
        std::max(plan_.max_summed_terms, std::max(max_valence, 2));  // a ring, or an edge's two ends
    set_smooth_masks(s, max_valence, smooth_vertex_mask);
    return s;
}

// Only vertices next to a feature (or cones) can differ from the smooth pass; they alone are visited, on threads.
void PlanBuilder::plan_feature_vertices(Step& step, HalvesOfFeatures& halves) const {
    std::vector<PartOutput> parts(feature_vertex_parts(options_.threads));
    for_each_feature_vertex(
        step.level, cones_, step.around,
        [&](const FeatureVertex& vertex, int part) {
            PartOutput& out = parts[part];
            const ChildOfVertex child = decay_into_child(step, vertex, out, halves);
            const SdcRule rule = sdc_vertex_rule(vertex.own_sharpness(), vertex.num_sharp_edges);
            step.types[vertex.vertex] = classify_vertex(rule, vertex, step.around);
            // The last level is refined no further, but its classes are reported too (what the result is tagged with):
            // an old vertex's from its child sharpness, over this level's neighbourhoods.
            if (step.last_child) {
                const FeatureVertex as_child{vertex.vertex,         vertex.edges,
                                             child.edge_sharpness,  vertex.tags,
                                             child.num_sharp_edges, {child.crease[0], child.crease[1]},
                                             vertex.tagged_cone};
                out.last_types.push_back(
                    {vertex.vertex, classify_vertex(sdc_vertex_rule(child.vertex_sharpness, child.num_sharp_edges),
                                                    as_child, step.around)});
            }
            add_vertex_mask(step, vertex, rule, child, out.specials);
        },
        options_.threads);
    join_parts(step, parts, halves);
}

// The child's features from a vertex: the half of each edge at it, its sharpness decayed at this end (Chaikin looks at
// the other edges there), and the vertex itself, decayed. Edges inside faces and vertices on edges start smooth.
PlanBuilder::ChildOfVertex PlanBuilder::decay_into_child(const Step& step, const FeatureVertex& vertex, PartOutput& out,
                                                         HalvesOfFeatures& halves) const {
    std::vector<float>& child_sharpness = out.child_sharpness;
    const Index v = vertex.vertex;
    const int valence = int(vertex.edges.size());
    child_sharpness.resize(valence);
    int num_child_sharp_edges = 0;
    Index child_crease[2] = {-1, -1};
    for (int k = 0; k < valence; ++k) {
        const Index e = vertex.edges[k];
        const float decayed = rules_->child_edge_sharpness(vertex.sharpness[k], vertex.sharpness.data(), valence);
        child_sharpness[k] = decayed;
        if (is_sharp(decayed) && num_child_sharp_edges++ < 2) child_crease[num_child_sharp_edges - 1] = e;
        const float child_tag = rules_->child_tag(vertex.tags[k], decayed);
        if (!(decayed > 0.0f || child_tag != 0.0f)) continue;
        const Index half_index = step.around.child_edge_at(e, v), m = step.nv + e;  // half 2e = (a, m), 2e + 1 = (m, b)
        const Feature half{half_index, decayed, child_tag, {half_index & 1 ? m : v, half_index & 1 ? v : m}};
        if (const Feature* feature = (*vertex.edge_features)[k])
            halves.slots[2 * std::size_t(feature - step.level.edges.data()) + std::size_t(half.index & 1)] = half;
        else out.edges.push_back(half);
    }
    const float child_vertex_sharpness = rules_->child_vertex_sharpness(vertex.own_sharpness());
    const float child_vertex_tag = rules_->child_tag(vertex.own_tag(), child_vertex_sharpness);
    if (child_vertex_sharpness > 0.0f || child_vertex_tag != 0.0f)
        out.vertices.push_back({v, child_vertex_sharpness, child_vertex_tag});
    return {child_sharpness, num_child_sharp_edges, {child_crease[0], child_crease[1]}, child_vertex_sharpness};
}

// The vertex point's mask, kept where it is not the smooth pass's.
void PlanBuilder::add_vertex_mask(const Step& step, const FeatureVertex& vertex, SdcRule rule,
                                  const ChildOfVertex& child, std::vector<SpecialVertex>& specials) const {
    const Index v = vertex.vertex;
    const int valence = int(vertex.edges.size());
    const VertexMask smooth = smooth_vertex_mask(valence);
    Index ends[2];
    const VertexMask mask = rules_->vertex_mask({step.types[v],
                                                 rule,
                                                 valence,
                                                 vertex.own_sharpness(),
                                                 child.vertex_sharpness,
                                                 vertex.sharpness.data(),
                                                 child.edge_sharpness.data(),
                                                 child.num_sharp_edges,
                                                 {vertex.crease[0], vertex.crease[1]},
                                                 {child.crease[0], child.crease[1]}},
                                                ends);
    if (mask.self != smooth.self || mask.ring != smooth.ring || mask.crease != 0.0) {
        const bool has_ends = mask.crease != 0.0;
        specials.push_back({v, has_ends ? step.around.other_end(ends[0], v) : v,
                            has_ends ? step.around.other_end(ends[1], v) : v, float(mask.self), float(mask.ring),
                            float(mask.crease), float(mask.crease)});
    }
}

void PlanBuilder::join_parts(Step& step, std::vector<PartOutput>& parts, const HalvesOfFeatures& halves) const {
    std::size_t joined[4] = {halves.slots.size(), 0, 0, 0};  // upper bounds: the joins then move nothing twice
    for (const PartOutput& out : parts) {
        joined[0] += out.edges.size(), joined[1] += out.vertices.size();
        joined[2] += out.specials.size(), joined[3] += out.last_types.size();
    }
    step.child.edges.reserve(joined[0]);
    step.child.vertices.reserve(joined[1]);
    step.tables.special_vertices.reserve(joined[2]);
    plan_.last_level_types.reserve(joined[3] + (step.last_child ? step.level.edges.size() : 0));
    for (const Feature& half : halves.slots)
        if (half.index >= 0) step.child.edges.push_back(half);
    bool unsorted = false;  // halves of edges that were no feature (a rule set that sharpens them)
    for (const PartOutput& out : parts) {
        unsorted |= !out.edges.empty();
        step.child.edges.insert(step.child.edges.end(), out.edges.begin(), out.edges.end());
        step.child.vertices.insert(step.child.vertices.end(), out.vertices.begin(), out.vertices.end());
        step.tables.special_vertices.insert(step.tables.special_vertices.end(), out.specials.begin(),
                                            out.specials.end());
        plan_.last_level_types.insert(plan_.last_level_types.end(), out.last_types.begin(), out.last_types.end());
    }
    if (unsorted)
        std::sort(step.child.edges.begin(),
                  step.child.edges.end());  // vertices were visited in order: child.vertices is sorted
}

// The last level's midpoints on sharp edges (its old vertices' classes come from plan_feature_vertices). A midpoint's
// only edges that can be sharp are its two halves, and its fan is its edge's faces, three child faces each between
// the halves.
void PlanBuilder::classify_last_midpoints(const Step& step, const HalvesOfFeatures& halves) const {
    for (std::size_t i = 0; i < step.level.edges.size(); ++i) {
        const Feature& f = step.level.edges[i];
        const int sharp_halves = halves.sharp(i, 0) + halves.sharp(i, 1);
        if (sharp_halves == 0) continue;
        const int faces = step.around.edge_face_count(f.index);
        const CreaseFan fan{2 + 2 * faces, faces > 2, faces == 1, faces == 1, 3};
        plan_.last_level_types.push_back({step.nv + f.index, hoppe94_vertex_type(sdc_vertex_rule(0.0f, sharp_halves),
                                                                                 false, [&fan] { return fan; })});
    }
}

// The last level needs only its triangles. The one before it needs its tables, but not its edge faces and vertex edges
// (a third of its memory traffic): the few vertices it classifies take them from this level. Where nothing else is
// refined (skip_level_before_last_), the level before the last is not built at all: its child's triangles come from
// this level through the numbering, as its tables do. With derived tables the other levels keep their connectivity
// only.
void PlanBuilder::refine_child(Step& step) const {
    Topology& child = step.child.topology;
    const Topology& parent = step.parent;
    if (skip_level_before_last_ && step.grandchild_last) {
        child.num_vertices = step.nv + step.ne;
    } else if (skip_level_before_last_ && step.last_child) {
        child.num_vertices = step.nv + step.ne;
        child.face_vertices.resize(48 * std::size_t(parent.num_faces()));
        if (derive_tables_) {  // else written beside this level's tables (fill_tables_from_parent, hand_over_tables)
            run_levels(std::max(1, options_.threads), 1, [&](int, int part, int parts) {
                const auto [f0, f1] = part_of(parent.num_faces(), part, parts);
                write_grandchild_faces(parent, f0, f1, child.face_vertices.data());
            });
        }
    } else {
        // With the limit surface the last level is the grandchild's parent: its pass reads rings, which plan_limit
        // writes from this level's parent, and its few vertices next to features are read through that parent.
        child = refine_topology(step.level.topology,
                                step.last_child || step.grandchild_last ? Refined::FacesOnly
                                : derive_tables_                        ? Refined::Connectivity
                                                                        : Refined::Full,
                                options_.threads);
    }
    step.child.own_neighbourhood = !step.grandchild_last;
}

// Edge points: the smooth pass gives every edge the smooth mask; sharp edges may take another.
void PlanBuilder::plan_edge_masks(Step& step, const HalvesOfFeatures& halves) const {
    for (std::size_t i = 0; i < step.level.edges.size(); ++i) {
        const Feature& feature = step.level.edges[i];
        if (!is_sharp(feature.sharpness)) continue;
        const Index a = feature.ends[0], b = feature.ends[1];
        const bool halves_sharp = halves.sharp(i, 0) && halves.sharp(i, 1);
        const EdgeMask mask = rules_->edge_mask({feature.sharpness, step.types[a], step.types[b],
                                                 step.around.edge_face_count(feature.index), halves_sharp});
        if (!(mask == smooth_edge_mask()))
            step.tables.special_edges.push_back({feature.index, float(mask.a), float(mask.b), float(mask.wings)});
    }
}

// What the tables keep of the level, moved rather than copied, by their form (LevelStencils). A level planned further
// keeps its offsets until its child is planned (its neighbourhoods may be derived from this level), then
// retire_parent hands them over; with derived tables the level after the base keeps the base whole, so the base's
// tables copy them. Derived tables (levels past the base) are not stored; those of a level not built are filled from
// its parent.
void PlanBuilder::hand_over_tables(Step& step) const {
    Topology& t = step.level.topology;
    LevelStencils& s = step.tables;
    if (skip_level_before_last_ && step.last_child && !derive_tables_) {
        fill_tables_from_parent(step.parent, s, step.child.topology.face_vertices.data(), options_.threads);
    } else if (!derive_tables_ || step.child_level == 1) {
        if (step.last_child) s.ring_offsets = std::move(t.vertex_edge_offsets);
        else if (derive_tables_) s.ring_offsets = t.vertex_edge_offsets;
        s.ring = std::move(t.vertex_vertices);
        s.edge_wing_c = std::move(t.edge_wing_c);
        s.edge_wing_d = std::move(t.edge_wing_d);
    }
    if (step.child_level >= 2 && !derive_tables_) {  // a split level, its rings as the fan kernels read them
        s.fan_first_midpoint = step.parent.num_vertices;
        s.fan_midpoints = step.nv - step.parent.num_vertices;
    }
}

// The level before `level` is done with once `level`'s child is planned: its edge list, which served its child's
// neighbourhoods, becomes its tables' edge ends; with derived tables a level's tables keep the whole level before (the
// base's tables their own edge list). Its faces go to the last level's tables where those read them.
void PlanBuilder::retire_parent(Topology& parent, int l) {
    std::vector<LevelStencils>& stencils = plan_.stencils;
    if (derive_tables_ && l > 0) {
        if (l == 1) stencils[0].edge_ends = parent.edge_vertices;
        stencils[l].derived_from = std::make_unique<Topology>(std::move(parent));
    } else if (l > 0) {
        hand_over_edges_and_offsets(parent, stencils[l - 1]);
    }
    if (stencils[l].interior) {  // the tables of the level before the last read the faces of its parent
        stencils[l].interior->face_vertices = std::move(parent.face_vertices);
        stencils[l].interior->face_edges = std::move(parent.face_edges);
    }
    if (l == 1) {  // the base, done with: its faces stay for the walks around its vertices on later levels
        if (stencils[1].derived_from) base_for_walks_ = stencils[1].derived_from.get();
        else if (!stencils[1].interior) base_for_walks_ = &(kept_base_ = std::move(parent));
    }
}

void PlanBuilder::drop_holes() {
    // Triangle t of the last level descends from input triangle t / 4^levels.
    const int shift = 2 * options_.levels;
    const std::size_t count = plan_.output_triangles.size() / 3;
    assert(count == std::size_t(plan_.num_input_triangles) << shift);
    std::vector<Index> renumbered(count, -1);
    LargeVector<Index>& kept = plan_.kept_triangles;
    for (std::size_t t = 0; t < count; ++t) {
        if (plan_.holes[t >> shift]) continue;
        renumbered[t] = Index(kept.size());
        kept.push_back(Index(t));
    }
    auto compact = [&kept](LargeVector<Index>& corners) {
        for (std::size_t k = 0; k < kept.size(); ++k)
            for (int c = 0; c < 3; ++c) corners[3 * k + c] = corners[3 * std::size_t(kept[k]) + c];
        corners.resize(3 * kept.size());
    };
    compact(plan_.output_triangles);
    for (FaceVaryingPlan& layer : plan_.face_varying) compact(layer.output_corner_values);
    if (plan_.limit) {
        std::vector<std::pair<Index, Index>> kept_sides;
        for (const auto& [corner, row] : plan_.limit->corner_sides)
            if (renumbered[corner / 3] >= 0) kept_sides.push_back({3 * renumbered[corner / 3] + corner % 3, row});
        plan_.limit->corner_sides = std::move(kept_sides);
    }
}

void PlanBuilder::collect_output_tags(const LevelState& last) {
    OutputTags& tags = plan_.output_tags;
    for (const Feature& f : last.edges) {
        if (f.sharpness > 0.0f) {
            tags.sharp_edges.push_back(f.ends[0]);
            tags.sharp_edges.push_back(f.ends[1]);
            tags.sharp_edge_sharpness.push_back(f.sharpness);
            tags.sharp_edge_indices.push_back(f.index);
        }
        if (f.tag <= 0.0f) continue;
        tags.crease_edges.push_back(f.ends[0]);
        tags.crease_edges.push_back(f.ends[1]);
        tags.crease_sharpness.push_back(f.tag);
        tags.crease_edge_indices.push_back(f.index);
    }
    for (const Feature& f : last.vertices) {
        if (f.tag <= 0.0f) continue;
        tags.corner_vertices.push_back(f.index);
        tags.corner_sharpness.push_back(f.tag);
    }
}

}  // namespace loopsub::detail
