// The checks of what a caller hands the core, written once: each calls report(problem) for every InputProblem it
// finds, in order, and stops early where report returns false. A Plan's validation reports to a function that throws
// the first (plan/validation.h), diagnose() to one that collects them all, welding to one that throws. The checks
// read the arrays in one pass each and build a problem only where one is found: they run on every plan and frame.
// Here, below every layer, as welding (api/) and the plan builder (plan/) share them; the checks that need the mesh's
// edges are in plan/validation.h.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "loopsub/loopsub.h"

namespace loopsub::detail {

using Problem = InputProblem;
using Kind = InputProblem::Kind;
using Element = InputProblem::Element;

inline bool finite_non_negative(float value) { return std::isfinite(value) && value >= 0.0f; }

inline Problem vertex_out_of_range(Element element, int index, int corner, std::int32_t vertex, int num_vertices) {
    Problem p;
    p.kind = Kind::VertexOutOfRange, p.element = element, p.index = index, p.corner = corner;
    p.refers_to = vertex, p.other = num_vertices;
    return p;
}

// The triangles' vertex indices (3 per triangle) in 0..num_vertices-1, and, with `distinct`, no triangle repeating
// one (degenerate).
template <typename Report>
bool check_triangles(const std::int32_t* triangles, int num_triangles, int num_vertices, bool distinct,
                     Report&& report) {
    for (int f = 0; f < num_triangles; ++f) {
        const std::int32_t* v = triangles + 3 * std::size_t(f);
        bool in_range = true;
        for (int k = 0; k < 3; ++k)
            if (v[k] < 0 || v[k] >= num_vertices) {
                in_range = false;
                if (!report(vertex_out_of_range(Element::Triangle, f, k, v[k], num_vertices))) return false;
            }
        if (distinct && in_range && (v[0] == v[1] || v[1] == v[2] || v[2] == v[0])) {
            Problem p;
            p.kind = Kind::DegenerateTriangle, p.element = Element::Triangle, p.index = f;
            p.corner = v[1] == v[0] ? 1 : 2;  // the later corner of the first pair that repeats
            p.refers_to = v[p.corner == 1 || v[2] == v[0] ? 0 : 1];
            if (!report(p)) return false;
        }
    }
    return true;
}

// MeshView::triangle_edges, where given: each number in 0..3 * num_triangles - 1, and on the same two vertices
// wherever it is given.
template <typename Report>
bool check_triangle_edges(const MeshView& mesh, Report&& report) {
    if (!mesh.triangle_edges) return true;
    const std::int64_t corners = 3 * std::int64_t(mesh.num_triangles);
    std::vector<std::int64_t> first_corner(std::size_t(corners), -1);  // of each number
    auto ends = [&mesh](std::int64_t corner) {
        const std::int32_t a = mesh.triangles[corner], b = mesh.triangles[corner - corner % 3 + (corner + 1) % 3];
        return std::pair<std::int32_t, std::int32_t>(std::min(a, b), std::max(a, b));
    };
    for (std::int64_t c = 0; c < corners; ++c) {
        const std::int32_t edge = mesh.triangle_edges[c];
        Problem p;
        p.element = Element::Triangle, p.index = int(c / 3), p.corner = int(c % 3), p.refers_to = edge;
        if (edge < 0 || edge >= corners) {
            p.kind = Kind::EdgeOutOfRange, p.other = int(corners);
            if (!report(p)) return false;
            continue;
        }
        std::int64_t& first = first_corner[std::size_t(edge)];
        if (first < 0) {
            first = c;
        } else if (ends(first) != ends(c)) {
            p.kind = Kind::EdgeEndsDiffer, p.other = int(first / 3);
            if (!report(p)) return false;
        }
    }
    return true;
}

// Vertex indices of tags (crease edges: two per tag, `per_tag` 2) in range, and their sharpness (or nullptr) finite
// and >= 0.
template <typename Report>
bool check_tags(Element element, const std::int32_t* vertices, int per_tag, const float* sharpness, int count,
                int num_vertices, Report&& report) {
    for (int k = 0; k < count; ++k) {
        for (int end = 0; end < per_tag; ++end) {
            const std::int32_t v = vertices[per_tag * std::size_t(k) + std::size_t(end)];
            if ((v < 0 || v >= num_vertices) && !report(vertex_out_of_range(element, k, -1, v, num_vertices)))
                return false;
        }
        if (sharpness && !finite_non_negative(sharpness[k])) {
            Problem p;
            p.kind = Kind::BadSharpness, p.element = element, p.index = k, p.value = sharpness[k];
            if (!report(p)) return false;
        }
    }
    return true;
}

// A face-varying layer's value index at each corner in 0..num_values-1.
template <typename Report>
bool check_layer(const FaceVaryingLayer& layer, int layer_index, int num_triangles, Report&& report) {
    const std::size_t corners = 3 * std::size_t(num_triangles);
    for (std::size_t c = 0; c < corners; ++c) {
        const std::int32_t value = layer.corner_values[c];
        if (value < 0 || value >= layer.num_values) {
            Problem p;
            p.kind = Kind::ValueOutOfRange, p.element = Element::Triangle, p.index = int(c / 3), p.corner = int(c % 3);
            p.refers_to = value, p.other = layer.num_values, p.layer = layer_index;
            if (!report(p)) return false;
        }
    }
    return true;
}

// Each layer in turn.
template <typename Report>
bool check_layers(const MeshView& mesh, Report&& report) {
    for (int k = 0; k < mesh.num_face_varying; ++k)
        if (!check_layer(mesh.face_varying[k], k, mesh.num_triangles, report)) return false;
    return true;
}

// The mesh and its tags, in the order a plan has always met them: holes, triangles (and their edges), creases, corners,
// cones, then the face-varying layers' value indices. The view must be readable (validate_view).
template <typename Report>
bool check_mesh(const MeshView& mesh, Report&& report) {
    for (int k = 0; k < mesh.num_holes; ++k) {
        const std::int32_t t = mesh.hole_triangles[k];
        if (t < 0 || t >= mesh.num_triangles) {
            Problem p;
            p.kind = Kind::TriangleOutOfRange, p.element = Element::Hole, p.index = k, p.refers_to = t;
            p.other = mesh.num_triangles;
            if (!report(p)) return false;
        }
    }
    const int n = mesh.num_vertices;
    return check_triangles(mesh.triangles, mesh.num_triangles, n, true, report) && check_triangle_edges(mesh, report) &&
           check_tags(Element::CreaseEdge, mesh.crease_edges, 2, mesh.crease_sharpness, mesh.num_crease_edges, n,
                      report) &&
           check_tags(Element::CornerVertex, mesh.corner_vertices, 1, mesh.corner_sharpness, mesh.num_corners, n,
                      report) &&
           check_tags(Element::Cone, mesh.cone_vertices, 1, nullptr, mesh.num_cones, n, report) &&
           check_layers(mesh, report);
}

// Per-element values (vertex values, or a face-varying layer's: element FaceVaryingValue of `layer`): finite, and,
// with largest > 0, within +-largest (the bound that keeps a kernel's sums of up to summed_terms values finite).
template <typename Report>
bool check_values(ChannelsView<const float> in, int count, Element element, int layer, float largest, int summed_terms,
                  Report&& report) {
    for (int v = 0; v < count; ++v)
        for (int c = 0; c < in.num_channels; ++c) {
            const float value = in.data[c * in.channel_stride + std::size_t(v) * in.element_stride];
            const bool finite = std::isfinite(value);
            if (!finite || (largest > 0.0f && std::fabs(value) > largest)) {
                Problem p;
                p.kind = finite ? Kind::ValueTooLarge : Kind::NonFiniteValue, p.element = element, p.index = v;
                p.layer = layer, p.channel = c, p.value = value;
                if (finite) p.limit = largest, p.other = summed_terms;
                if (!report(p)) return false;
            }
        }
    return true;
}

// Per-corner values (num_channels per corner of each triangle): finite. `layer`: the face-varying layer they are
// welded into, or -1.
template <typename Report>
bool check_corner_values(const float* in, std::size_t num_triangles, int num_channels, int layer, Report&& report) {
    const std::size_t corner = std::size_t(num_channels), face = 3 * corner;
    for (std::size_t i = 0; i < face * num_triangles; ++i)
        if (!std::isfinite(in[i])) {
            Problem p;
            p.kind = Kind::NonFiniteValue, p.element = Element::Triangle, p.index = int(i / face);
            p.corner = int(i % face / corner), p.channel = int(i % corner), p.layer = layer, p.value = in[i];
            if (!report(p)) return false;
        }
    return true;
}

// A report that throws the first problem (what a Plan and an evaluation do), its message after `context`.
struct ThrowFirst {
    const char* context = "";
    bool operator()(const Problem& problem) const { throw InputError(problem, context); }
};

}  // namespace loopsub::detail
