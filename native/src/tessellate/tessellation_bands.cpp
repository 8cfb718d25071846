// The bands of a tessellation's build: each band's submesh (its triangles and those around their corners, with the
// input's tags) and its control points' plan, patches and local refinement.
#include "tessellate/tessellation_builder.h"

#include <algorithm>

namespace loopsub::detail {

void TessellationBuilder::make_submesh(const LevelPatches& input, int band) {
    BandBuilder& bb = band_builders_[std::size_t(band)];
    std::vector<std::int32_t>& vertices = d_.bands[std::size_t(band)].vertices;
    std::vector<char> taken(std::size_t(mesh_.num_triangles), 0);
    for (int f = 0; f < mesh_.num_triangles; ++f)
        if (face_band_[std::size_t(f)] == band)
            for (int k = 0; k < 3; ++k) {
                const int v = mesh_.triangles[3 * f + k];
                for (const std::int32_t* c = input.corners_begin(v); c != input.corners_end(v); ++c)
                    taken[std::size_t(*c / 3)] = 1;
            }
    std::vector<std::int32_t> local(std::size_t(mesh_.num_vertices), -1);
    bb.face.assign(std::size_t(mesh_.num_triangles), -1);
    LocalMesh& sub = bb.mesh;
    std::vector<std::uint64_t> sub_edges;
    for (int f = 0; f < mesh_.num_triangles; ++f) {
        if (!taken[std::size_t(f)]) continue;
        bb.face[std::size_t(f)] = std::int32_t(sub.triangles.size() / 3);
        for (int k = 0; k < 3; ++k) {
            const std::int32_t v = mesh_.triangles[3 * f + k];
            if (local[std::size_t(v)] < 0) local[std::size_t(v)] = std::int32_t(vertices.size()), vertices.push_back(v);
            sub.triangles.push_back(local[std::size_t(v)]);
            sub_edges.push_back(detail::edge_key(v, mesh_.triangles[3 * f + (k + 1) % 3]));
        }
    }
    std::sort(sub_edges.begin(), sub_edges.end());
    for (int e = 0; e < mesh_.num_crease_edges; ++e) {
        const std::int32_t a = mesh_.crease_edges[2 * e], b = mesh_.crease_edges[2 * e + 1];
        if (!std::binary_search(sub_edges.begin(), sub_edges.end(), detail::edge_key(a, b))) continue;
        sub.creases.push_back(local[std::size_t(a)]), sub.creases.push_back(local[std::size_t(b)]);
        sub.crease_sharpness.push_back(mesh_.crease_sharpness[e]);
    }
    for (int k = 0; k < mesh_.num_corners; ++k)
        if (const std::int32_t v = local[std::size_t(mesh_.corner_vertices[k])]; v >= 0)
            sub.corners.push_back(v), sub.corner_sharpness.push_back(mesh_.corner_sharpness[k]);
    for (int k = 0; k < mesh_.num_cones; ++k)
        if (const std::int32_t v = local[std::size_t(mesh_.cone_vertices[k])]; v >= 0) sub.cones.push_back(v);
    bb.view = sub.view(int(vertices.size()));
}

void TessellationBuilder::make_control(int band) {
    TessellationImpl::Band& b = d_.bands[std::size_t(band)];
    BandBuilder& bb = band_builders_[std::size_t(band)];
    Options control = options_;
    control.limit_surface = false, control.levels = b.levels;
    b.control = std::make_unique<Plan>(bb.view, control);
    bb.patches = std::make_unique<LevelPatches>(*b.control);
    bb.local = std::make_unique<LocalRefiner>(*bb.patches, *b.control, control, bb.mesh.cones.data(),
                                              int(bb.mesh.cones.size()), refinement_bytes_);
}

}  // namespace loopsub::detail
