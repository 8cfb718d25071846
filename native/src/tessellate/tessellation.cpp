// A Tessellation: the points of every input triangle's pattern (topology/tessellation_pattern.h), each placed on the
// limit surface from the plans of the levels the rates need. With L levels, 2^L at least the largest rate, no point
// lies inside a level-L triangle at an input vertex (where the surface is irregular) other than the vertex itself:
// a point at a vertex of level L takes the limit plan's point and normal, every other point a stencil over the level's
// control points, a box spline where its triangle is a regular patch (level_patches.h) and the refined neighbourhood's
// (local_refinement.h) where a semi-sharp edge or a non-manifold one leaves the triangle irregular.
#include "loopsub/tessellation.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "tessellate/level_patches.h"
#include "tessellate/local_refinement.h"
#include "topology/tessellation_pattern.h"

namespace loopsub {

struct TessellationImpl {
    int levels = 0;
    int num_input_vertices = 0;
    std::int64_t num_points = 0;
    std::vector<std::int32_t> triangles, parent_triangles, corner_face_points;
    // A sample per face point (the normals' rows). A sample at a vertex of the level takes the limit plan's point and
    // normal; any other its stencil over the control plan's points.
    std::vector<float> parameters;              // (u, v) per sample
    std::vector<std::int32_t> sample_point;     // the point a sample places, -1 where an earlier sample places it
    std::vector<std::int32_t> sample_vertex;    // the level's vertex, -1 for a stencil
    std::vector<std::int32_t> sample_normal;    // the limit plan's normal of a vertex sample
    std::vector<std::int64_t> stencil_offsets;  // per sample and one more
    std::vector<std::int32_t> stencil_points;
    std::vector<float> stencil_weights;    // position, d/ds, d/dt per entry
    std::unique_ptr<Plan> control, limit;  // the levels' control points and limit surface
    mutable std::vector<float> control_points, limit_points, limit_normals;
};

namespace {

using detail::FacePattern;
using detail::FacePoint;
using detail::LevelPatches;
using detail::LocalRefiner;
using detail::Stencil;

[[noreturn]] void fail(const std::string& message) { throw InputError("tessellation: " + message); }

int rate_in_range(int rate, const std::string& what) {
    if (rate < 1 || rate > kMaxTessellationRate)
        fail(what + " must be between 1 and " + std::to_string(kMaxTessellationRate) + ", got " + std::to_string(rate));
    return rate;
}

// The input's edges, each once, as sorted keys, with their rates and the number of their first inner point.
struct Edges {
    std::vector<std::uint64_t> keys;
    std::vector<int> rates;
    std::vector<std::int64_t> first_point;
    int find(std::int32_t a, std::int32_t b) const {
        const auto at = std::lower_bound(keys.begin(), keys.end(), detail::edge_key(a, b));
        return at != keys.end() && *at == detail::edge_key(a, b) ? int(at - keys.begin()) : -1;
    }
};

Edges edges_with_rates(const MeshView& mesh, const TessellationRates& rates) {
    Edges edges;
    const int uniform = rate_in_range(rates.uniform_rate, "uniform_rate");
    for (std::size_t c = 0; c < 3 * std::size_t(mesh.num_triangles); ++c)
        edges.keys.push_back(detail::edge_key(mesh.triangles[c], mesh.triangles[c - c % 3 + (c + 1) % 3]));
    std::sort(edges.keys.begin(), edges.keys.end());
    edges.keys.erase(std::unique(edges.keys.begin(), edges.keys.end()), edges.keys.end());
    edges.rates.assign(edges.keys.size(), uniform);
    if (rates.num_edges < 0) fail("num_edges must not be negative");
    for (int k = 0; k < rates.num_edges; ++k) {
        const std::int32_t a = rates.edges[2 * k], b = rates.edges[2 * k + 1];
        const int e = edges.find(a, b);
        const std::string name = "edge (" + std::to_string(a) + ", " + std::to_string(b) + ")";
        if (e < 0) fail("a rate for " + name + ", which no triangle has");
        edges.rates[std::size_t(e)] = rate_in_range(rates.rates[k], "the rate of " + name);
    }
    std::int64_t next = mesh.num_vertices;
    for (int rate : edges.rates) edges.first_point.push_back(next), next += rate - 1;
    return edges;
}

// One input triangle's sides: their edges' rates and first points, and whether each runs along its edge.
struct Sides {
    int rates[3];
    std::int64_t first_point[3];
    bool along[3];
    int inner_rate() const { return std::max({rates[0], rates[1], rates[2]}); }
};

class Builder {
public:
    Builder(TessellationImpl& d, const MeshView& mesh, const Options& options)
        : d_(d), mesh_(mesh), options_(options) {}

    void build(const TessellationRates& rates) {
        // The limit plan of no levels checks the mesh and the options before anything reads them.
        options_.limit_surface = true, options_.levels = 0;
        d_.limit = std::make_unique<Plan>(mesh_, options_);
        edges_ = edges_with_rates(mesh_, rates);
        const int largest = edges_.rates.empty() ? 1 : *std::max_element(edges_.rates.begin(), edges_.rates.end());
        while ((1 << d_.levels) < largest) ++d_.levels;
        options_.levels = d_.levels;
        if (d_.levels > 0) d_.limit = std::make_unique<Plan>(mesh_, options_);
        d_.num_input_vertices = mesh_.num_vertices;

        std::vector<Sides> sides(std::size_t(mesh_.num_triangles));
        std::vector<std::int64_t> face_first(std::size_t(mesh_.num_triangles));
        std::int64_t next =
            edges_.first_point.empty() ? mesh_.num_vertices : edges_.first_point.back() + edges_.rates.back() - 1;
        std::int64_t num_samples = 0;
        for (int f = 0; f < mesh_.num_triangles; ++f) {
            Sides& s = sides[std::size_t(f)];
            for (int k = 0; k < 3; ++k) {
                const std::int32_t a = mesh_.triangles[3 * f + k], b = mesh_.triangles[3 * f + (k + 1) % 3];
                const int e = edges_.find(a, b);
                s.rates[k] = edges_.rates[std::size_t(e)], s.first_point[k] = edges_.first_point[std::size_t(e)];
                s.along[k] = a < b;
            }
            face_first[std::size_t(f)] = next;
            const std::int64_t inner = detail::num_inner_points(s.rates, s.inner_rate());
            next += inner;
            num_samples += detail::first_edge_point(s.rates, 3) + inner;
        }
        if (next > std::int64_t(INT32_MAX) || num_samples > std::int64_t(INT32_MAX))
            throw MemoryLimitError("tessellation: more than 2^31 points", std::uint64_t(num_samples) * 64);
        d_.num_points = next;
        placed_.assign(std::size_t(next), false);
        d_.stencil_offsets.push_back(0);
        for (int f = 0; f < mesh_.num_triangles; ++f) add_face(f, sides[std::size_t(f)], face_first[std::size_t(f)]);
    }

private:
    void add_face(int f, const Sides& s, std::int64_t face_first) {
        detail::tessellate_triangle(s.rates, s.inner_rate(), pattern_);
        const int first_inner = detail::first_edge_point(s.rates, 3);
        std::vector<std::int32_t>& number = numbers_;
        number.resize(pattern_.points.size());
        int p = 0;
        for (; p < 3; ++p) number[std::size_t(p)] = mesh_.triangles[3 * f + p];
        for (int k = 0; k < 3; ++k)
            for (int i = 1; i < s.rates[k]; ++i, ++p)
                number[std::size_t(p)] = std::int32_t(s.first_point[k] + (s.along[k] ? i : s.rates[k] - i) - 1);
        for (; p < int(pattern_.points.size()); ++p)
            number[std::size_t(p)] = std::int32_t(face_first + p - first_inner);

        const int first_sample = int(d_.sample_vertex.size());
        for (std::size_t q = 0; q < pattern_.points.size(); ++q) {
            const std::int32_t point = number[q];
            d_.sample_point.push_back(placed_[std::size_t(point)] ? -1 : point);
            placed_[std::size_t(point)] = true;
            const detail::PatternPoint& at = pattern_.points[q];
            d_.parameters.push_back(float(double(at.b1) / at.den)),
                d_.parameters.push_back(float(double(at.b2) / at.den));
            add_sample(f, FacePoint{at.b1, at.b2, at.den});
        }
        for (std::int32_t p : pattern_.triangles) {
            d_.triangles.push_back(number[std::size_t(p)]);
            d_.corner_face_points.push_back(first_sample + p);
        }
        d_.parent_triangles.insert(d_.parent_triangles.end(), pattern_.triangles.size() / 3, f);
    }

    void add_sample(int f, FacePoint at) {
        int t = f;
        for (int l = 0; l < d_.levels; ++l) t = 4 * t + detail::descend(at);
        const int corner = at.T == 0 ? (at.S == 0 ? 0 : at.S == at.D ? 1 : -1) : (at.S == 0 && at.T == at.D ? 2 : -1);
        if (corner >= 0) {
            const std::size_t c = 3 * std::size_t(t) + std::size_t(corner);
            d_.sample_vertex.push_back(d_.limit->output_triangles()[c]);
            d_.sample_normal.push_back(d_.limit->corner_normal_indices()[c]);
        } else {
            if (!patches_) make_control();
            const double s = double(at.S) / double(at.D), u = double(at.T) / double(at.D);
            detail::PatchWeights weights;
            if (patches_->patch(t, s, u, weights)) {
                stencil_.clear();
                for (int i = 0; i < weights.count; ++i)
                    stencil_.add(weights.points[i], weights.position[i], weights.ds[i], weights.dt[i]);
            } else {
                local_->weights(t, at, stencil_);
            }
            d_.sample_vertex.push_back(-1);
            d_.sample_normal.push_back(-1);
            for (std::size_t i = 0; i < stencil_.points.size(); ++i) {
                d_.stencil_points.push_back(stencil_.points[i]);
                const float w[3] = {float(stencil_.position[i]), float(stencil_.ds[i]), float(stencil_.dt[i])};
                d_.stencil_weights.insert(d_.stencil_weights.end(), w, w + 3);
            }
        }
        d_.stencil_offsets.push_back(std::int64_t(d_.stencil_points.size()));
    }

    // The control points' plan and its patches, on the first point that needs them.
    void make_control() {
        Options control = options_;
        control.limit_surface = false;
        d_.control = std::make_unique<Plan>(mesh_, control);
        const Plan& plan = *d_.control;
        const auto& sharp = plan.output_sharp_edges();
        const auto& sharp_corners = plan.output_corner_vertices();
        patches_ = std::make_unique<LevelPatches>(
            plan.output_triangles(), plan.num_output_triangles(), plan.num_output_vertices(), sharp.data(),
            plan.output_sharp_edge_sharpness().data(), int(sharp.size() / 2), sharp_corners.data(),
            int(sharp_corners.size()), plan.level_vertex_types(d_.levels).data());
        local_ = std::make_unique<LocalRefiner>(*patches_, plan, control, mesh_.cone_vertices, mesh_.num_cones);
    }

    TessellationImpl& d_;
    const MeshView& mesh_;
    Options options_;
    Edges edges_;
    std::vector<bool> placed_;
    std::unique_ptr<LevelPatches> patches_;
    std::unique_ptr<LocalRefiner> local_;
    FacePattern pattern_;
    std::vector<std::int32_t> numbers_;
    Stencil stencil_;
};

}  // namespace

Tessellation::Tessellation(const MeshView& mesh, const Options& options, const TessellationRates& rates)
    : impl_(std::make_unique<TessellationImpl>()) {
    if (mesh.num_holes > 0) fail("holes are not supported");
    if (mesh.num_face_varying > 0) fail("face-varying layers are not supported");
    if (options.boundary == Boundary::None) fail("Boundary::None is not supported (it makes holes)");
    Builder(*impl_, mesh, options).build(rates);
}

Tessellation::~Tessellation() = default;
Tessellation::Tessellation(Tessellation&&) noexcept = default;
Tessellation& Tessellation::operator=(Tessellation&&) noexcept = default;

int Tessellation::num_points() const { return int(impl_->num_points); }
int Tessellation::num_triangles() const { return int(impl_->triangles.size() / 3); }
const std::int32_t* Tessellation::triangles() const { return impl_->triangles.data(); }
const std::int32_t* Tessellation::parent_triangles() const { return impl_->parent_triangles.data(); }
int Tessellation::num_face_points() const { return int(impl_->sample_vertex.size()); }
const std::int32_t* Tessellation::corner_face_points() const { return impl_->corner_face_points.data(); }
const float* Tessellation::face_point_parameters() const { return impl_->parameters.data(); }
int Tessellation::levels() const { return impl_->levels; }

void Tessellation::evaluate(const float* positions, float* points, float* normals) const {
    const TessellationImpl& d = *impl_;
    const ChannelsView<const float> in = interleaved(positions, 3);
    d.limit_points.resize(3 * std::size_t(d.limit->num_output_vertices()));
    d.limit_normals.resize(3 * std::size_t(d.limit->num_limit_normals()));
    d.limit->evaluate(in, interleaved(d.limit_points.data(), 3), Plan::LimitNormals{d.limit_normals.data()});
    if (d.control) {
        d.control_points.resize(3 * std::size_t(d.control->num_output_vertices()));
        d.control->evaluate(in, interleaved(d.control_points.data(), 3));
    }
    const std::size_t num_samples = d.sample_vertex.size();
    for (std::size_t s = 0; s < num_samples; ++s) {
        double p[3] = {0, 0, 0}, n[3] = {0, 0, 0};
        if (const std::int32_t v = d.sample_vertex[s]; v >= 0) {
            for (int c = 0; c < 3; ++c) p[c] = d.limit_points[3 * std::size_t(v) + c];
            for (int c = 0; c < 3; ++c) n[c] = d.limit_normals[3 * std::size_t(d.sample_normal[s]) + c];
        } else {
            double ds[3] = {0, 0, 0}, dt[3] = {0, 0, 0};
            for (std::int64_t i = d.stencil_offsets[s]; i < d.stencil_offsets[s + 1]; ++i) {
                const float* x = d.control_points.data() + 3 * std::size_t(d.stencil_points[std::size_t(i)]);
                const float* w = d.stencil_weights.data() + 3 * std::size_t(i);
                for (int c = 0; c < 3; ++c) p[c] += w[0] * x[c], ds[c] += w[1] * x[c], dt[c] += w[2] * x[c];
            }
            n[0] = ds[1] * dt[2] - ds[2] * dt[1], n[1] = ds[2] * dt[0] - ds[0] * dt[2],
            n[2] = ds[0] * dt[1] - ds[1] * dt[0];
            const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            for (double& c : n) c = length > 0.0 ? c / length : 0.0;
        }
        if (const std::int32_t point = d.sample_point[s]; point >= 0)
            for (int c = 0; c < 3; ++c) points[3 * std::size_t(point) + c] = float(p[c]);
        if (normals)
            for (int c = 0; c < 3; ++c) normals[3 * s + c] = float(n[c]);
    }
}

}  // namespace loopsub
