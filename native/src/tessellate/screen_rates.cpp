// Rates from the screen (loopsub/tessellation.h, screen_space_rates): an edge's length on screen, in segments; and the
// camera of a look-at and a perspective (look_at_camera).
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "base/input_checks.h"
#include "loopsub/tessellation.h"
#include "rules/rules.h"
#include "tessellate/level_patches.h"
#include "tessellate/tessellation_rates.h"

namespace loopsub {

namespace {

[[noreturn]] void fail(const std::string& message) { throw InputError("screen_space_rates: " + message); }

struct Clip {
    double x, y, w;
};

Clip to_clip(const float m[16], const float* p) {
    auto row = [&](int r) {
        return double(m[4 * r]) * p[0] + double(m[4 * r + 1]) * p[1] + m[4 * r + 2] * double(p[2]) + m[4 * r + 3];
    };
    return {row(0), row(1), row(3)};
}

// The first split of the mesh under the smooth rules, with boundaries as creases, for DicingMeasure::Deviation: each
// edge's bulge, how far its new point lies off the chord of its ends' new points. For a quadratic surface that is
// (h^2 / 8) t'Ht, the chord's distance from the surface along the edge (h its length, t its direction, H the Hessian):
// what a segment of the edge strays by, over r^2 when the edge is cut into r. (The distance of the new point from the
// old ends' midpoint, (c + d - a - b) / 8, measures the curvature across the edge and is blind to the curvature along
// it.)
class FirstSplit {
public:
    FirstSplit() = default;
    FirstSplit(const MeshView& mesh, const float* positions, const detail::SortedEdges& edges)
        : positions_(positions), opposite_(2 * edges.keys.size(), -1), corner_edges_(&edges.corner_edges) {
        const std::vector<std::uint64_t>& keys = edges.keys;
        for (std::size_t c = 0; c < edges.corner_edges.size(); ++c) {
            const std::size_t face = c - c % 3;
            std::int32_t* slot = &opposite_[2 * std::size_t(edges.corner_edges[c])];
            slot[slot[0] < 0 ? 0 : 1] = mesh.triangles[face + (c + 2) % 3];
        }
        // Each vertex's neighbours summed, all of them and those along the boundary.
        const std::size_t n = std::size_t(mesh.num_vertices);
        std::vector<double> ring(3 * n, 0.0), along(3 * n, 0.0);
        std::vector<int> valence(n, 0), boundary(n, 0);
        for (std::size_t e = 0; e < keys.size(); ++e) {
            const std::int32_t ends[2] = {std::int32_t(keys[e] >> 32), std::int32_t(keys[e] & 0xffffffffu)};
            const bool on_boundary = opposite_[2 * e + 1] < 0;
            for (int k = 0; k < 2; ++k) {
                const std::size_t v = std::size_t(ends[k]);
                const float* other = positions + 3 * std::size_t(ends[1 - k]);
                ++valence[v];
                boundary[v] += on_boundary;
                for (int i = 0; i < 3; ++i) ring[3 * v + i] += other[i], along[3 * v + i] += on_boundary ? other[i] : 0;
            }
        }
        // A vertex's new point: the smooth mask inside, the crease mask on a boundary it runs along, itself where
        // neither applies (a boundary vertex on more than one stretch of boundary).
        split_vertices_.resize(3 * n);
        for (std::size_t v = 0; v < n; ++v) {
            const float* p = positions + 3 * v;
            const bool inside = boundary[v] == 0 && valence[v] >= 3, crease = boundary[v] == 2;
            const detail::VertexMask mask =
                inside ? detail::smooth_vertex_mask(valence[v]) : detail::crease_vertex_mask();
            for (int i = 0; i < 3; ++i)
                split_vertices_[3 * v + i] = inside   ? mask.self * p[i] + mask.ring * ring[3 * v + i]
                                             : crease ? mask.self * p[i] + mask.crease * along[3 * v + i]
                                                      : p[i];
        }
    }

    // Edge e's bulge, from a to b.
    void bulge(std::size_t e, std::int32_t a, std::int32_t b, float out[3]) const {
        const std::int32_t c = opposite_[2 * e], d = opposite_[2 * e + 1];
        const float *pa = positions_ + 3 * std::size_t(a), *pb = positions_ + 3 * std::size_t(b);
        const detail::EdgeMask mask = d >= 0 ? detail::smooth_edge_mask() : detail::crease_edge_mask();
        for (int i = 0; i < 3; ++i) {
            const double wings =
                d >= 0 ? mask.wings * (double(positions_[3 * std::size_t(c) + i]) + positions_[3 * std::size_t(d) + i])
                       : 0.0;
            const double point = mask.a * pa[i] + mask.b * pb[i] + wings;
            out[i] = float(point -
                           0.5 * (split_vertices_[3 * std::size_t(a) + i] + split_vertices_[3 * std::size_t(b) + i]));
        }
    }

    // No edge coarser than the other edges of its triangles: a triangle whose edges' rates differ is cut into its
    // inner lattice and a strip along each edge, and the strip along a coarse edge fans from its few points to the
    // fine lattice beside it. Along an edge where the surface is straight (its bulge 0) but twisted across, those fans
    // would stray by the twist, several times what the lattice does (docs/benchmark.md).
    void raise_to_triangles(std::vector<std::int32_t>& rates) const {
        std::vector<std::int32_t> raised = rates;
        for (std::size_t c = 0; c < corner_edges_->size(); c += 3) {
            const std::size_t e[3] = {std::size_t((*corner_edges_)[c]), std::size_t((*corner_edges_)[c + 1]),
                                      std::size_t((*corner_edges_)[c + 2])};
            const std::int32_t most = std::max({rates[e[0]], rates[e[1]], rates[e[2]]});
            for (std::size_t k : e) raised[k] = std::max(raised[k], most);
        }
        rates = std::move(raised);
    }

private:
    const float* positions_ = nullptr;
    std::vector<std::int32_t> opposite_;  // the third corners of each edge's first two faces (-1: none)
    const std::vector<std::int32_t>* corner_edges_ = nullptr;  // SortedEdges::corner_edges, the caller's
    std::vector<double> split_vertices_;                       // 3 per vertex
};

// Distances from the camera, from world_to_clip alone. A perspective projection's w row is the view direction
// (times the object's scale, as every row is), and its x and y rows are the frustum's focal scales along the camera's
// right and up plus the lens shift times that direction: the camera's x and y are then (x - shift w) / scale. An
// orthographic projection has a constant w: every point is at depth |w| = 1 for what it measures. So is any matrix
// whose frame cannot be told apart (a w row past the float range, an x or y row along it): measured at its depth.
class CameraDistance {
public:
    CameraDistance(const float m[16], double viewport_height) {
        const double w[3] = {m[12], m[13], m[14]};
        const double ww = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
        // Pixels per unit of length at depth 1 (w = 1), perpendicular to the view: the up row's scale times half
        // the viewport's height; at distance 1 for a perspective, its focal scale of y.
        pixels_at_one_ =
            std::sqrt(double(m[4]) * m[4] + double(m[5]) * m[5] + double(m[6]) * m[6]) * 0.5 * viewport_height;
        if (!(ww > 0.0) || !std::isfinite(ww)) return;
        for (int axis = 0; axis < 2; ++axis) {
            const float* row = m + 4 * axis;
            shift_[axis] = (row[0] * w[0] + row[1] * w[1] + row[2] * w[2]) / ww;
            double across = 0.0;
            for (int k = 0; k < 3; ++k) across += (row[k] - shift_[axis] * w[k]) * (row[k] - shift_[axis] * w[k]);
            scale_[axis] = std::sqrt(across / ww);
            if (!(scale_[axis] > 0.0) || !std::isfinite(scale_[axis])) return;
        }
        perspective_ = true;
        pixels_at_one_ = scale_[1] * std::sqrt(ww) * 0.5 * viewport_height;
    }

    double pixels_at_one() const { return pixels_at_one_; }

    // The distance of a point (its clip coordinates) from the camera, or its depth where the frame is not told.
    double operator()(const Clip& c) const {
        if (!perspective_) return std::fabs(c.w);
        const double x = (c.x - shift_[0] * c.w) / scale_[0], y = (c.y - shift_[1] * c.w) / scale_[1];
        return std::sqrt(x * x + y * y + c.w * c.w);
    }

private:
    bool perspective_ = false;
    double pixels_at_one_ = 0.0;
    double shift_[2] = {0.0, 0.0}, scale_[2] = {1.0, 1.0};
};

// Whether the edge from p to q, midpoint mid, is in view: the box around its ends on screen overlaps the view (its
// midpoint alone would leave the triangles along the view's border coarse where their edges run out of it); an edge
// that reaches behind the camera, where its midpoint is.
bool reaches_view(const Clip& p, const Clip& q, const Clip& mid) {
    if (!(p.w > 0.0 && q.w > 0.0)) return mid.w > 0.0 && std::fabs(mid.x) <= mid.w && std::fabs(mid.y) <= mid.w;
    const double px = p.x / p.w, py = p.y / p.w, qx = q.x / q.w, qy = q.y / q.w;
    return std::max(px, qx) >= -1.0 && std::min(px, qx) <= 1.0 && std::max(py, qy) >= -1.0 && std::min(py, qy) <= 1.0;
}

// The arguments of screen_space_rates that are no data of the mesh or the camera's matrix: plain InputErrors, as a
// plan's options.
void validate_screen_arguments(float pixels, int max_rate, float offscreen_scale, const Camera& camera) {
    if (!(pixels > 0.0f) || !std::isfinite(pixels))
        fail("pixels must be a positive number, got " + std::to_string(pixels));
    detail::validate_rate_argument(max_rate, "max_rate", "screen_space_rates: ");
    if (!(offscreen_scale >= 1.0f) || !std::isfinite(offscreen_scale))
        fail("offscreen_scale must be at least 1, got " + std::to_string(offscreen_scale));
    if (!(camera.viewport_width > 0.0f) || !(camera.viewport_height > 0.0f) || !std::isfinite(camera.viewport_width) ||
        !std::isfinite(camera.viewport_height))
        fail("the viewport must have a positive size");
}

// The mesh's triangles, the positions and the camera's matrix, by the core's checks (base/input_checks.h): the
// first problem thrown as an InputError that carries it.
void check_screen_input(const MeshView& mesh, const float* positions, const Camera& camera) {
    if (mesh.num_vertices < 0 || mesh.num_triangles < 0 || (mesh.num_triangles > 0 && !mesh.triangles))
        fail("no triangles");
    if (mesh.num_vertices > 0 && !positions) fail("positions are missing (null)");
    const detail::ThrowFirst report{"screen_space_rates: "};
    detail::check_values({camera.world_to_clip, 1, 1, 1}, 16, InputProblem::Element::Camera, -1, 0.0f, 0, report);
    detail::check_triangles(mesh.triangles, mesh.num_triangles, mesh.num_vertices, false, report);
    // A deviation reads the neighbours' positions too.
    detail::check_values(interleaved(positions, 3), mesh.num_vertices, InputProblem::Element::Vertex, -1, 0.0f, 0,
                         report);
}

}  // namespace

Camera look_at_camera(const float eye[3], const float target[3], const float up[3], float fov_degrees, float width,
                      float height) {
    using Vector = std::array<double, 3>;
    auto cross = [](const Vector& a, const Vector& b) {
        return Vector{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    };
    auto unit = [](Vector a) {
        const double length = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        if (!(length > 0.0)) throw InputError("look_at_camera: the eye, the target and up must span a view");
        for (double& c : a) c /= length;
        return a;
    };
    const Vector forward = unit({double(target[0]) - eye[0], double(target[1]) - eye[1], double(target[2]) - eye[2]}),
                 right = unit(cross(forward, {up[0], up[1], up[2]})), above = cross(right, forward);
    const double f = 1.0 / std::tan(0.5 * double(fov_degrees) * 3.14159265358979323846 / 180.0);
    const double aspect = double(width) / height, near = 1e-3, far = 1e6;
    const double* axes[3] = {right.data(), above.data(), forward.data()};
    double view[3][4];  // rows: right, up, -forward (OpenGL looks down -z); translation last
    for (int r = 0; r < 3; ++r) {
        const double sign = r == 2 ? -1.0 : 1.0;
        for (int c = 0; c < 3; ++c) view[r][c] = sign * axes[r][c];
        view[r][3] = -(view[r][0] * eye[0] + view[r][1] * eye[1] + view[r][2] * eye[2]);
    }
    Camera camera;
    const double scale[4] = {f / aspect, f, (far + near) / (near - far), -1.0};
    for (int c = 0; c < 4; ++c) {
        camera.world_to_clip[c] = float(scale[0] * view[0][c]);
        camera.world_to_clip[4 + c] = float(scale[1] * view[1][c]);
        camera.world_to_clip[8 + c] = float(scale[2] * view[2][c] + (c == 3 ? 2.0 * far * near / (near - far) : 0.0));
        camera.world_to_clip[12 + c] = float(scale[3] * view[2][c]);
    }
    camera.viewport_width = width, camera.viewport_height = height;
    return camera;
}

TessellationRates ScreenRates::view() const {
    TessellationRates view;
    view.edges = edges.data(), view.rates = rates.data(), view.num_edges = int(rates.size());
    return view;
}

ScreenRates screen_space_rates(const MeshView& mesh, const float* positions, const Camera& camera, float pixels,
                               int max_rate, DicingMeasure measure, float offscreen_scale) {
    const bool by_deviation = measure == DicingMeasure::Deviation;
    validate_screen_arguments(pixels, max_rate, offscreen_scale, camera);
    check_screen_input(mesh, positions, camera);
    // By deviation each corner's edge is wanted too.
    const detail::SortedEdges edges =
        by_deviation ? detail::sorted_edges(mesh.triangles, mesh.num_triangles)
                     : detail::SortedEdges{detail::sorted_edge_keys(mesh.triangles, mesh.num_triangles), {}};
    const std::vector<std::uint64_t>& keys = edges.keys;
    const FirstSplit split = by_deviation ? FirstSplit(mesh, positions, edges) : FirstSplit();

    ScreenRates out;
    out.edges.reserve(2 * keys.size()), out.rates.reserve(keys.size());
    const float* m = camera.world_to_clip;
    const CameraDistance distance(m, camera.viewport_height);
    for (std::size_t e = 0; e < keys.size(); ++e) {
        const std::int32_t a = std::int32_t(keys[e] >> 32), b = std::int32_t(keys[e] & 0xffffffffu);
        const float* pa = positions + 3 * std::size_t(a);
        const float* pb = positions + 3 * std::size_t(b);
        // The edge's midpoint (halves added: the sum of two finite ends may pass the float range), and what is
        // measured there: the edge or its bulge.
        float middle[3], offset[3];
        for (int k = 0; k < 3; ++k) middle[k] = 0.5f * pa[k] + 0.5f * pb[k], offset[k] = pb[k] - pa[k];
        if (by_deviation) split.bulge(e, a, b, offset);
        const Clip p = to_clip(m, pa), q = to_clip(m, pb), mid = to_clip(m, middle);
        const double length =
            std::sqrt(double(offset[0]) * offset[0] + double(offset[1]) * offset[1] + double(offset[2]) * offset[2]);
        if (!std::isfinite(p.x + p.y + p.w + q.x + q.y + q.w + mid.x + mid.y + mid.w + length))
            fail("edge (" + std::to_string(a) + ", " + std::to_string(b) + ") is too large to measure");
        int rate = 1;
        if (p.w > 0.0 || q.w > 0.0) {  // else both ends are behind the camera: unseen, one segment
            // As Cycles measures: the length in pixels it would have straight ahead of the camera at its midpoint's
            // distance, facing it; an edge out of the view coarser by offscreen_scale. (By depth, an edge beside the
            // camera, out of the picture, would be cut finest of all.)
            double measured = length * distance.pixels_at_one() / std::max(distance(mid), 1e-6);
            const bool in_view = reaches_view(p, q, mid);
            double segments = by_deviation ? std::sqrt(measured / pixels) : measured / pixels;
            if (!in_view) segments /= offscreen_scale;
            rate = int(std::clamp(std::ceil(segments), 1.0, double(max_rate)));
        }
        out.edges.push_back(a), out.edges.push_back(b), out.rates.push_back(rate);
    }
    if (by_deviation) split.raise_to_triangles(out.rates);
    return out;
}

}  // namespace loopsub
