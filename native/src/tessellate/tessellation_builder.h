// The build of a Tessellation: the order of its steps, each input triangle's points numbered and its triangles
// written from its pattern (tessellation_builder.cpp); each band's submesh and plans (tessellation_bands.cpp); where
// each point takes its position from (tessellation_samples.cpp).
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

#include "tessellate/kept_input.h"
#include "tessellate/level_patches.h"
#include "tessellate/local_refinement.h"
#include "tessellate/tessellation_data.h"
#include "tessellate/tessellation_rates.h"
#include "topology/tessellation_pattern.h"

namespace loopsub::detail {

class TessellationBuilder {
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
    TessellationBuilder(TessellationImpl& d, const MeshView& mesh, const Options& options)
        : d_(d), mesh_(mesh), options_(options) {}

    // kept: an earlier build's input, taken where it was made for the same mesh.
    void build(const TessellationRates& rates, const std::shared_ptr<const KeptInput>& kept);

private:
    using Kind = TessellationImpl::Kind;
    // build's steps (tessellation_builder.cpp): the result's points (the input's vertices, the edges' and the
    // triangles' inner points), face points and triangles, as the first pass counts them.
    struct ResultCounts {
        std::int64_t points, samples, triangles;
    };
    ResultCounts sides_and_bands(const KeptInput& input, const EdgeRates& edges, std::vector<Sides>& sides,
                                 std::vector<std::int64_t>& face_first);
    void join_band(int f, const Sides& s);  // input triangle f, no patch of the input, joins its band
    std::uint64_t check_budget(const KeptInput& input, const ResultCounts& counts);  // the build's bytes
    // Input triangle f's points numbered, its samples and its triangles (tessellation_builder.cpp).
    void add_face(int f, const Sides& s, std::int64_t face_first);
    // Where each point takes its position from (tessellation_samples.cpp).
    // A point of input triangle f, which is in band `band`.
    void add_sample(int band, FacePoint at, int f);
    // The block of weights of one part of `pattern` (made for `sides`: 0 its corners, 1 to 3 the
    // points of edge 0 to 2, 4 its inner points) in a patch of this rotation and shape; -1 for a part with no points.
    // The points of a part are where they are in every pattern with that part's rate.
    std::int32_t block(const FacePattern& pattern, const Sides& sides, int part, std::pair<int, PatchShape> shape);
    // A point at corner `corner` of triangle t of the band's limit plan.
    void add_vertex(int band, int t, int corner);
    // The level's triangle t as a patch of the tessellation (its number), or -1 where it is no regular patch.
    std::int32_t find_patch(const BandBuilder& bb, int t);
    // The weights at a point of a patch: shared by every point at the same place in a patch of the same shape (at one
    // rate, the points of every input triangle).
    std::int32_t weight_set(int rotation, PatchShape shape, const FacePoint& at);
    // The bands' plans (tessellation_bands.cpp).
    // The mesh of a band's plans: its input triangles and the triangles around their corners, which shape them
    // (local_refinement.h); a vertex of it, the input's vertices[v]; the input's tags on it.
    void make_submesh(const LevelPatches& input, int band);
    // A band's control points' plan and its patches, on the first point that needs them.
    void make_control(int band);

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

}  // namespace loopsub::detail
