#include "tessellate/local_refinement.h"

#include <algorithm>

namespace loopsub::detail {

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
    return view;
}

struct LocalRefiner::Neighbourhood {
    std::vector<std::int32_t> vertices;  // local number -> the level's
    LocalMesh mesh;
    int face = 0;    // the face's local number
    int levels = 0;  // of the plan below
    std::shared_ptr<Plan> plan;
    std::vector<float> rows;  // per refined point, its weights over the local points
    std::shared_ptr<LevelPatches> patches;

    void refine(int to_levels, Options options, bool limit_surface) {
        options.levels = to_levels, options.limit_surface = limit_surface, options.threads = 1;
        const MeshView view = mesh.view(int(vertices.size()));
        patches.reset();
        plan = std::make_shared<Plan>(view, options);
        levels = to_levels;
        const int k = view.num_vertices;
        std::vector<float> identity(std::size_t(k) * std::size_t(k), 0.0f);
        for (int v = 0; v < k; ++v) identity[std::size_t(v) * std::size_t(k) + std::size_t(v)] = 1.0f;
        rows.assign(std::size_t(plan->num_output_vertices()) * std::size_t(k), 0.0f);
        plan->evaluate(interleaved(identity.data(), k), interleaved(rows.data(), k));
        if (!limit_surface) patches = std::make_shared<LevelPatches>(*plan);
    }

    // Adds `weight` times refined point q's weights to the sums (one per local point).
    void add_row(int q, double position, double ds, double dt, std::vector<double> sums[3]) const {
        const std::size_t k = vertices.size();
        const float* row = rows.data() + std::size_t(q) * k;
        for (std::size_t c = 0; c < k; ++c)
            sums[0][c] += position * row[c], sums[1][c] += ds * row[c], sums[2][c] += dt * row[c];
    }

    // The triangle of the refined level that holds the point, the point moved into it.
    int locate(FacePoint& point) const {
        int t = face;
        for (int l = 0; l < levels; ++l) t = 4 * t + descend(point);
        return t;
    }
};

LocalRefiner::LocalRefiner(const LevelPatches& level, const Plan& plan, const Options& options,
                           const std::int32_t* cones, int num_cones)
    : level_(level), options_(options) {
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

LocalRefiner::Neighbourhood& LocalRefiner::neighbourhood(int face) {
    std::unique_ptr<Neighbourhood>& cached = cache_[face];
    if (cached) return *cached;
    cached = std::make_unique<Neighbourhood>();
    Neighbourhood& n = *cached;
    const std::int32_t* triangles = level_.triangles();
    std::vector<int> faces;
    for (int k = 0; k < 3; ++k) {
        const int v = triangles[3 * face + k];
        for (const std::int32_t* c = level_.corners_begin(v); c != level_.corners_end(v); ++c) faces.push_back(*c / 3);
    }
    std::sort(faces.begin(), faces.end());
    faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
    std::unordered_map<std::int32_t, std::int32_t> local;
    for (int g : faces) {
        if (g == face) n.face = int(n.mesh.triangles.size() / 3);
        for (int k = 0; k < 3; ++k) {
            const std::int32_t v = triangles[3 * g + k];
            const auto [at, added] = local.try_emplace(v, std::int32_t(n.vertices.size()));
            if (added) n.vertices.push_back(v);
            n.mesh.triangles.push_back(at->second);
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

void LocalRefiner::weights(int face, FacePoint point, Stencil& out) {
    Neighbourhood& n = neighbourhood(face);
    const std::size_t k = n.vertices.size();
    std::vector<double> sums[3] = {std::vector<double>(k, 0.0), std::vector<double>(k, 0.0),
                                   std::vector<double>(k, 0.0)};
    bool found = false;
    for (;;) {
        if (!n.patches) n.refine(n.levels + 1, options_, false);
        FacePoint at = point;
        const int t = n.locate(at);
        Patch patch;
        found = n.patches->find_patch(t, patch);
        if (found) {
            PatchWeights weights;
            patch_weights(patch, double(at.S) / double(at.D), double(at.T) / double(at.D), weights);
            for (int i = 0; i < kBoxSplinePoints; ++i)
                if (patch.points[i] >= 0)
                    n.add_row(patch.points[i], weights.position[i], weights.ds[i], weights.dt[i], sums);
            break;
        }
        if (n.levels == kMaxLocalLevels) break;
        n.patches.reset();  // not regular yet: one level more
    }
    if (!found) {
        // A point that refinement does not bring into a regular patch (beside a non-manifold edge): the triangle
        // between its corners' limit points, refined to the deepest level.
        Neighbourhood limit = n;  // the same faces and tags, refined to the limit
        limit.refine(kMaxLocalLevels, options_, true);
        FacePoint at = point;
        const int t = limit.locate(at);
        const double s = double(at.S) / double(at.D), u = double(at.T) / double(at.D);
        const std::int32_t* corners = limit.plan->output_triangles() + 3 * t;
        limit.add_row(corners[0], 1.0 - s - u, -1.0, -1.0, sums);
        limit.add_row(corners[1], s, 1.0, 0.0, sums);
        limit.add_row(corners[2], u, 0.0, 1.0, sums);
    }
    out.clear();
    for (std::size_t c = 0; c < k; ++c)
        if (sums[0][c] != 0.0 || sums[1][c] != 0.0 || sums[2][c] != 0.0)
            out.add(n.vertices[c], sums[0][c], sums[1][c], sums[2][c]);
}

}  // namespace loopsub::detail
