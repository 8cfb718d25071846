#include "tessellate/local_refinement.h"

#include <algorithm>
#include <string>

#include "rules/rule_set.h"

namespace loopsub::detail {

namespace {

// What a level's LevelPatches hold per triangle, at most: its corners, their ranks and offsets, and its sharp edges in
// a hash map.
constexpr std::uint64_t kPatchBytesPerFace = 96;

}  // namespace

int descend(FacePoint& point) {
    const std::int64_t S = point.S, T = point.T, D = point.D;
    if (2 * S >= D) {  // corner child 1, (v1, m1, m0)
        point.S = 2 * T, point.T = 2 * D - 2 * S - 2 * T;
        return 1;
    }
    if (2 * T >= D) {  // corner child 2, (v2, m2, m1)
        point.S = 2 * D - 2 * T - 2 * S, point.T = 2 * S;
        return 2;
    }
    if (2 * (S + T) <= D) {  // corner child 0, (v0, m0, m2)
        point.S = 2 * S, point.T = 2 * T;
        return 0;
    }
    point.S = 2 * T - D + 2 * S, point.T = D - 2 * S;  // the middle child, (m0, m1, m2)
    return 3;
}

MeshView LocalMesh::view(int num_vertices) const {
    MeshView view;
    view.num_vertices = num_vertices;
    view.triangles = triangles.data(), view.num_triangles = int(triangles.size() / 3);
    view.crease_edges = creases.data(), view.crease_sharpness = crease_sharpness.data();
    view.num_crease_edges = int(crease_sharpness.size());
    view.corner_vertices = corners.data(), view.corner_sharpness = corner_sharpness.data();
    view.num_corners = int(corners.size());
    view.cone_vertices = cones.data(), view.num_cones = int(cones.size());
    view.triangle_edges = triangle_edges.empty() ? nullptr : triangle_edges.data();
    return view;
}

// A neighbourhood refined to some levels: its plan, and per refined point its weights over the local points.
struct LocalRefiner::Refined {
    std::shared_ptr<Plan> plan;
    int levels = 0;
    std::vector<float> rows;
    std::uint64_t bytes = 0;  // counted: the plan with one evaluation of every channel (the rows), and the patches

    // Adds `weight` times refined point q's weights to the sums (one per local point).
    void add_row(int q, double position, double ds, double dt, std::vector<double> sums[3]) const {
        const std::size_t k = sums[0].size();
        const float* row = rows.data() + std::size_t(q) * k;
        for (std::size_t c = 0; c < k; ++c)
            sums[0][c] += position * row[c], sums[1][c] += ds * row[c], sums[2][c] += dt * row[c];
    }
};

struct LocalRefiner::Neighbourhood {
    std::vector<std::int32_t> vertices;  // local number -> the level's
    LocalMesh mesh;
    int face = 0;  // the face's local number
    Refined control, limit;
    std::shared_ptr<LevelPatches> patches;  // of control

    // The triangle of the refined level that holds the point, the point moved into it.
    int locate(FacePoint& point, int levels) const {
        int t = face;
        for (int l = 0; l < levels; ++l) t = 4 * t + descend(point);
        return t;
    }
};

// The fans of a vertex's faces (joined across its edges of two faces that run against each other), and its edges.
struct LocalRefiner::Fans {
    struct Edge {
        std::int32_t end;
        int faces = 0, forward = 0;    // faces on it; of them, those that run from the vertex to `end`
        float sharpness = 0.0f;        // on the level as a plan of it reads it: boundary or non-manifold, or its tag
        std::vector<int> first_faces;  // its three lowest faces
        bool manifold() const { return faces == 2 && forward == 1; }
        bool sharp() const { return is_infinite(sharpness); }
        bool semi_sharp() const { return is_semi_sharp(sharpness); }
    };
    std::vector<int> face, fan;  // per corner of the vertex: its face and its fan
    std::vector<Edge> edges;
    // fins: edges of three faces or more; sharp, semi_sharp: edges infinitely and semi-sharp.
    int num_fans = 0, fins = 0, sharp = 0, semi_sharp = 0;
    float sharpness = 0.0f;  // the vertex's own, as a plan of the level reads it
    // A corner on every level whatever its semi-sharp edges: sharp itself, or on two fins and a third sharp edge.
    bool corner_forever = false;
    // Where the vertex's rule, or the decay of its semi-sharp edges, reads them: every fan of a semi-sharp edge kept.
    bool keeps_semi_sharp = false;
    bool reducible = false;  // non-manifold: other fans may be left out
    // The edge to `end` (edges are in the order of their ends), edges.size() where v has none.
    std::size_t edge(std::int32_t end) const {
        const auto e = std::lower_bound(edges.begin(), edges.end(), end,
                                        [](const Edge& edge, std::int32_t value) { return edge.end < value; });
        return e != edges.end() && e->end == end ? std::size_t(e - edges.begin()) : edges.size();
    }
};

LocalRefiner::LocalRefiner(const LevelPatches& level, const Plan& plan, const Options& options,
                           const std::int32_t* cones, int num_cones, RefinementBytes& bytes)
    : level_(level), options_(options), rules_(make_rule_set(options)), bytes_(bytes) {
    const auto& creases = plan.output_crease_edges();
    const auto& crease_sharpness = plan.output_crease_sharpness();
    for (std::size_t e = 0; e < crease_sharpness.size(); ++e)
        crease_tags_[edge_key(creases[2 * e], creases[2 * e + 1])] = crease_sharpness[e];
    const auto& corners = plan.output_corner_vertices();
    for (std::size_t k = 0; k < corners.size(); ++k) corner_tags_[corners[k]] = plan.output_corner_sharpness()[k];
    cone_.assign(std::size_t(plan.num_output_vertices()), false);
    for (int k = 0; k < num_cones; ++k) cone_[std::size_t(cones[k])] = true;
}

LocalRefiner::~LocalRefiner() = default;

// v's sharpness as a plan of the level reads it (RuleSet::base_vertex_sharpness), v non-manifold with `valence` edges
// of `edge_faces` faces in all, `fins` of them edges of three faces or more.
float LocalRefiner::vertex_sharpness(std::int32_t v, int valence, int edge_faces, int fins) const {
    const auto tag = corner_tags_.find(v);
    return rules_->base_vertex_sharpness(tag == corner_tags_.end() ? 0.0f : tag->second, true, valence,
                                         [=] { return std::pair<int, int>(edge_faces, fins); });
}

const LocalRefiner::Fans& LocalRefiner::fans(std::int32_t v) {
    std::unique_ptr<Fans>& found = fans_[v];
    if (found) return *found;
    found = std::make_unique<Fans>();
    Fans& f = *found;
    const std::int32_t* triangles = level_.triangles();
    std::vector<std::pair<std::int32_t, int>> ends;  // (the other end, the corner) per edge of each face at v
    for (const std::int32_t* c = level_.corners_begin(v); c != level_.corners_end(v); ++c) {
        const int g = *c / 3, k = *c % 3, i = int(f.face.size());
        f.face.push_back(g);
        ends.push_back({triangles[3 * g + (k + 1) % 3], 2 * i}),
            ends.push_back({triangles[3 * g + (k + 2) % 3], 2 * i + 1});
    }
    std::sort(ends.begin(), ends.end());
    std::vector<int> root(f.face.size());
    for (std::size_t i = 0; i < root.size(); ++i) root[i] = int(i);
    auto find = [&root](int i) {
        while (root[std::size_t(i)] != i) i = root[std::size_t(i)] = root[std::size_t(root[std::size_t(i)])];
        return i;
    };
    for (std::size_t i = 0; i < ends.size();) {
        Fans::Edge& e = f.edges.emplace_back();
        e.end = ends[i].first;
        const std::size_t first = i;
        for (; i < ends.size() && ends[i].first == e.end; ++i) {
            ++e.faces, e.forward += ends[i].second % 2 == 0;
            e.first_faces.push_back(f.face[std::size_t(ends[i].second / 2)]);
        }
        std::sort(e.first_faces.begin(), e.first_faces.end());
        e.first_faces.resize(std::min<std::size_t>(e.first_faces.size(), 3));
        if (e.manifold()) root[std::size_t(find(ends[first].second / 2))] = find(ends[first + 1].second / 2);
        const auto tag = crease_tags_.find(edge_key(v, e.end));
        e.sharpness = rules_->base_edge_sharpness(tag == crease_tags_.end() ? 0.0f : tag->second, e.faces,
                                                  e.faces > 1 && !e.manifold());
        f.fins += e.faces > 2, f.sharp += e.sharp(), f.semi_sharp += e.semi_sharp();
    }
    f.fan.resize(f.face.size());
    std::vector<int> number(f.face.size(), -1);
    for (std::size_t i = 0; i < f.face.size(); ++i) {
        int& n = number[std::size_t(find(int(i)))];
        if (n < 0) n = f.num_fans++;
        f.fan[i] = n;
    }
    const bool non_manifold = f.num_fans > 1 || std::any_of(f.edges.begin(), f.edges.end(), [](const Fans::Edge& e) {
                                  return !e.manifold() && e.faces > 1;
                              });
    hold(sizeof(Fans) + f.face.size() * 2 * sizeof(int) + f.edges.size() * (sizeof(Fans::Edge) + 3 * sizeof(int)) + 64,
         0, [] { return std::string("the fans around a vertex"); });  // with the map's node
    if (!non_manifold) return f;
    int edge_faces = 0;
    for (const Fans::Edge& e : f.edges) edge_faces += e.faces;
    f.sharpness = vertex_sharpness(v, int(f.edges.size()), edge_faces, f.fins);
    f.corner_forever = is_infinite(f.sharpness) || (f.fins == 2 && f.sharp > 2);
    f.keeps_semi_sharp = f.semi_sharp > 0 && (!f.corner_forever || rules_->decay_reads_other_edges());
    f.reducible = true;
    return f;
}

// The faces around v that shape `face`: all of them, or where v is non-manifold (above) the fans of face and of the
// faces that keep v's rule.
void LocalRefiner::add_faces_around(std::int32_t v, int face, std::vector<int>& faces) {
    const Fans& f = fans(v);
    if (!f.reducible) {
        faces.insert(faces.end(), f.face.begin(), f.face.end());
        return;
    }
    std::vector<char> kept(std::size_t(f.num_fans), 0);
    auto keep_fan_of = [&](int g) {
        for (std::size_t i = 0; i < f.face.size(); ++i)
            if (f.face[i] == g) kept[std::size_t(f.fan[i])] = 1;
    };
    keep_fan_of(face);
    const std::int32_t* triangles = level_.triangles();
    std::vector<char> touched(f.edges.size() + 1, 0);  // the edges of face's fan (and, last, v itself)
    for (std::size_t i = 0; i < f.face.size(); ++i)
        if (kept[std::size_t(f.fan[i])])
            for (int k = 0; k < 3; ++k) touched[f.edge(triangles[3 * f.face[i] + k])] = 1;
    // The edges that decide v's rule besides: with two fins, the crease they make; with more, three of them (still
    // more than two); a sharp edge that is no fin where there is one (a corner, not a crease; one of face's fan where
    // it has one); and where v's rule or their decay reads them, its semi-sharp edges.
    int fins = 0, other_sharp = -1;
    for (std::size_t e = 0; e < f.edges.size(); ++e) {
        const Fans::Edge& edge = f.edges[e];
        if (edge.faces > 2 && (f.fins == 2 || fins < 3)) touched[e] = 1, ++fins;
        if (edge.sharp() && edge.faces <= 2 && (other_sharp < 0 || (touched[e] && !touched[std::size_t(other_sharp)])))
            other_sharp = int(e);
        if (edge.semi_sharp() && f.keeps_semi_sharp) touched[e] = 1;
    }
    if (f.fins == 2 && other_sharp >= 0) touched[std::size_t(other_sharp)] = 1;
    for (std::size_t e = 0; e < f.edges.size(); ++e)
        if (touched[e])
            for (int g : f.edges[e].first_faces) keep_fan_of(g);
    if (std::count(kept.begin(), kept.end(), 1) == 1 && f.num_fans > 1)  // several fans and no fin: keep two
        kept[std::size_t(kept[0] ? 1 : 0)] = 1;
    for (std::size_t i = 0; i < f.face.size(); ++i)
        if (kept[std::size_t(f.fan[i])]) faces.push_back(f.face[i]);
}

// Whether v, among these faces, keeps what its rule and class on every level are read from (rules/rule_set.h): every
// edge of v here its face count (or three faces or more) and so its sharpness; v its own sharpness, being
// non-manifold; and then a corner on every level, or the same sharp edges (two fins) and every semi-sharp one.
bool LocalRefiner::keeps_rules(std::int32_t v, const std::vector<int>& faces) {
    const Fans& f = fans(v);
    std::vector<int> count(f.edges.size() + 1, 0);  // per edge (and, last, v itself)
    std::vector<char> fan_kept(std::size_t(f.num_fans), 0);
    const std::int32_t* triangles = level_.triangles();
    for (std::size_t i = 0; i < f.face.size(); ++i) {
        if (!std::binary_search(faces.begin(), faces.end(), f.face[i])) continue;
        fan_kept[std::size_t(f.fan[i])] = 1;
        for (int k = 0; k < 3; ++k) ++count[f.edge(triangles[3 * f.face[i] + k])];
    }
    int valence = 0, edge_faces = 0, fins = 0, sharp = 0, semi_sharp = 0;
    bool non_manifold = std::count(fan_kept.begin(), fan_kept.end(), 1) > 1;
    for (std::size_t e = 0; e < f.edges.size(); ++e) {
        if (count[e] == 0) continue;
        const Fans::Edge& edge = f.edges[e];
        // The same face count, or three faces or more (still non-manifold): the same sharpness.
        if (count[e] != edge.faces && (count[e] < 3 || edge.faces < 3)) return false;
        ++valence, edge_faces += count[e], fins += count[e] > 2;
        sharp += edge.sharp(), semi_sharp += edge.semi_sharp();
        non_manifold |= !edge.manifold();
    }
    if (!non_manifold || vertex_sharpness(v, valence, edge_faces, fins) != f.sharpness) return false;
    if (f.keeps_semi_sharp && semi_sharp != f.semi_sharp) return false;
    if (f.corner_forever) return is_infinite(f.sharpness) || (fins == 2 && sharp > 2);
    return fins == 2 && sharp == f.sharp;
}

LocalRefiner::Neighbourhood& LocalRefiner::neighbourhood(int face) {
    if (const auto found = cache_.find(face); found != cache_.end()) return *found->second;
    if (cached_bytes_ > kCachedBytes) cache_.clear(), bytes_.held -= cached_bytes_, cached_bytes_ = 0;
    std::unique_ptr<Neighbourhood>& cached = cache_[face];
    cached = std::make_unique<Neighbourhood>();
    Neighbourhood& n = *cached;
    const std::int32_t* triangles = level_.triangles();
    std::vector<int> faces;
    for (int k = 0; k < 3; ++k) add_faces_around(triangles[3 * face + k], face, faces);
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    bool whole = true;
    for (int k = 0; k < 3; ++k) {
        const std::int32_t v = triangles[3 * face + k];
        if (fans(v).reducible && !keeps_rules(v, faces)) whole = false;
    }
    if (!whole) {  // the fans left out changed a rule: all the faces around the corners
        faces.clear();
        for (int k = 0; k < 3; ++k) {
            const Fans& f = fans(triangles[3 * face + k]);
            faces.insert(faces.end(), f.face.begin(), f.face.end());
        }
        std::sort(faces.begin(), faces.end());
        faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    }
    std::unordered_map<std::int32_t, std::int32_t> local, local_edge;
    const std::int32_t* edges = level_.triangle_edges();
    for (int g : faces) {
        if (g == face) n.face = int(n.mesh.triangles.size() / 3);
        for (int k = 0; k < 3; ++k) {
            const std::int32_t v = triangles[3 * g + k];
            const auto [at, added] = local.try_emplace(v, std::int32_t(n.vertices.size()));
            if (added) n.vertices.push_back(v);
            n.mesh.triangles.push_back(at->second);
            if (edges)
                n.mesh.triangle_edges.push_back(
                    local_edge.try_emplace(edges[3 * g + k], std::int32_t(local_edge.size())).first->second);
        }
    }
    std::unordered_map<std::uint64_t, bool> seen;
    for (int g : faces)
        for (int k = 0; k < 3; ++k) {
            const std::int32_t a = triangles[3 * g + k], b = triangles[3 * g + (k + 1) % 3];
            const auto tag = crease_tags_.find(edge_key(a, b));
            if (tag == crease_tags_.end() || !seen.try_emplace(edge_key(a, b), true).second) continue;
            n.mesh.creases.push_back(local[a]), n.mesh.creases.push_back(local[b]);
            n.mesh.crease_sharpness.push_back(tag->second);
        }
    for (std::size_t i = 0; i < n.vertices.size(); ++i) {
        const std::int32_t v = n.vertices[i];
        if (const auto tag = corner_tags_.find(v); tag != corner_tags_.end())
            n.mesh.corners.push_back(std::int32_t(i)), n.mesh.corner_sharpness.push_back(tag->second);
        if (cone_[std::size_t(v)]) n.mesh.cones.push_back(std::int32_t(i));
    }
    return n;
}

template <typename What>
void LocalRefiner::hold(std::uint64_t bytes, std::uint64_t transient, What what) {
    const std::uint64_t needed = bytes_.held + bytes + transient;
    if (needed > bytes_.limit)
        throw MemoryLimitError("tessellation: " + what() + " would need about " + describe_bytes(needed) +
                                   " in all, more than the limit of " + describe_bytes(bytes_.limit),
                               needed);
    bytes_.held += bytes, bytes_.peak = std::max(bytes_.peak, needed);
}

void LocalRefiner::refine(Neighbourhood& n, Refined& r, int levels, bool limit_surface) {
    Options options = options_;
    options.levels = levels, options.limit_surface = limit_surface, options.threads = 1;
    const MeshView view = n.mesh.view(int(n.vertices.size()));
    const int k = view.num_vertices;
    // The plan with its rows, the patches of its triangles and, while it is made, the unit vectors.
    const std::uint64_t faces = std::uint64_t(view.num_triangles) << 2 * levels;
    const std::uint64_t bytes = Plan::estimate_bytes(k, view.num_triangles, levels, k) + faces * kPatchBytesPerFace;
    const std::uint64_t identity = std::uint64_t(k) * std::uint64_t(k) * sizeof(float);
    hold(bytes, identity, [&] {
        return "refining a neighbourhood of " + std::to_string(view.num_triangles) + " triangles " +
               std::to_string(levels) + " times";
    });
    cached_bytes_ += bytes;
    if (&r == &n.control) n.patches.reset();
    r.plan = std::make_shared<Plan>(view, options);
    r.levels = levels;
    std::vector<float> unit(std::size_t(k) * std::size_t(k), 0.0f);
    for (int v = 0; v < k; ++v) unit[std::size_t(v) * std::size_t(k) + std::size_t(v)] = 1.0f;
    r.rows.assign(std::size_t(r.plan->num_output_vertices()) * std::size_t(k), 0.0f);
    r.plan->evaluate(interleaved(unit.data(), k), interleaved(r.rows.data(), k));
    if (!limit_surface) n.patches = std::make_shared<LevelPatches>(*r.plan);
    bytes_.held -= r.bytes, cached_bytes_ -= r.bytes, r.bytes = bytes;
}

void LocalRefiner::weights(int face, FacePoint point, Stencil& out) {
    Neighbourhood& n = neighbourhood(face);
    const std::size_t k = n.vertices.size();
    std::vector<double> sums[3] = {std::vector<double>(k, 0.0), std::vector<double>(k, 0.0),
                                   std::vector<double>(k, 0.0)};
    bool found = false;
    for (;;) {
        if (!n.patches) refine(n, n.control, n.control.levels + 1, false);
        FacePoint at = point;
        const int t = n.locate(at, n.control.levels);
        Patch patch;
        found = n.patches->find_patch(t, patch);
        if (found) {
            PatchWeights weights;
            patch_weights(patch, double(at.S) / double(at.D), double(at.T) / double(at.D), weights);
            for (int i = 0; i < kBoxSplinePoints; ++i)
                if (patch.points[i] >= 0)
                    n.control.add_row(patch.points[i], weights.position[i], weights.ds[i], weights.dt[i], sums);
            break;
        }
        if (n.control.levels == kMaxLocalLevels) break;
        n.patches.reset();  // not regular yet: one level more
    }
    if (!found) {
        // A point that refinement does not bring into a regular patch (beside a non-manifold edge): the triangle
        // between its corners' limit points, the same faces and tags refined to the limit at the deepest level.
        if (!n.limit.plan) refine(n, n.limit, kMaxLocalLevels, true);
        FacePoint at = point;
        const int t = n.locate(at, kMaxLocalLevels);
        const double s = double(at.S) / double(at.D), u = double(at.T) / double(at.D);
        const std::int32_t* corners = n.limit.plan->output_triangles() + 3 * t;
        n.limit.add_row(corners[0], 1.0 - s - u, -1.0, -1.0, sums);
        n.limit.add_row(corners[1], s, 1.0, 0.0, sums);
        n.limit.add_row(corners[2], u, 0.0, 1.0, sums);
    }
    out.clear();
    for (std::size_t c = 0; c < k; ++c)
        if (sums[0][c] != 0.0 || sums[1][c] != 0.0 || sums[2][c] != 0.0)
            out.add(n.vertices[c], sums[0][c], sums[1][c], sums[2][c]);
}

}  // namespace loopsub::detail
