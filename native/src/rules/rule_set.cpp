#include "rules/rule_set.h"

#include <algorithm>

namespace loopsub::detail {

namespace {

// The seed's rules (after Hoppe et al. 94): sharpness is all or nothing, tags are carried unchanged, and the masks
// follow the vertex classes, cones and the {5,3} edge rule included.
class Hoppe94Rules final : public RuleSet {
public:
    Hoppe94Rules(Boundary boundary, float crease_threshold) : RuleSet(boundary), threshold_(crease_threshold) {}

    bool has_cones() const override { return true; }
    float edge_sharpness_from_tag(float tag) const override {
        return tag > 0.0f && tag >= threshold_ ? kInfiniteSharpness : 0.0f;
    }
    float vertex_sharpness_from_tag(float tag) const override { return tag > 0.0f ? kInfiniteSharpness : 0.0f; }
    float child_edge_sharpness(float sharpness, const float*, int) const override { return sharpness; }
    float child_vertex_sharpness(float sharpness) const override { return sharpness; }
    bool decay_reads_other_edges() const override { return false; }
    float child_tag(float tag, float) const override { return tag; }

    VertexMask vertex_mask(const VertexSituation& vertex, std::int32_t ends[2]) const override {
        ends[0] = vertex.crease[0], ends[1] = vertex.crease[1];
        switch (vertex.type) {
            case VertexType::Cone: return cone_vertex_mask(vertex.valence);
            case VertexType::Corner: return corner_vertex_mask();
            case VertexType::RegularCrease:
            case VertexType::IrregularCrease: return crease_vertex_mask();
            default: return smooth_vertex_mask(vertex.valence);  // smooth and dart
        }
    }

    EdgeMask edge_mask(const EdgeSituation& edge) const override {
        const auto irregular_or_corner = [](VertexType type) {
            return type == VertexType::IrregularCrease || type == VertexType::Corner;
        };
        // A dart's crease edge is smooth where it has two faces; next to an irregular crease or corner, a regular
        // crease vertex takes the {5,3} rule.
        if ((edge.type_a == VertexType::Dart || edge.type_b == VertexType::Dart) && edge.face_count == 2)
            return smooth_edge_mask();
        if (edge.type_a == VertexType::RegularCrease && irregular_or_corner(edge.type_b))
            return five_three_edge_mask(true);
        if (edge.type_b == VertexType::RegularCrease && irregular_or_corner(edge.type_a))
            return five_three_edge_mask(false);
        return crease_edge_mask();
    }

    LimitMask limit_mask(const VertexSituation& vertex, double vertex_weight_a, double vertex_weight_b) const override {
        switch (vertex.type) {
            // A cone's ring refines with the cone's weight; its limit follows from that weight as a smooth vertex's
            // does.
            case VertexType::Cone: return ring_limit_mask(cone_vertex_mask(vertex.valence), vertex.valence);
            case VertexType::Corner: return corner_limit_mask();
            case VertexType::RegularCrease:
            case VertexType::IrregularCrease:
                return hoppe94_crease_limit_mask(vertex.type == VertexType::RegularCrease, vertex_weight_a,
                                                 vertex_weight_b);
            default: return smooth_limit_mask(vertex.valence);
        }
    }

private:
    float threshold_;
};

// OpenSubdiv's Loop (Sdc::SCHEME_LOOP with Sdc::Crease): semi-sharp creases decaying by one per level (uniformly or
// by Chaikin), tags following the sharpness, and masks blended where a vertex's or an edge's rule changes between
// levels.
class OpenSubdivRules final : public RuleSet {
public:
    OpenSubdivRules(Boundary boundary, CreaseMethod method) : RuleSet(boundary), method_(method) {}

    bool has_cones() const override { return false; }
    float edge_sharpness_from_tag(float tag) const override { return std::min(tag, kInfiniteSharpness); }
    float vertex_sharpness_from_tag(float tag) const override { return std::min(tag, kInfiniteSharpness); }
    float child_edge_sharpness(float sharpness, const float* at_vertex, int count) const override {
        return method_ == CreaseMethod::Chaikin ? chaikin_sharpness_at_vertex(sharpness, at_vertex, count)
                                                : decrement_sharpness(sharpness);
    }
    float child_vertex_sharpness(float sharpness) const override { return decrement_sharpness(sharpness); }
    bool decay_reads_other_edges() const override { return method_ == CreaseMethod::Chaikin; }
    float child_tag(float tag, float child_sharpness) const override { return tag == 0.0f ? tag : child_sharpness; }

    VertexMask vertex_mask(const VertexSituation& vertex, std::int32_t ends[2]) const override {
        ends[0] = vertex.crease[0], ends[1] = vertex.crease[1];
        if (vertex.rule != SdcRule::Crease && vertex.rule != SdcRule::Corner) return smooth_vertex_mask(vertex.valence);
        // The parent's mask, blended with the child's where the rule changes between the levels.
        VertexMask mask = mask_for(vertex.rule, vertex.valence);
        const SdcRule child_rule = sdc_vertex_rule(vertex.child_sharpness, vertex.num_child_sharp_edges);
        if (child_rule != vertex.rule) {
            const float weight = transition_weight(method_, vertex.sharpness, vertex.child_sharpness,
                                                   vertex.edge_sharpness, vertex.child_edge_sharpness, vertex.valence);
            mask = blend(mask, weight, mask_for(child_rule, vertex.valence));
            if (child_rule == SdcRule::Crease) ends[0] = vertex.child_crease[0], ends[1] = vertex.child_crease[1];
        }
        return mask;
    }

    EdgeMask edge_mask(const EdgeSituation& edge) const override {
        // The new vertex's rule comes from its two halves; short of a crease, the smooth mask is blended with the
        // crease mask by the parent's sharpness (Sdc::Scheme::ComputeEdgeVertexMask).
        if (is_infinite(edge.sharpness) || edge.halves_sharp) return crease_edge_mask();
        return blend(crease_edge_mask(), edge.sharpness, smooth_edge_mask());
    }

    // Sdc::Scheme::ComputeVertexLimitMask: by the vertex's rule on the last level, semi-sharp features as sharp ones.
    LimitMask limit_mask(const VertexSituation& vertex, double, double) const override {
        switch (vertex.rule) {
            case SdcRule::Crease: return crease_limit_mask();
            case SdcRule::Corner: return corner_limit_mask();
            default: return smooth_limit_mask(vertex.valence);
        }
    }

private:
    static VertexMask mask_for(SdcRule rule, int valence) {
        switch (rule) {
            case SdcRule::Crease: return crease_vertex_mask();
            case SdcRule::Corner: return corner_vertex_mask();
            default: return smooth_vertex_mask(valence);
        }
    }

    CreaseMethod method_;
};

}  // namespace

SpentRing RuleSet::refine_until_spent(const RingSituation& ring) const {
    const int n = ring.valence, size = n + 1;
    std::vector<float> sharpness(ring.edge_sharpness, ring.edge_sharpness + n);
    std::vector<float> far(ring.far_half_sharpness, ring.far_half_sharpness + n), child(n), child_far(n);
    float vertex = ring.vertex_sharpness;
    SpentRing out;
    out.refinement.assign(std::size_t(size) * size, 0.0);
    for (int i = 0; i < size; ++i) out.refinement[std::size_t(i) * size + i] = 1.0;
    std::vector<double> step(out.refinement.size()), product(out.refinement.size());
    auto first_two_sharp = [n](const std::vector<float>& of, int crease[2]) {
        int count = 0;
        crease[0] = crease[1] = -1;
        for (int k = 0; k < n; ++k)
            if (is_sharp(of[k]) && count++ < 2) crease[count - 1] = k;
        return count;
    };
    // Every level takes at least one off the largest finite sharpness there (Chaikin's averages never exceed it).
    while (is_semi_sharp(vertex) || std::any_of(sharpness.begin(), sharpness.end(), is_semi_sharp)) {
        for (int k = 0; k < n; ++k) child[k] = child_edge_sharpness(sharpness[k], sharpness.data(), n);
        const float child_vertex = child_vertex_sharpness(vertex);
        int crease[2], child_crease[2];
        const int num_sharp_edges = first_two_sharp(sharpness, crease);
        const int num_child_sharp_edges = first_two_sharp(child, child_crease);
        std::fill(step.begin(), step.end(), 0.0);
        // The vertex point.
        std::int32_t ends[2];
        const VertexMask v = vertex_mask({VertexType::Smooth,
                                          sdc_vertex_rule(vertex, num_sharp_edges),
                                          n,
                                          vertex,
                                          child_vertex,
                                          sharpness.data(),
                                          child.data(),
                                          num_child_sharp_edges,
                                          {crease[0], crease[1]},
                                          {child_crease[0], child_crease[1]}},
                                         ends);
        step[0] = v.self;
        for (int k = 0; k < n; ++k) step[1 + k] = v.ring;
        if (v.crease != 0.0) step[1 + ends[0]] += v.crease, step[1 + ends[1]] += v.crease;
        // The edge points, the vertex as their end A.
        for (int k = 0; k < n; ++k) {
            const EdgeMask e = is_sharp(sharpness[k])
                                   ? edge_mask({sharpness[k], VertexType::Smooth, VertexType::Smooth,
                                                ring.face_count[k], is_sharp(child[k]) && is_sharp(far[k])})
                                   : smooth_edge_mask();
            double* row = &step[std::size_t(1 + k) * size];
            row[0] += e.a;
            row[1 + k] += e.b;
            row[ring.wings[2 * k]] += e.wings;
            row[ring.wings[2 * k + 1]] += e.wings;
        }
        // An edge point weighs at most four points of the ring: the product skips the rest.
        std::fill(product.begin(), product.end(), 0.0);
        for (int i = 0; i < size; ++i)
            for (int m = 0; m < size; ++m) {
                const double w = step[std::size_t(i) * size + m];
                if (w == 0.0) continue;
                const double* from = &out.refinement[std::size_t(m) * size];
                double* to = &product[std::size_t(i) * size];
                for (int j = 0; j < size; ++j) to[j] += w * from[j];
            }
        out.refinement.swap(product);
        // The next level: the far end of edge k is the midpoint of this level's edge k, where only its two halves can
        // be sharp.
        for (int k = 0; k < n; ++k) {
            const float halves[2] = {child[k], far[k]};
            child_far[k] = child_edge_sharpness(child[k], halves, 2);
        }
        sharpness.swap(child);
        far.swap(child_far);
        vertex = child_vertex;
        ++out.levels;
    }
    out.rule = sdc_vertex_rule(vertex, first_two_sharp(sharpness, out.crease));
    return out;
}

std::unique_ptr<RuleSet> make_rule_set(const Options& options) {
    if (options.rules == Rules::Hoppe94)
        return std::make_unique<Hoppe94Rules>(options.boundary, options.crease_threshold);
    return std::make_unique<OpenSubdivRules>(options.boundary, options.crease_method);
}

}  // namespace loopsub::detail
