// A tessellation's face-varying layers, each cut as a surface of its own whose face points are the surface's.
#include <algorithm>
#include <string>
#include <unordered_map>

#include "tessellate/kept_input.h"
#include "tessellate/local_refinement.h"
#include "rules/face_varying_rules.h"
#include "tessellate/tessellation_data.h"

namespace loopsub {

namespace {

// The input's tags and edge rates, looked up by edge or vertex as the layers' meshes take them.
struct InputTags {
    std::unordered_map<std::uint64_t, float> crease_of;
    std::unordered_map<std::int32_t, float> corner_of;
    std::vector<bool> cone;
    std::vector<int> faces_at;
    std::unordered_map<std::uint64_t, int> rate_of;
};

InputTags input_tags(const MeshView& mesh, const TessellationRates& rates) {
    InputTags in;
    for (int e = 0; e < mesh.num_crease_edges; ++e)
        in.crease_of[detail::edge_key(mesh.crease_edges[2 * e], mesh.crease_edges[2 * e + 1])] =
            mesh.crease_sharpness[e];
    for (int k = 0; k < mesh.num_corners; ++k) in.corner_of[mesh.corner_vertices[k]] = mesh.corner_sharpness[k];
    in.cone.assign(std::size_t(mesh.num_vertices), false);
    for (int k = 0; k < mesh.num_cones; ++k) in.cone[std::size_t(mesh.cone_vertices[k])] = true;
    in.faces_at.assign(std::size_t(mesh.num_vertices), 0);
    for (std::size_t c = 0; c < 3 * std::size_t(mesh.num_triangles); ++c) ++in.faces_at[std::size_t(mesh.triangles[c])];
    for (int e = 0; e < rates.num_edges; ++e)
        in.rate_of[detail::edge_key(rates.edges[2 * e], rates.edges[2 * e + 1])] = rates.rates[e];
    return in;
}

// A layer's input level as a mesh of its own, with the input's tags where they apply to its values, and its edges
// with the rates of the mesh edges they lie on.
struct LayerMesh {
    detail::LocalMesh tags;
    std::vector<std::int32_t> edges, edge_rates;
};

LayerMesh tagged_layer_mesh(const MeshView& mesh, const Options& options, const TessellationRates& rates,
                            const InputTags& input, const Plan::FaceVaryingBase& base) {
    const std::size_t corners = 3 * std::size_t(mesh.num_triangles);
    const int n = int(base.values.size());
    std::vector<std::int32_t> vertex_of(static_cast<std::size_t>(n));
    for (std::size_t c = 0; c < corners; ++c) vertex_of[std::size_t(base.corner_values[c])] = mesh.triangles[c];
    LayerMesh out;
    detail::LocalMesh& tags = out.tags;
    std::unordered_map<std::uint64_t, bool> seen;
    for (std::size_t c = 0; c < corners; ++c) {
        const std::size_t next = c - c % 3 + (c + 1) % 3;
        const std::int32_t x = base.corner_values[c], y = base.corner_values[next];
        if (!seen.try_emplace(detail::edge_key(x, y), true).second) continue;
        const std::uint64_t key = detail::edge_key(mesh.triangles[c], mesh.triangles[next]);
        if (const auto crease = input.crease_of.find(key); crease != input.crease_of.end())
            tags.creases.insert(tags.creases.end(), {x, y}), tags.crease_sharpness.push_back(crease->second);
        const auto rate = input.rate_of.find(key);
        out.edges.insert(out.edges.end(), {x, y}),
            out.edge_rates.push_back(rate != input.rate_of.end() ? rate->second : rates.uniform_rate);
    }
    for (std::int32_t x = 0; x < n; ++x) {
        const std::int32_t v = vertex_of[std::size_t(x)];
        const auto corner = input.corner_of.find(v);
        const detail::FaceVaryingLayerTag tag = detail::face_varying_layer_tag(
            base.classes[std::size_t(x)], corner != input.corner_of.end() ? corner->second : 0.0f,
            input.cone[std::size_t(v)],
            options.boundary == Boundary::EdgesAndCorners && input.faces_at[std::size_t(v)] == 1);
        if (tag.cone) tags.cones.push_back(x);
        if (tag.sharpness > 0.0f) tags.corners.push_back(x), tags.corner_sharpness.push_back(tag.sharpness);
    }
    tags.triangles = base.corner_values;
    return out;
}

// Layer k's mesh cut at its edges' rates into `layer`, whose face points must be the surface's (d's).
void cut_layer(TessellationImpl& d, int k, const LayerMesh& layer_mesh, int num_values, const Options& options,
               const TessellationRates& rates, const InputTopology& kept, TessellationImpl::Layer& layer) {
    Options cut = options;
    cut.boundary = Boundary::EdgesOnly;  // a corner of one face is tagged above where the rules make one
    TessellationRates layer_rates;
    layer_rates.uniform_rate = rates.uniform_rate;
    layer_rates.edges = layer_mesh.edges.data(), layer_rates.rates = layer_mesh.edge_rates.data();
    layer_rates.num_edges = int(layer_mesh.edge_rates.size());
    // The layer's cut spends what the surface's left of the memory limit.
    cut.memory_limit_bytes = options.memory_limit_bytes - std::min(options.memory_limit_bytes, d.estimated_bytes);
    // The layer's triangles are the mesh's: those without a surface are its holes.
    MeshView view = layer_mesh.tags.view(num_values);
    view.hole_triangles = d.input->holes.data(), view.num_holes = int(d.input->holes.size());
    try {
        layer.surface = std::make_unique<Tessellation>(view, cut, layer_rates, kept);
    } catch (const MemoryLimitError& error) {
        const std::uint64_t total = d.estimated_bytes + error.required_bytes;
        throw MemoryLimitError("tessellation: with face-varying layer " + std::to_string(k) + " it would need about " +
                                   describe_bytes(total) + ", more than the limit of " +
                                   describe_bytes(options.memory_limit_bytes),
                               total);
    }
    const Tessellation& surface = *layer.surface;
    d.estimated_bytes += surface.estimated_bytes();
    if (surface.num_face_points() != int(d.samples.size()) ||
        !std::equal(d.corner_face_points.begin(), d.corner_face_points.end(), surface.corner_face_points()))
        throw std::logic_error("tessellation: a face-varying layer's face points are not the surface's");
    layer.face_point_point.resize(d.samples.size());
    for (std::size_t c = 0; c < d.corner_face_points.size(); ++c)
        layer.face_point_point[std::size_t(d.corner_face_points[c])] = surface.triangles()[c];
}

}  // namespace

// A face-varying layer cut as the surface is: its input level as a mesh of its own (Plan::face_varying_base) with the
// mesh's tags carried onto it where they apply to its values (their class says which), the values that stay tagged as
// corners, each of its edges at the rate of the mesh edge it lies on. Its face points are the surface's, one for one:
// the same triangles in the same order, with the same rates.
void add_face_varying_layers(TessellationImpl& d, const MeshView& mesh, const Options& options,
                             const TessellationRates& rates, const InputTopologyParts* reuse) {
    const std::size_t corners = 3 * std::size_t(mesh.num_triangles);
    d.face_point_parent.resize(d.samples.size());
    for (std::size_t c = 0; c < d.corner_face_points.size(); ++c)
        d.face_point_parent[std::size_t(d.corner_face_points[c])] = d.parent_triangles[c / 3];
    Options classify = options;
    classify.levels = 0, classify.limit_surface = false;
    const Plan plan(mesh, classify);  // checks the layers, and classifies their values as a plan refines them
    if (options.face_varying == FaceVaryingInterpolation::All) {
        for (int k = 0; k < mesh.num_face_varying; ++k) {
            TessellationImpl::Layer& layer = d.layers.emplace_back();
            layer.num_values = mesh.face_varying[k].num_values;
            layer.corner_values.assign(mesh.face_varying[k].corner_values,
                                       mesh.face_varying[k].corner_values + corners);
        }
        return;
    }

    const InputTags input = input_tags(mesh, rates);
    for (int k = 0; k < mesh.num_face_varying; ++k) {
        TessellationImpl::Layer& layer = d.layers.emplace_back();
        layer.num_values = mesh.face_varying[k].num_values;
        const Plan::FaceVaryingBase base = plan.face_varying_base(k);
        layer.base_values = base.values;
        const LayerMesh layer_mesh = tagged_layer_mesh(mesh, options, rates, input, base);
        const InputTopology kept =
            reuse != nullptr && std::size_t(k) < reuse->layers.size() ? reuse->layers[std::size_t(k)] : InputTopology();
        cut_layer(d, k, layer_mesh, int(base.values.size()), options, rates, kept, layer);
    }
}

}  // namespace loopsub
