// libFuzzer target: raw bytes as a mesh with tags, options and rates, straight into Tessellation and its evaluate,
// and into screen_space_rates: indices out of range, NaN and huge values, rates out of range, edges that are none.
// Layout (each field from the bytes in turn, zero when they run out): options byte (rules, boundary, crease method,
// kernel, 2 threads, boundary none), uniform rate 0-15, vertex count 0-31, triangle count 0-31, crease count 0-7,
// corner count 0-3, cone count 0-3, rated edge count 0-7, then the triangles' indices, crease edges and sharpness,
// corners and sharpness, cones, rated edges and their rates (0-15), then the positions (raw float bits) and a camera
// (16 floats, a viewport, pixels, a measure byte), then a face-varying layer (a byte: bit 0 whether, the rest its mode;
// a value count 0-63, each corner's value index, the values' raw float bits).
//
// Checked on every accepted input: the result's indices are in range, its parameters in the unit triangle, its points
// and normals finite; on a mesh whose every edge has two triangles, so has every edge of the result (no crack), where
// no two triangles share two edges (else the lattice edge between those edges' points joins the same two points in
// both triangles, two edges that vertex pairs cannot tell apart); output_edges names each side by its ends; the
// layer's values at the face points are finite.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <map>
#include <vector>

#include "fuzz_common.h"
#include "loopsub/tessellation.h"

namespace {

// Every edge of the triangles has exactly two of them.
bool closed(const std::int32_t* triangles, int count) {
    std::map<std::pair<int, int>, int> uses;
    for (int c = 0; c < 3 * count; ++c) {
        const int a = triangles[c], b = triangles[c - c % 3 + (c + 1) % 3];
        ++uses[{std::min(a, b), std::max(a, b)}];
    }
    for (const auto& [edge, n] : uses)
        if (n != 2) return false;
    return !uses.empty();
}

// Whether two triangles share two edges (or all three: two triangles on the same three vertices).
bool shares_two_edges(const std::int32_t* triangles, int count) {
    std::map<std::pair<int, int>, std::vector<int>> faces_of;
    for (int c = 0; c < 3 * count; ++c) {
        const int a = triangles[c], b = triangles[c - c % 3 + (c + 1) % 3];
        faces_of[{std::min(a, b), std::max(a, b)}].push_back(c / 3);
    }
    std::map<std::pair<int, int>, int> shared;
    for (const auto& [edge, faces] : faces_of)
        for (std::size_t i = 0; i < faces.size(); ++i)
            for (std::size_t j = i + 1; j < faces.size(); ++j)
                if (faces[i] != faces[j] && ++shared[{std::min(faces[i], faces[j]), std::max(faces[i], faces[j])}] > 1)
                    return true;
    return false;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace loopsub;
    fuzz::Bytes in(data, size);
    const std::uint8_t flags = in.byte();
    Options options = fuzz::options_from(flags);
    if (flags & 64) options.boundary = Boundary::None;
    const int uniform = in.byte() % 16, vertices = in.byte() % 32, triangles = in.byte() % 32, creases = in.byte() % 8,
              corners = in.byte() % 4, cones = in.byte() % 4, rated = in.byte() % 8;
    MeshData mesh;
    mesh.positions.resize(3 * std::size_t(vertices));
    fuzz::read_mesh(in, mesh, vertices, triangles, creases, corners, cones);
    std::vector<std::int32_t> edges, rates;
    for (int i = 0; i < rated; ++i) {
        edges.insert(edges.end(), {in.index(vertices), in.index(vertices)});
        rates.push_back(in.byte() % 16);
    }
    for (float& value : mesh.positions) value = in.number();
    Camera camera;
    for (float& m : camera.world_to_clip) m = in.number();
    camera.viewport_width = in.number(), camera.viewport_height = in.number();
    const float pixels = in.number();
    const DicingMeasure measure = in.byte() & 1 ? DicingMeasure::Deviation : DicingMeasure::Length;
    // A face-varying layer, when the next byte says so: its mode, its value count, each corner's value, the values.
    const std::uint8_t layer_flags = in.byte();
    options.face_varying = FaceVaryingInterpolation((layer_flags >> 1) % 6);
    const int layer_values = in.byte() % 64;
    std::vector<std::int32_t> corner_values(mesh.triangles.size());
    for (std::int32_t& value : corner_values) value = in.index(layer_values);
    std::vector<float> values(2 * std::size_t(layer_values));
    for (float& value : values) value = in.number();
    const FaceVaryingLayer layer{corner_values.data(), layer_values};
    MeshView view = mesh.view();
    if (layer_flags & 1) view.face_varying = &layer, view.num_face_varying = 1;

    TessellationRates given;
    given.uniform_rate = uniform;
    given.edges = edges.data(), given.rates = rates.data(), given.num_edges = rated;
    try {
        const Tessellation t(view, options, given);
        const int n = t.num_points(), m = t.num_face_points();
        for (int c = 0; c < 3 * t.num_triangles(); ++c)
            if (t.triangles()[c] < 0 || t.triangles()[c] >= n || t.corner_face_points()[c] < 0 ||
                t.corner_face_points()[c] >= m)
                std::abort();
        for (int k = 0; k < 2 * m; ++k)
            if (!(t.face_point_parameters()[k] >= 0.0f && t.face_point_parameters()[k] <= 1.0f)) std::abort();
        if (closed(mesh.triangles.data(), mesh.num_triangles()) &&
            !shares_two_edges(mesh.triangles.data(), mesh.num_triangles()) && !closed(t.triangles(), t.num_triangles()))
            std::abort();                                        // a crack
        const Tessellation::Edges edges_out = t.output_edges();  // each side names an edge with its two ends
        for (int c = 0; c < 3 * t.num_triangles(); ++c) {
            const std::int32_t e = edges_out.triangle_edges[std::size_t(c)];
            if (e < 0 || std::size_t(e) >= edges_out.edge_vertices.size() / 2) std::abort();
            const std::int32_t a = t.triangles()[c], b = t.triangles()[c - c % 3 + (c + 1) % 3];
            const std::int32_t u = edges_out.edge_vertices[2 * std::size_t(e)],
                               v = edges_out.edge_vertices[2 * std::size_t(e) + 1];
            if (std::minmax(a, b) != std::minmax(u, v)) std::abort();
        }
        std::vector<float> points(3 * std::size_t(n)), normals(3 * std::size_t(m));
        try {
            t.evaluate(mesh.positions.data(), points.data(), normals.data());
            fuzz::require_finite(points);
            fuzz::require_finite(normals);
        } catch (const InputError&) {}
        for (int k = 0; k < t.num_face_varying_layers(); ++k) {
            std::vector<float> at_face_points(2 * std::size_t(m));
            try {
                t.evaluate_face_varying(k, values.data(), 2, at_face_points.data());
                fuzz::require_finite(at_face_points);
            } catch (const InputError&) {}
        }
    } catch (const InputError&) {
    } catch (const MemoryLimitError&) {}
    try {
        const ScreenRates screen = screen_space_rates(mesh.view(), mesh.positions.data(), camera, pixels, 64, measure);
        for (int rate : screen.rates)
            if (rate < 1 || rate > 64) std::abort();
    } catch (const InputError&) {}
    return 0;
}
