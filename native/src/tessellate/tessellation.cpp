// A Tessellation: the points of every input triangle's pattern (topology/tessellation_pattern.h), each placed on the
// limit surface. An input triangle that is a regular patch itself (level_patches.h) takes every point from the box
// spline of the input's own points, whatever its rates. The others go through plans of the levels their rates need,
// made on the mesh of those triangles and the triangles around their corners (all that shapes them): with L levels,
// 2^L at least their largest rate, no point lies inside a level-L triangle at an input vertex (where the surface is
// irregular) other than the vertex itself, so a point at a vertex of a level takes the limit plan's point and normal,
// and every other point a stencil over the level's control points, a box spline where its triangle is a regular patch
// and the refined neighbourhood's (local_refinement.h) where a semi-sharp edge or a non-manifold one leaves the
// triangle irregular.
#include "loopsub/tessellation.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <deque>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>

#include "base/parallel.h"
#include "kernels/kernels.h"
#include "tessellate/level_patches.h"
#include "tessellate/local_refinement.h"
#include "topology/tessellation_pattern.h"

namespace loopsub {

struct KeptInput;

struct TessellationImpl {
    std::shared_ptr<const KeptInput> input;  // what the build read of the mesh alone (InputTopology)
    int levels = 0;
    int threads = 1;
    int num_input_vertices = 0;
    std::int64_t num_points = 0;
    std::vector<std::int32_t> triangles, parent_triangles, corner_face_points;
    std::vector<float> parameters;  // (u, v) per face point
    // A sample per face point, the normals' rows. In a triangle that is a patch of the input, its triangle's blocks
    // of weights (below) say everything. Elsewhere: at a vertex of the level, the limit plan's point and normal row;
    // in a regular patch of the level, the patch and the weights at its place there; else a stencil of its own.
    enum class Kind : std::uint8_t { Vertex, Patch, Stencil, InputPatch };
    struct Sample {
        Kind kind;
        std::uint8_t band;  // Vertex, Patch, Stencil: whose plans (below)
        std::int32_t a, b;  // Vertex: vertex, normal row; Patch: patch, weights; Stencil: stencil; InputPatch: none
    };
    std::vector<Sample> samples;
    std::vector<std::int32_t> sample_point;  // the point a sample places, -1 where an earlier sample places it
    // Per input triangle: its first sample (and one more), and its patch among input_patch_points (-1: through the
    // plans, on the submesh) with the blocks of weights of its points (kernels.h, PatchFn), one per part of its
    // pattern: its corners, each edge's points, its inner points (-1: none).
    static constexpr int kParts = 5;
    static constexpr int kInnerPart = kParts - 1;  // a triangle's own points, numbered one after the other
    std::vector<std::int32_t> face_first_sample, face_patch, face_blocks;
    std::vector<std::int32_t> input_patch_points;  // 12 per patch of the input's own points
    // A block per part of a pattern, its rate and its patch's shape, shared by every triangle that has the same: its
    // samples, its stride and where its weights start.
    struct Block {
        int count, stride;
        std::size_t first;
    };
    std::vector<Block> blocks;
    std::vector<float> block_weights;
    detail::PatchFn patch_kernel = nullptr;
    // The input triangles that are no patch themselves, in bands by the levels their rates need: each band's plans
    // (control points and limit) on the mesh of its triangles and those around their corners, whose vertices are the
    // input's `vertices`.
    struct Band {
        int levels = 0, limit_levels = 0;
        std::vector<std::int32_t> vertices;
        std::unique_ptr<Plan> control, limit;
        mutable std::vector<float> positions, control_points, limit_points, limit_normals;
    };
    std::vector<Band> bands;
    std::vector<std::int32_t> patch_points;  // 12 per patch (phantoms -1, weighted 0)
    std::vector<float> patch_weights;        // 36 per weight set: position, d/ds, d/dt of each of 12 points
    std::vector<std::int64_t> stencil_offsets{0};
    std::vector<std::int32_t> stencil_points;
    std::vector<float> stencil_weights;  // position, d/ds, d/dt per entry
    // Face-varying layers: each its input level as a mesh of its own, cut by the same rates, whose face points are
    // this tessellation's one for one; or (FaceVaryingInterpolation::All) linear in each triangle, from the caller's
    // value at each input corner.
    struct Layer {
        int num_values = 0;
        std::vector<std::int32_t> base_values;       // per vertex of the layer's mesh: the caller's value
        std::unique_ptr<Tessellation> surface;       // none: linear
        std::vector<std::int32_t> face_point_point;  // the surface's point at each face point
        std::vector<std::int32_t> corner_values;     // linear: the caller's value at each input corner
    };
    std::vector<Layer> layers;
    std::vector<std::int32_t> face_point_parent;  // each face point's input triangle (the linear layers read it)
    std::uint64_t estimated_bytes = 0;            // Tessellation::estimated_bytes
};

namespace {

// The position, and the unit normal of the derivatives s x t (zero where they span no plane).
void finish_sums(const float* p, const float* s, const float* t, float position[3], float normal[3]) {
    const double n[3] = {double(s[1]) * t[2] - double(s[2]) * t[1], double(s[2]) * t[0] - double(s[0]) * t[2],
                         double(s[0]) * t[1] - double(s[1]) * t[0]};
    const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const double inverse = length > 0.0 ? 1.0 / length : 0.0;
    for (int c = 0; c < 3; ++c) position[c] = p[c], normal[c] = float(n[c] * inverse);
}

using detail::FacePattern;
using detail::FacePoint;
using detail::LevelPatches;
using detail::LocalMesh;
using detail::LocalRefiner;
using detail::Patch;
using detail::Stencil;
using Kind = TessellationImpl::Kind;

// Sums of weighted control points (3 floats each, read four at a time: the buffer has a float to spare at its end):
// the position and its two derivatives, then the position and unit normal they give. SSE2, every x86-64's, with its
// scalar twin elsewhere.
#if defined(__SSE2__)
class PointSums {
public:
    void add(const float* x, float wp, float ws, float wt) {
        const __m128 v = _mm_loadu_ps(x);
        p_ = _mm_add_ps(p_, _mm_mul_ps(_mm_set1_ps(wp), v));
        s_ = _mm_add_ps(s_, _mm_mul_ps(_mm_set1_ps(ws), v));
        t_ = _mm_add_ps(t_, _mm_mul_ps(_mm_set1_ps(wt), v));
    }
    void finish(float position[3], float normal[3]) const {
        alignas(16) float p[4], s[4], t[4];
        _mm_store_ps(p, p_), _mm_store_ps(s, s_), _mm_store_ps(t, t_);
        finish_sums(p, s, t, position, normal);
    }

private:
    __m128 p_ = _mm_setzero_ps(), s_ = _mm_setzero_ps(), t_ = _mm_setzero_ps();
};
#else
class PointSums {
public:
    void add(const float* x, float wp, float ws, float wt) {
        for (int c = 0; c < 3; ++c) p_[c] += wp * x[c], s_[c] += ws * x[c], t_[c] += wt * x[c];
    }
    void finish(float position[3], float normal[3]) const { finish_sums(p_, s_, t_, position, normal); }

private:
    float p_[3] = {0, 0, 0}, s_[3] = {0, 0, 0}, t_[3] = {0, 0, 0};
};
#endif

// A point's three floats. std::copy_n of three compiles to a call of memmove, which cost more than the copy once per
// sample (docs/benchmark.md, "The tessellation's frame").
void copy_point(const float* from, float* to) { to[0] = from[0], to[1] = from[1], to[2] = from[2]; }

[[noreturn]] void fail(const std::string& message) { throw InputError("tessellation: " + message); }

// what(): the rate's name, made only for the error.
template <typename Name>
int rate_in_range(int rate, Name what) {
    if (rate < 1 || rate > kMaxTessellationRate)
        fail(what() + " must be between 1 and " + std::to_string(kMaxTessellationRate) + ", got " +
             std::to_string(rate));
    return rate;
}

}  // namespace

// What a build reads of the input mesh alone, whatever the rates: the limit plan of no levels (it checks the mesh and
// the options, and classifies the input's vertices), the input triangles that are regular patches, the edges. Kept
// (InputTopology) for one of the same mesh at other rates, which takes it where the triangles, tags and rules are the
// same. Read only once made: tessellations on other threads may share it.
struct KeptInput {
    KeptInput(const MeshView& mesh, const Options& options)
        : mesh_(copy_of(mesh)),
          rules_(options.rules),
          boundary_(options.boundary),
          crease_method_(options.crease_method),
          crease_threshold_(options.crease_threshold) {
        Options input = options;
        input.limit_surface = true, input.levels = 0;
        plan = std::make_unique<Plan>(mesh, input);
        patches = std::make_unique<LevelPatches>(*plan);
        face_patch.assign(std::size_t(mesh.num_triangles), -1);
        for (int f = 0; f < mesh.num_triangles; ++f) {  // every face asked now, so that nothing is ordered later
            detail::Patch patch;
            if (!patches->find_patch(f, patch)) continue;
            face_patch[std::size_t(f)] = std::int32_t(patch_list.size());
            patch_list.push_back(patch);
        }
        edges = detail::sorted_edges(mesh.triangles, mesh.num_triangles);
    }

    // Whether this was made for the same triangles, tags and rules.
    bool made_for(const MeshView& mesh, const Options& options) const {
        auto same = [](const auto& kept, const auto* given, int count) {
            return kept.size() == std::size_t(count) && std::equal(kept.begin(), kept.end(), given);
        };
        return mesh.num_vertices == mesh_.num_vertices &&
               same(mesh_.triangles, mesh.triangles, 3 * mesh.num_triangles) &&
               same(mesh_.crease_edges, mesh.crease_edges, 2 * mesh.num_crease_edges) &&
               same(mesh_.crease_sharpness, mesh.crease_sharpness, mesh.num_crease_edges) &&
               same(mesh_.corner_vertices, mesh.corner_vertices, mesh.num_corners) &&
               same(mesh_.corner_sharpness, mesh.corner_sharpness, mesh.num_corners) &&
               same(mesh_.cone_vertices, mesh.cone_vertices, mesh.num_cones) && options.rules == rules_ &&
               options.boundary == boundary_ && options.crease_method == crease_method_ &&
               options.crease_threshold == crease_threshold_;
    }

    int find_edge(std::int32_t a, std::int32_t b) const {
        const auto at = std::lower_bound(edges.keys.begin(), edges.keys.end(), detail::edge_key(a, b));
        return at != edges.keys.end() && *at == detail::edge_key(a, b) ? int(at - edges.keys.begin()) : -1;
    }

    std::unique_ptr<Plan> plan;
    std::unique_ptr<LevelPatches> patches;
    std::vector<std::int32_t> face_patch;  // per input triangle, its patch in patch_list, or -1
    std::vector<detail::Patch> patch_list;
    detail::SortedEdges edges;

private:
    struct Kept {  // the mesh's triangles and tags
        int num_vertices = 0;
        std::vector<std::int32_t> triangles, crease_edges, corner_vertices, cone_vertices;
        std::vector<float> crease_sharpness, corner_sharpness;
    };
    static Kept copy_of(const MeshView& mesh) {
        Kept kept;
        kept.num_vertices = mesh.num_vertices;
        auto copy = [](auto& to, const auto* from, int count) {
            if (count > 0) to.assign(from, from + count);
        };
        copy(kept.triangles, mesh.triangles, 3 * mesh.num_triangles);
        copy(kept.crease_edges, mesh.crease_edges, 2 * mesh.num_crease_edges);
        copy(kept.crease_sharpness, mesh.crease_sharpness, mesh.num_crease_edges);
        copy(kept.corner_vertices, mesh.corner_vertices, mesh.num_corners);
        copy(kept.corner_sharpness, mesh.corner_sharpness, mesh.num_corners);
        copy(kept.cone_vertices, mesh.cone_vertices, mesh.num_cones);
        return kept;
    }
    Kept mesh_;
    Rules rules_;
    Boundary boundary_;
    CreaseMethod crease_method_;
    float crease_threshold_;
};

struct InputTopologyParts {
    std::shared_ptr<const KeptInput> surface;
    std::vector<InputTopology> layers;  // each face-varying layer's cut's
};

InputTopology::InputTopology() = default;
InputTopology::~InputTopology() = default;
InputTopology::InputTopology(const InputTopology&) = default;
InputTopology& InputTopology::operator=(const InputTopology&) = default;
bool InputTopology::empty() const { return !parts_; }

namespace {

// The input's edges' rates (in KeptInput::edges' order), and the number of each one's first inner point.
struct EdgeRates {
    std::vector<int> rates;
    std::vector<std::int64_t> first_point;
};

EdgeRates edges_with_rates(const KeptInput& input, int num_vertices, const TessellationRates& rates) {
    EdgeRates edges;
    const int uniform = rate_in_range(rates.uniform_rate, [] { return std::string("uniform_rate"); });
    edges.rates.assign(input.edges.keys.size(), uniform);
    if (rates.num_edges < 0) fail("num_edges must not be negative");
    for (int k = 0; k < rates.num_edges; ++k) {
        const std::int32_t a = rates.edges[2 * k], b = rates.edges[2 * k + 1];
        // screen_space_rates gives the edges in this order: then the k-th is the one.
        const int e =
            std::size_t(k) < input.edges.keys.size() && input.edges.keys[std::size_t(k)] == detail::edge_key(a, b)
                ? k
                : input.find_edge(a, b);
        auto name = [a, b] { return "edge (" + std::to_string(a) + ", " + std::to_string(b) + ")"; };
        if (e < 0) fail("a rate for " + name() + ", which no triangle has");
        edges.rates[std::size_t(e)] = rate_in_range(rates.rates[k], [&] { return "the rate of " + name(); });
    }
    std::int64_t next = num_vertices;
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
    // What building a band needs: its submesh (make_submesh), each input triangle's number in it (-1: none), its
    // level's patches and local refinement.
    struct BandBuilder {
        std::vector<std::int32_t> face;
        LocalMesh mesh;
        MeshView view;
        std::unique_ptr<LevelPatches> patches;
        std::unique_ptr<LocalRefiner> local;
    };

public:
    Builder(TessellationImpl& d, const MeshView& mesh, const Options& options)
        : d_(d), mesh_(mesh), options_(options) {}

    // kept: an earlier build's input, taken where it was made for the same mesh.
    void build(const TessellationRates& rates, const std::shared_ptr<const KeptInput>& kept) {
        // The input first: its limit plan of no levels checks the mesh and the options before anything reads them (a
        // kept one checked the same).
        d_.input = kept && kept->made_for(mesh_, options_) ? kept : std::make_shared<const KeptInput>(mesh_, options_);
        const KeptInput& input = *d_.input;
        options_.limit_surface = true;  // the bands' limit plans (their levels set each)
        const EdgeRates edges = edges_with_rates(input, mesh_.num_vertices, rates);
        d_.num_input_vertices = mesh_.num_vertices;

        std::vector<Sides> sides(std::size_t(mesh_.num_triangles));
        std::vector<std::int64_t> face_first(std::size_t(mesh_.num_triangles));
        std::int64_t next =
            edges.first_point.empty() ? mesh_.num_vertices : edges.first_point.back() + edges.rates.back() - 1;
        std::int64_t num_samples = 0, num_triangles = 0;
        d_.face_patch.assign(std::size_t(mesh_.num_triangles), -1);
        face_band_.assign(std::size_t(mesh_.num_triangles), -1);
        for (int f = 0; f < mesh_.num_triangles; ++f) {
            Sides& s = sides[std::size_t(f)];
            for (int k = 0; k < 3; ++k) {
                const std::int32_t a = mesh_.triangles[3 * f + k], b = mesh_.triangles[3 * f + (k + 1) % 3];
                const std::size_t e = std::size_t(input.edges.corner_edges[3 * std::size_t(f) + std::size_t(k)]);
                s.rates[k] = edges.rates[e], s.first_point[k] = edges.first_point[e];
                s.along[k] = a < b;
            }
            face_first[std::size_t(f)] = next;
            const std::int64_t inner = detail::num_inner_points(s.rates, s.inner_rate());
            next += inner;
            num_samples += detail::first_edge_point(s.rates, 3) + inner;
            num_triangles += detail::num_pattern_triangles(s.rates, s.inner_rate());
            if (const std::int32_t found = input.face_patch[std::size_t(f)]; found >= 0) {
                const Patch& patch = input.patch_list[std::size_t(found)];
                d_.face_patch[std::size_t(f)] = std::int32_t(input_shapes_.size());
                d_.input_patch_points.insert(d_.input_patch_points.end(), patch.points,
                                             patch.points + detail::kBoxSplinePoints);
                input_shapes_.push_back({patch.rotation, patch.shape});
                continue;
            }
            // Its band: the levels its rates need (2^L at least its largest). The points at vertices of a level are
            // those i / r along an edge of rate r, or of the inner lattice, whose denominator, reduced, is a power of
            // two: vertices of the level of the largest power of two in any rate, which the band's limit plan need go
            // no deeper than.
            int levels = 0;
            while ((1 << levels) < s.inner_rate()) ++levels;
            const auto [band, added] = band_of_levels_.try_emplace(levels, int(d_.bands.size()));
            if (added) d_.bands.emplace_back().levels = levels, band_builders_.emplace_back();
            face_band_[std::size_t(f)] = band->second;
            TessellationImpl::Band& b = d_.bands[std::size_t(band->second)];
            for (int rate : {s.rates[0], s.rates[1], s.rates[2], s.inner_rate()})
                b.limit_levels = std::max(b.limit_levels, two_adic(rate));
            d_.levels = std::max(d_.levels, levels);
        }
        // What the result holds: per face point its sample, point, parameters and a normal; per triangle its corners,
        // their face points and its parent; per point its position. Then each band's two plans (limit and control
        // points, Plan::estimate_bytes of its submesh): one budget for all, checked before any of them is made.
        std::uint64_t bytes =
            std::uint64_t(num_samples) * 40 + std::uint64_t(num_triangles) * 28 + std::uint64_t(next) * 16;
        const std::uint64_t result_bytes = bytes;
        for (std::size_t b = 0; b < d_.bands.size(); ++b) {
            make_submesh(*input.patches, int(b));
            const MeshView& sub = band_builders_[b].view;
            const auto sub_edges = std::int64_t(detail::sorted_edge_keys(sub.triangles, sub.num_triangles).size());
            for (int levels : {d_.bands[b].limit_levels, d_.bands[b].levels})
                bytes += Plan::estimate_bytes(sub.num_vertices, sub.num_triangles, levels, 3, sub_edges);
        }
        if (bytes > options_.memory_limit_bytes)
            throw MemoryLimitError("tessellation: " + std::to_string(num_triangles) + " triangles would need about " +
                                       describe_bytes(bytes) + " (the result " + describe_bytes(result_bytes) +
                                       ", the plans of the triangles that are no patch the rest), more than the "
                                       "limit of " +
                                       describe_bytes(options_.memory_limit_bytes),
                                   bytes);
        if (next > std::int64_t(INT32_MAX) || num_samples > std::int64_t(INT32_MAX) ||
            3 * num_triangles > std::int64_t(INT32_MAX))
            throw MemoryLimitError("tessellation: more than 2^31 points", bytes);
        refinement_bytes_ = {options_.memory_limit_bytes, bytes, bytes};
        for (std::size_t b = 0; b < d_.bands.size(); ++b) {
            options_.levels = d_.bands[b].limit_levels;
            d_.bands[b].limit = std::make_unique<Plan>(band_builders_[b].view, options_);
        }
        d_.num_points = next;
        placed_.assign(std::size_t(next), 0);
        d_.samples.reserve(std::size_t(num_samples)), d_.sample_point.reserve(std::size_t(num_samples));
        d_.triangles.reserve(3 * std::size_t(num_triangles)),
            d_.corner_face_points.reserve(3 * std::size_t(num_triangles));
        d_.parent_triangles.reserve(std::size_t(num_triangles));
        d_.parameters.reserve(2 * std::size_t(num_samples));
        subface_patch_.assign(std::size_t(1) << 2 * d_.levels, kUnknown);
        for (int f = 0; f < mesh_.num_triangles; ++f) add_face(f, sides[std::size_t(f)], face_first[std::size_t(f)]);
        d_.face_first_sample.push_back(std::int32_t(d_.samples.size()));
        d_.estimated_bytes = refinement_bytes_.peak;
    }

private:
    void add_face(int f, const Sides& s, std::int64_t face_first) {
        // A pattern depends on the rates alone: made once for each triple of them (at one rate, once in all), with its
        // points' parameters.
        const auto [cached, added] = patterns_.try_emplace({s.rates[0], s.rates[1], s.rates[2]});
        if (added) {
            detail::tessellate_triangle(s.rates, s.inner_rate(), cached->second.pattern);
            for (const detail::PatternPoint& at : cached->second.pattern.points)
                cached->second.parameters.insert(cached->second.parameters.end(),
                                                 {float(double(at.b1) / at.den), float(double(at.b2) / at.den)});
        }
        const FacePattern& pattern = cached->second.pattern;
        const int first_inner = detail::first_edge_point(s.rates, 3);
        std::vector<std::int32_t>& number = numbers_;
        number.resize(pattern.points.size());
        int p = 0;
        for (; p < 3; ++p) number[std::size_t(p)] = mesh_.triangles[3 * f + p];
        for (int k = 0; k < 3; ++k)
            for (int i = 1; i < s.rates[k]; ++i, ++p)
                number[std::size_t(p)] = std::int32_t(s.first_point[k] + (s.along[k] ? i : s.rates[k] - i) - 1);
        for (; p < int(pattern.points.size()); ++p)  // TessellationImpl::kInnerPart
            number[std::size_t(p)] = std::int32_t(face_first + p - first_inner);

        const int first_sample = int(d_.samples.size());
        d_.face_first_sample.push_back(first_sample);
        for (std::int32_t within : touched_) subface_patch_[std::size_t(within)] = kUnknown;
        touched_.clear();
        const std::int32_t input_patch = d_.face_patch[std::size_t(f)];
        for (const std::int32_t point : number) {
            d_.sample_point.push_back(placed_[std::size_t(point)] ? -1 : point);
            placed_[std::size_t(point)] = 1;
        }
        d_.parameters.insert(d_.parameters.end(), cached->second.parameters.begin(), cached->second.parameters.end());
        if (input_patch >= 0) d_.samples.insert(d_.samples.end(), pattern.points.size(), {Kind::InputPatch, 0, -1, -1});
        else
            for (const detail::PatternPoint& at : pattern.points)
                add_sample(face_band_[std::size_t(f)], FacePoint{at.b1, at.b2, at.den}, f);
        for (int part = 0; part < TessellationImpl::kParts; ++part)
            d_.face_blocks.push_back(input_patch >= 0 ? block(pattern, s, part, input_shapes_[std::size_t(input_patch)])
                                                      : -1);
        const std::size_t corners = d_.triangles.size();
        d_.triangles.resize(corners + pattern.triangles.size());
        d_.corner_face_points.resize(corners + pattern.triangles.size());
        for (std::size_t c = 0; c < pattern.triangles.size(); ++c) {
            const std::int32_t p = pattern.triangles[c];
            d_.triangles[corners + c] = number[std::size_t(p)];
            d_.corner_face_points[corners + c] = first_sample + p;
        }
        d_.parent_triangles.insert(d_.parent_triangles.end(), pattern.triangles.size() / 3, f);
    }

    // A point of input triangle f, which is in band `band`.
    void add_sample(int band, FacePoint at, int f) {
        const TessellationImpl::Band& b = d_.bands[std::size_t(band)];
        BandBuilder& bb = band_builders_[std::size_t(band)];
        int t = bb.face[std::size_t(f)], within = 0;  // the level's triangle, and its number among f's descendants
        for (int l = 0; l <= b.levels; ++l) {
            if (l == b.limit_levels) {  // a vertex here, or never one
                const int corner = at.T == 0 ? (at.S == 0      ? 0
                                                : at.S == at.D ? 1
                                                               : -1)
                                             : (at.S == 0 && at.T == at.D ? 2 : -1);
                if (corner >= 0) return add_vertex(band, t, corner);
            }
            if (l == b.levels) break;
            const int child = detail::descend(at);
            t = 4 * t + child, within = 4 * within + child;
        }
        if (!bb.patches) make_control(band);
        std::int32_t& patch = subface_patch_[std::size_t(within)];
        if (patch == kUnknown) patch = find_patch(bb, t), touched_.push_back(within);
        const std::uint8_t in_band = std::uint8_t(band);
        if (patch >= 0) {
            const auto [rotation, shape] = patch_shape_[std::size_t(patch)];
            d_.samples.push_back({Kind::Patch, in_band, patch, weight_set(rotation, shape, at)});
            return;
        }
        bb.local->weights(t, at, stencil_);
        d_.samples.push_back({Kind::Stencil, in_band, std::int32_t(d_.stencil_offsets.size() - 1), 0});
        for (std::size_t i = 0; i < stencil_.points.size(); ++i) {
            d_.stencil_points.push_back(stencil_.points[i]);
            const float w[3] = {float(stencil_.position[i]), float(stencil_.ds[i]), float(stencil_.dt[i])};
            d_.stencil_weights.insert(d_.stencil_weights.end(), w, w + 3);
        }
        d_.stencil_offsets.push_back(std::int64_t(d_.stencil_points.size()));
    }

    // The block of weights of one part of `pattern` (made for `sides`: 0 its corners, 1 to 3 the
    // points of edge 0 to 2, 4 its inner points) in a patch of this rotation and shape; -1 for a part with no points.
    // The points of a part are where they are in every pattern with that part's rate.
    std::int32_t block(const FacePattern& pattern, const Sides& sides, int part,
                       std::pair<int, detail::PatchShape> shape) {
        const int begin = part == 0 ? 0 : detail::first_edge_point(sides.rates, part - 1);
        const int end = part == 0  ? 3
                        : part < 4 ? detail::first_edge_point(sides.rates, part)
                                   : int(pattern.points.size());
        if (begin == end) return -1;
        // The inner points depend on the inner rate, and on whether the rates differ below an inner rate of 3 (a
        // centre).
        const int rate = part == 0  ? 0
                         : part < 4 ? sides.rates[part - 1]
                                    : (end - begin == 1 ? -1 : sides.inner_rate());
        const BlockKey key{part, rate, shape.first, shape.second};
        const auto [found, added] = blocks_.try_emplace(key, std::int32_t(d_.blocks.size()));
        if (!added) return found->second;
        const int count = end - begin, stride = (count + 7) / 8 * 8;
        d_.blocks.push_back({count, stride, d_.block_weights.size()});
        d_.block_weights.resize(d_.block_weights.size() + std::size_t(3 * kPoints) * std::size_t(stride), 0.0f);
        float* weights = &d_.block_weights[d_.blocks.back().first];
        Patch patch;
        patch.rotation = shape.first, patch.shape = shape.second;
        for (int q = 0; q < count; ++q) {
            const detail::PatternPoint& at = pattern.points[std::size_t(begin + q)];
            detail::PatchWeights w;
            detail::patch_weights(patch, double(at.b1) / at.den, double(at.b2) / at.den, w);
            const double* kinds[3] = {w.position, w.ds, w.dt};
            for (int k = 0; k < 3; ++k)
                for (int i = 0; i < kPoints; ++i)
                    weights[std::size_t(kPoints * k + i) * std::size_t(stride) + std::size_t(q)] = float(kinds[k][i]);
        }
        return found->second;
    }

    // A point at corner `corner` of triangle t of the band's limit plan.
    void add_vertex(int band, int t, int corner) {
        const Plan& limit = *d_.bands[std::size_t(band)].limit;
        const std::size_t c = 3 * std::size_t(t) + std::size_t(corner);
        d_.samples.push_back(
            {Kind::Vertex, std::uint8_t(band), limit.output_triangles()[c], limit.corner_normal_indices()[c]});
    }

    // The level's triangle t as a patch of the tessellation (its number), or -1 where it is no regular patch.
    std::int32_t find_patch(const BandBuilder& bb, int t) {
        Patch patch;
        if (!bb.patches->find_patch(t, patch)) return -1;
        const std::int32_t number = std::int32_t(d_.patch_points.size() / detail::kBoxSplinePoints);
        for (std::int32_t p : patch.points) d_.patch_points.push_back(p);
        patch_shape_.push_back({patch.rotation, patch.shape});
        return number;
    }

    // The weights at a point of a patch: shared by every point at the same place in a patch of the same shape (at one
    // rate, the points of every input triangle).
    std::int32_t weight_set(int rotation, detail::PatchShape shape, const FacePoint& at) {
        const WeightKey key{at.S, at.T, at.D, rotation, shape};
        const auto [found, added] =
            weight_sets_.try_emplace(key, std::int32_t(d_.patch_weights.size() / (3 * kPoints)));
        if (!added) return found->second;
        Patch patch;
        patch.rotation = rotation, patch.shape = shape;
        detail::PatchWeights w;
        detail::patch_weights(patch, double(at.S) / double(at.D), double(at.T) / double(at.D), w);
        for (const double* part : {w.position, w.ds, w.dt})
            for (int i = 0; i < kPoints; ++i) d_.patch_weights.push_back(float(part[i]));
        return found->second;
    }

    // The mesh of a band's plans: its input triangles and the triangles around their corners, which shape them
    // (local_refinement.h); a vertex of it, the input's vertices[v]; the input's tags on it.
    void make_submesh(const LevelPatches& input, int band) {
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
                if (local[std::size_t(v)] < 0)
                    local[std::size_t(v)] = std::int32_t(vertices.size()), vertices.push_back(v);
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

    // A band's control points' plan and its patches, on the first point that needs them.
    void make_control(int band) {
        TessellationImpl::Band& b = d_.bands[std::size_t(band)];
        BandBuilder& bb = band_builders_[std::size_t(band)];
        Options control = options_;
        control.limit_surface = false, control.levels = b.levels;
        b.control = std::make_unique<Plan>(bb.view, control);
        bb.patches = std::make_unique<LevelPatches>(*b.control);
        bb.local = std::make_unique<LocalRefiner>(*bb.patches, *b.control, control, bb.mesh.cones.data(),
                                                  int(bb.mesh.cones.size()), refinement_bytes_);
    }

    static int two_adic(int rate) {  // the exponent of the largest power of two dividing rate
        int e = 0;
        while (rate % 2 == 0) rate /= 2, ++e;
        return e;
    }

    TessellationImpl& d_;
    std::map<int, int> band_of_levels_;
    std::vector<int> face_band_;             // per input triangle, -1 for a patch of the input
    std::deque<BandBuilder> band_builders_;  // a deque: each band's view points into its arrays
    const MeshView& mesh_;
    Options options_;
    std::vector<std::uint8_t> placed_;
    static constexpr std::int32_t kUnknown = -2;
    // Per level triangle of the input triangle at hand: its patch, or -1; and those that have been asked.
    std::vector<std::int32_t> subface_patch_, touched_;
    std::vector<std::pair<int, detail::PatchShape>> patch_shape_, input_shapes_;  // per patch: rotation, shape
    struct WeightKey {
        std::int64_t S, T, D;
        int rotation;
        detail::PatchShape shape;
        bool operator==(const WeightKey& o) const {
            return S == o.S && T == o.T && D == o.D && rotation == o.rotation && shape == o.shape;
        }
    };
    struct WeightKeyHash {
        std::size_t operator()(const WeightKey& k) const {
            return std::hash<std::int64_t>()(((k.S * 1000003 + k.T) * 1000003 + k.D) * 16 + k.rotation * 4 +
                                             int(k.shape));
        }
    };
    std::unordered_map<WeightKey, std::int32_t, WeightKeyHash> weight_sets_;
    static constexpr int kPoints = detail::kBoxSplinePoints;
    using BlockKey = std::tuple<int, int, int, detail::PatchShape>;  // part, its rate, rotation, shape
    std::map<BlockKey, std::int32_t> blocks_;
    struct CachedPattern {
        FacePattern pattern;
        std::vector<float> parameters;  // (u, v) per point
    };
    std::map<std::tuple<int, int, int>, CachedPattern> patterns_;
    std::vector<std::int32_t> numbers_;
    Stencil stencil_;
    detail::RefinementBytes refinement_bytes_;  // Tessellation::estimated_bytes, with what local refinement held
};

}  // namespace

namespace {

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

    std::unordered_map<std::uint64_t, float> crease_of;
    for (int e = 0; e < mesh.num_crease_edges; ++e)
        crease_of[detail::edge_key(mesh.crease_edges[2 * e], mesh.crease_edges[2 * e + 1])] = mesh.crease_sharpness[e];
    std::unordered_map<std::int32_t, float> corner_of;
    for (int k = 0; k < mesh.num_corners; ++k) corner_of[mesh.corner_vertices[k]] = mesh.corner_sharpness[k];
    std::vector<bool> cone(std::size_t(mesh.num_vertices), false);
    for (int k = 0; k < mesh.num_cones; ++k) cone[std::size_t(mesh.cone_vertices[k])] = true;
    std::vector<int> faces_at(std::size_t(mesh.num_vertices), 0);
    for (std::size_t c = 0; c < corners; ++c) ++faces_at[std::size_t(mesh.triangles[c])];
    std::unordered_map<std::uint64_t, int> rate_of;
    for (int e = 0; e < rates.num_edges; ++e)
        rate_of[detail::edge_key(rates.edges[2 * e], rates.edges[2 * e + 1])] = rates.rates[e];

    for (int k = 0; k < mesh.num_face_varying; ++k) {
        TessellationImpl::Layer& layer = d.layers.emplace_back();
        layer.num_values = mesh.face_varying[k].num_values;
        const Plan::FaceVaryingBase base = plan.face_varying_base(k);
        layer.base_values = base.values;
        const int n = int(base.values.size());
        std::vector<std::int32_t> vertex_of(static_cast<std::size_t>(n));
        for (std::size_t c = 0; c < corners; ++c) vertex_of[std::size_t(base.corner_values[c])] = mesh.triangles[c];

        detail::LocalMesh tags;
        std::vector<std::int32_t> edges, edge_rates;
        std::unordered_map<std::uint64_t, bool> seen;
        for (std::size_t c = 0; c < corners; ++c) {
            const std::size_t next = c - c % 3 + (c + 1) % 3;
            const std::int32_t x = base.corner_values[c], y = base.corner_values[next];
            if (!seen.try_emplace(detail::edge_key(x, y), true).second) continue;
            const std::uint64_t key = detail::edge_key(mesh.triangles[c], mesh.triangles[next]);
            if (const auto crease = crease_of.find(key); crease != crease_of.end())
                tags.creases.insert(tags.creases.end(), {x, y}), tags.crease_sharpness.push_back(crease->second);
            const auto rate = rate_of.find(key);
            edges.insert(edges.end(), {x, y}),
                edge_rates.push_back(rate != rate_of.end() ? rate->second : rates.uniform_rate);
        }
        for (std::int32_t x = 0; x < n; ++x) {
            const std::int32_t v = vertex_of[std::size_t(x)];
            const auto corner = corner_of.find(v);
            float sharpness = 0.0f;
            switch (base.classes[std::size_t(x)]) {
                case FaceVaryingValueClass::Stays: sharpness = kInfiniteSharpness; break;
                case FaceVaryingValueClass::Vertex:  // the vertex's own rules: its tags, its corner of one face
                    if (corner != corner_of.end()) sharpness = corner->second;
                    if (options.boundary == Boundary::EdgesAndCorners && faces_at[std::size_t(v)] == 1)
                        sharpness = kInfiniteSharpness;
                    if (cone[std::size_t(v)]) tags.cones.push_back(x);
                    break;
                case FaceVaryingValueClass::Held:  // by the vertex's own sharpness (its span's edges are carried)
                    if (corner != corner_of.end()) sharpness = corner->second;
                    break;
                case FaceVaryingValueClass::Seam: break;
            }
            if (sharpness > 0.0f) tags.corners.push_back(x), tags.corner_sharpness.push_back(sharpness);
        }
        tags.triangles = base.corner_values;
        Options cut = options;
        cut.boundary = Boundary::EdgesOnly;  // a corner of one face is tagged above where the rules make one
        TessellationRates layer_rates;
        layer_rates.uniform_rate = rates.uniform_rate;
        layer_rates.edges = edges.data(), layer_rates.rates = edge_rates.data();
        layer_rates.num_edges = int(edge_rates.size());
        // The layer's cut spends what the surface's left of the memory limit.
        cut.memory_limit_bytes = options.memory_limit_bytes - std::min(options.memory_limit_bytes, d.estimated_bytes);
        const InputTopology kept =
            reuse != nullptr && std::size_t(k) < reuse->layers.size() ? reuse->layers[std::size_t(k)] : InputTopology();
        try {
            layer.surface = std::make_unique<Tessellation>(tags.view(n), cut, layer_rates, kept);
        } catch (const MemoryLimitError& error) {
            const std::uint64_t total = d.estimated_bytes + error.required_bytes;
            throw MemoryLimitError("tessellation: with face-varying layer " + std::to_string(k) +
                                       " it would need about " + describe_bytes(total) + ", more than the limit of " +
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
}

}  // namespace

Tessellation::Tessellation(const MeshView& mesh, const Options& options, const TessellationRates& rates,
                           const InputTopology& reuse)
    : impl_(std::make_unique<TessellationImpl>()) {
    if (mesh.num_holes > 0) fail("holes are not supported");
    if (options.boundary == Boundary::None) fail("Boundary::None is not supported (it makes holes)");
    impl_->threads = std::max(1, options.threads);
    impl_->patch_kernel = detail::kernel_functions(detail::resolve_kernel(options.kernel)).patch;
    MeshView surface = mesh;
    surface.face_varying = nullptr, surface.num_face_varying = 0;
    const InputTopologyParts* kept = reuse.parts_.get();
    Builder(*impl_, surface, options).build(rates, kept != nullptr ? kept->surface : nullptr);
    if (mesh.num_face_varying > 0) add_face_varying_layers(*impl_, mesh, options, rates, kept);
}

int Tessellation::num_face_varying_layers() const { return int(impl_->layers.size()); }

void Tessellation::evaluate_face_varying(int layer, const float* values, int channels, float* out) const {
    const TessellationImpl& d = *impl_;
    if (layer < 0 || layer >= int(d.layers.size()))
        throw InputError("tessellation: face-varying layer " + std::to_string(layer) + " is not in 0.." +
                         std::to_string(int(d.layers.size()) - 1));
    if (channels < 1) throw InputError("tessellation: at least one face-varying channel is needed");
    const TessellationImpl::Layer& l = d.layers[std::size_t(layer)];
    const std::size_t c = std::size_t(channels);
    for (std::size_t i = 0; i < std::size_t(l.num_values) * c; ++i)
        if (!std::isfinite(values[i]))
            throw InputError("tessellation: face-varying value " + std::to_string(i / c) + " is not finite");
    const std::size_t num_face_points = d.samples.size();
    if (!l.surface) {
        for (std::size_t f = 0; f < num_face_points; ++f) {
            const std::int32_t* v = &l.corner_values[3 * std::size_t(d.face_point_parent[f])];
            const float u = d.parameters[2 * f], w = d.parameters[2 * f + 1];
            for (std::size_t j = 0; j < c; ++j) {
                const float a = values[std::size_t(v[0]) * c + j], b = values[std::size_t(v[1]) * c + j],
                            e = values[std::size_t(v[2]) * c + j];
                out[f * c + j] = a + u * (b - a) + w * (e - a);
            }
        }
        return;
    }
    // The layer's surface places three channels at a time, as positions.
    std::vector<float> positions(3 * l.base_values.size()), points(3 * std::size_t(l.surface->num_points()));
    for (std::size_t first = 0; first < c; first += 3) {
        const std::size_t count = std::min<std::size_t>(3, c - first);
        for (std::size_t x = 0; x < l.base_values.size(); ++x)
            for (std::size_t j = 0; j < 3; ++j)
                positions[3 * x + j] = j < count ? values[std::size_t(l.base_values[x]) * c + first + j] : 0.0f;
        l.surface->evaluate(positions.data(), points.data(), nullptr);
        for (std::size_t f = 0; f < num_face_points; ++f)
            for (std::size_t j = 0; j < count; ++j)
                out[f * c + first + j] = points[3 * std::size_t(l.face_point_point[f]) + j];
    }
}

Tessellation::~Tessellation() = default;
Tessellation::Tessellation(Tessellation&&) noexcept = default;
Tessellation& Tessellation::operator=(Tessellation&&) noexcept = default;

int Tessellation::num_points() const { return int(impl_->num_points); }
std::uint64_t Tessellation::estimated_bytes() const { return impl_->estimated_bytes; }

InputTopology Tessellation::input_topology() const {
    auto parts = std::make_shared<InputTopologyParts>();
    parts->surface = impl_->input;
    for (const TessellationImpl::Layer& layer : impl_->layers)
        parts->layers.push_back(layer.surface ? layer.surface->input_topology() : InputTopology());
    InputTopology topology;
    topology.parts_ = std::move(parts);
    return topology;
}
int Tessellation::num_triangles() const { return int(impl_->triangles.size() / 3); }
const std::int32_t* Tessellation::triangles() const { return impl_->triangles.data(); }
const std::int32_t* Tessellation::parent_triangles() const { return impl_->parent_triangles.data(); }
int Tessellation::num_face_points() const { return int(impl_->samples.size()); }
const std::int32_t* Tessellation::corner_face_points() const { return impl_->corner_face_points.data(); }
const float* Tessellation::face_point_parameters() const { return impl_->parameters.data(); }
int Tessellation::levels() const { return impl_->levels; }
const std::vector<InputProblem>& Tessellation::notes() const { return impl_->input->plan->notes(); }

Tessellation::Edges Tessellation::output_edges() const {
    const std::vector<std::int32_t>& corners = impl_->triangles;
    const std::size_t num_points = std::size_t(impl_->num_points);
    // Each side of each triangle, under its smaller end: a side already there under that end is an edge found again.
    // A point's sides are few (its valence), so a bucket is searched linearly.
    std::vector<std::int32_t> bucket_first(num_points + 1, 0);
    auto lower_end = [&](std::size_t c) {
        const std::size_t face = c - c % 3;
        return std::min(corners[c], corners[face + (c + 1) % 3]);
    };
    for (std::size_t c = 0; c < corners.size(); ++c) ++bucket_first[std::size_t(lower_end(c)) + 1];
    for (std::size_t p = 0; p < num_points; ++p) bucket_first[p + 1] += bucket_first[p];
    std::vector<std::int32_t> bucket_size(num_points, 0), bucket_edges(corners.size());
    Edges out;
    out.triangle_edges.resize(corners.size());
    out.edge_vertices.reserve(corners.size());  // closed: 1.5 edges a triangle; open: up to 3
    for (std::size_t c = 0; c < corners.size(); ++c) {
        const std::size_t face = c - c % 3;
        const std::int32_t a = corners[c], b = corners[face + (c + 1) % 3];
        const std::size_t low = std::size_t(std::min(a, b));
        const std::int32_t high = std::max(a, b);
        const std::int32_t* first = &bucket_edges[std::size_t(bucket_first[low])];
        const std::int32_t* last = first + bucket_size[low];
        // Every edge in the bucket has `low` as an end; the one whose other end is `high` is this side's.
        const std::int32_t* found = std::find_if(first, last, [&](std::int32_t e) {
            return out.edge_vertices[2 * std::size_t(e)] == high || out.edge_vertices[2 * std::size_t(e) + 1] == high;
        });
        if (found == last) {  // a new edge, appended to the bucket (at `last`)
            bucket_edges[std::size_t(bucket_first[low]) + std::size_t(bucket_size[low]++)] =
                std::int32_t(out.edge_vertices.size() / 2);
            out.edge_vertices.push_back(a), out.edge_vertices.push_back(b);
        }
        out.triangle_edges[c] = *found;
    }
    return out;
}

void Tessellation::evaluate(const float* positions, float* points, float* normals) const {
    const TessellationImpl& d = *impl_;
    const std::size_t num_faces = d.face_patch.size();
    // A patch sums 12 weighted points, its derivatives' weights up to about 6 in all: inputs below the float maximum
    // over 64 keep every sum finite.
    constexpr float kLargest = std::numeric_limits<float>::max() / 64.0f;
    for (std::size_t i = 0; i < 3 * std::size_t(d.num_input_vertices); ++i)
        if (!(std::fabs(positions[i]) <= kLargest))
            throw InputError("tessellation: position " + std::to_string(i / 3) + " is not finite or larger than " +
                             std::to_string(kLargest));
    for (const TessellationImpl::Band& b : d.bands) {
        b.positions.resize(3 * b.vertices.size());
        for (std::size_t v = 0; v < b.vertices.size(); ++v)
            copy_point(positions + 3 * std::size_t(b.vertices[v]), &b.positions[3 * v]);
        const ChannelsView<const float> in = interleaved(b.positions.data(), 3);
        b.limit_points.resize(3 * std::size_t(b.limit->num_output_vertices()));
        b.limit_normals.resize(3 * std::size_t(b.limit->num_limit_normals()));
        b.limit->evaluate(in, interleaved(b.limit_points.data(), 3), Plan::LimitNormals{b.limit_normals.data()});
        if (b.control) {
            b.control_points.resize(3 * std::size_t(b.control->num_output_vertices()) + 1);
            b.control->evaluate(in, interleaved(b.control_points.data(), 3));
        }
    }
    constexpr int kPoints = detail::kPatchPoints;
    auto write = [&](std::size_t s, const float* p, const float* n) {
        if (const std::int32_t point = d.sample_point[s]; point >= 0) copy_point(p, points + 3 * std::size_t(point));
        if (normals) copy_point(n, normals + 3 * s);
    };
    // An input triangle that is a patch: its 12 points for the patch kernel, over its block of weights; the positions
    // of the points it places copied out, but for its inner points: its own, one after the other, written in place.
    auto place_patch_face = [&](std::size_t f, std::vector<float>& scratch) {
        const std::int32_t* patch = &d.input_patch_points[std::size_t(d.face_patch[f]) * kPoints];
        alignas(16) float x[kPoints][4] = {};  // a phantom's point is zero, with zero weights
        for (int i = 0; i < kPoints; ++i)
            if (patch[i] >= 0) copy_point(positions + 3 * std::size_t(patch[i]), x[i]);
        std::size_t sample = std::size_t(d.face_first_sample[f]);
        for (int part = 0; part < TessellationImpl::kParts; ++part) {
            const std::int32_t b = d.face_blocks[TessellationImpl::kParts * f + std::size_t(part)];
            if (b < 0) continue;
            const TessellationImpl::Block& block = d.blocks[std::size_t(b)];
            float* part_normals = normals ? normals + 3 * sample : scratch.data() + 3 * std::size_t(block.count);
            if (part == TessellationImpl::kInnerPart) {
                const std::int32_t first_point = d.sample_point[sample];
                for (int q = 0; q < block.count; ++q)
                    assert(d.sample_point[sample + std::size_t(q)] == first_point + q);
                d.patch_kernel(x, &d.block_weights[block.first], block.count, block.stride,
                               points + 3 * std::size_t(first_point), part_normals);
                sample += std::size_t(block.count);
                continue;
            }
            d.patch_kernel(x, &d.block_weights[block.first], block.count, block.stride, scratch.data(), part_normals);
            for (int q = 0; q < block.count; ++q, ++sample)
                if (const std::int32_t point = d.sample_point[sample]; point >= 0)
                    copy_point(&scratch[3 * std::size_t(q)], points + 3 * std::size_t(point));
        }
    };
    auto place = [&](std::size_t s) {
        const TessellationImpl::Sample& sample = d.samples[s];
        const TessellationImpl::Band& band = d.bands[sample.band];
        const float* x = band.control_points.data();
        float p[3], n[3];
        if (sample.kind == Kind::Vertex) {
            copy_point(&band.limit_points[3 * std::size_t(sample.a)], p);
            copy_point(&band.limit_normals[3 * std::size_t(sample.b)], n);
        } else {
            PointSums sums;
            if (sample.kind == Kind::Patch) {
                const std::int32_t* patch = &d.patch_points[std::size_t(sample.a) * kPoints];
                const float* w = &d.patch_weights[std::size_t(sample.b) * 3 * kPoints];
                for (int i = 0; i < kPoints; ++i)
                    if (patch[i] >= 0)
                        sums.add(x + 3 * std::size_t(patch[i]), w[i], w[kPoints + i], w[2 * kPoints + i]);
            } else {
                const std::size_t first = std::size_t(d.stencil_offsets[std::size_t(sample.a)]),
                                  last = std::size_t(d.stencil_offsets[std::size_t(sample.a) + 1]);
                for (std::size_t i = first; i < last; ++i) {
                    const float* w = &d.stencil_weights[3 * i];
                    sums.add(x + 3 * std::size_t(d.stencil_points[i]), w[0], w[1], w[2]);
                }
            }
            sums.finish(p, n);
        }
        write(s, p, n);
    };
    // Each part's scratch takes the largest block once: resized block by block, it was zeroed again for every face.
    std::size_t largest_block = 0;
    for (const TessellationImpl::Block& block : d.blocks)
        largest_block = std::max(largest_block, std::size_t(block.count));
    detail::run_levels(d.threads, 1, [&](int, int part, int parts) {
        const auto [first, last] = detail::part_of(num_faces, part, parts);
        std::vector<float> scratch(6 * largest_block);
        for (std::size_t f = first; f < last; ++f) {
            if (d.face_patch[f] >= 0) {
                place_patch_face(f, scratch);
                continue;
            }
            for (std::size_t s = std::size_t(d.face_first_sample[f]); s < std::size_t(d.face_first_sample[f + 1]); ++s)
                place(s);
        }
    });
}

}  // namespace loopsub
