// The subdivision rules, as pure functions of local quantities: no mesh here (OpenSubdiv's Sdc in spirit).
//
// Every mask is expressed in the shape the kernels evaluate (stencils.h):
//   vertex  v' = self * v + ring * (sum of all neighbours) + crease * (the two crease neighbours)
//   edge    e' = a * A + b * B + wings * (C + D)
#pragma once

#include <vector>

#include "loopsub/loopsub.h"

namespace loopsub::detail {

struct VertexMask {
    double self = 1.0, ring = 0.0, crease = 0.0;
};

struct EdgeMask {
    double a = 0.375, b = 0.375, wings = 0.125;
    bool operator==(const EdgeMask& other) const { return a == other.a && b == other.b && wings == other.wings; }
};

// Loop's smooth vertex mask for valence n: self 1 - a(n), each neighbour a(n) / n (seed: c0 = n / a(n) - n, ci = 1).
// Valence 6 uses OpenSubdiv's exact 5/8 and 1/16.
VertexMask smooth_vertex_mask(int valence);
VertexMask crease_vertex_mask();           // (6 v0 + the two crease neighbours) / 8
VertexMask corner_vertex_mask();           // the vertex stays
VertexMask cone_vertex_mask(int valence);  // seed / Hoppe: c0 = n / (5/8 - b(n)) - n, ci = 1
VertexMask blend(const VertexMask& a, double weight_a, const VertexMask& b);  // weight_a * a + (1 - weight_a) * b

// {3, 3, 1, 1} / 8: the one place it is written (the kernels' smooth pass reads it through stencils.h).
constexpr EdgeMask smooth_edge_mask() { return {0.375, 0.375, 0.125}; }
EdgeMask crease_edge_mask();                    // {1, 1, 0, 0} / 2
EdgeMask five_three_edge_mask(bool five_on_a);  // {5, 3, 0, 0} / 8 with the 5 on the regular crease vertex
EdgeMask blend(const EdgeMask& a, double weight_a, const EdgeMask& b);  // weight_a * a + (1 - weight_a) * b

// ---- The limit surface --------------------------------------------------------------------------------------
// Where a vertex of the last level lands on the limit surface: the left eigenvector (eigenvalue 1) of the
// refinement around it, in the kernels' vertex shape with the two crease neighbours weighted apart (Hoppe94's
// {5,3} edges make them differ).
struct LimitMask {
    double self = 1.0, ring = 0.0, end_a = 0.0, end_b = 0.0;
};

// A vertex refined by `refinement` (self, ring weight beta each) over smooth edges: each neighbour gets
// beta' / (1 + n beta') with beta' = 8 beta / 3, the vertex the rest. Loop's smooth vertices (OpenSubdiv's
// smooth limit mask; valence 6: 1/12 and 1/2) and the seed's cones.
LimitMask ring_limit_mask(const VertexMask& refinement, int valence);
LimitMask smooth_limit_mask(int valence);
// OpenSubdiv's crease limit (1, 4, 1) / 6 (the uniform cubic B-spline), and its corner: the vertex stays.
LimitMask crease_limit_mask();
LimitMask corner_limit_mask();
// Hoppe94's crease vertex: its crease is a B-spline only away from irregular vertices, so the limit is one step of
// the crease masks (the vertex keeps `vertex_weight_a` / `_b` of the edge points towards its crease neighbours:
// 1/2, or 3/8 and 5/8 under the {5,3} rule) followed by the stationary mask of its child, whose crease neighbours
// are regular: (1, 4, 1) / 6 at a regular crease vertex, (1, 3, 1) / 5 at an irregular one (Hoppe et al. 94).
LimitMask hoppe94_crease_limit_mask(bool regular, double vertex_weight_a, double vertex_weight_b);
// The weight a crease vertex keeps in the edge point of one of its crease edges (`edge`, whose end A it is or not), as
// the crease limit reads it. Where the edge is refined as a smooth edge (Hoppe 94's crease edge ending at a dart) the
// limit there depends on the surface beyond, and the crease's own B-spline weight, 1/2, stands in.
inline double crease_end_weight(const EdgeMask& edge, bool vertex_is_a) {
    return edge.wings == 0.0 ? (vertex_is_a ? edge.a : edge.b) : 0.5;
}

// Limit tangents (OpenSubdiv's Sdc::Scheme<SCHEME_LOOP> masks; Hoppe et al. 94's). Around a smooth vertex with
// its neighbours p_0 .. p_{n-1} counter-clockwise: t1 = sum cos(2 pi i / n) p_i, t2 = sum sin(2 pi i / n) p_i.
void smooth_tangent_weights(int valence, std::vector<float>& t1, std::vector<float>& t2);
// One side of a crease (or a boundary) spanning `faces` faces, neighbours p_0 .. p_faces counter-clockwise from
// the leading crease edge: faces + 2 weights each, the vertex's first, then p_0 .. p_faces. t1 runs along the
// crease, t2 into the side; t1 x t2 is the side's outward normal.
void side_tangent_weights(int faces, std::vector<float>& t1, std::vector<float>& t2);
// OpenSubdiv's dart, a vertex with one infinitely sharp edge: the vertex and its other edges refine smoothly, the sharp
// edge's midpoint as a crease's. Its limit is not the smooth one (which Far::PrimvarRefiner::Limit takes, 2e-3 of the
// bounding box off Bfr on a torus): it is the dominant left eigenvector of the 1-ring's subdivision matrix, and its
// tangent plane that of the two next, found here by iterating the matrix. Ring p_0 .. p_{n-1} counter-clockwise, the
// sharp edge to p_0; n + 1 weights each, the vertex's first; t1 x t2 is the outward normal.
void dart_limit_masks(int valence, std::vector<double>& position, std::vector<double>& t1, std::vector<double>& t2);

// OpenSubdiv's creasing (Sdc::Crease), single precision as OpenSubdiv computes it.
enum class SdcRule { Smooth, Dart, Crease, Corner };
SdcRule sdc_vertex_rule(float vertex_sharpness, int sharp_edge_count);
// Where a vertex's limit normal is one per side of its sharp edges rather than one for its whole fan.
inline bool normal_per_side(SdcRule rule) { return rule == SdcRule::Crease || rule == SdcRule::Corner; }
float decrement_sharpness(float sharpness);  // uniform decay: s - 1, 0 below 1, infinite stays infinite
// Chaikin decay of one edge's sharpness at one of its end vertices, given the sharpness of all edges there.
float chaikin_sharpness_at_vertex(float edge_sharpness, const float* incident_sharpness, int incident_count);
// Weight of the parent mask when a vertex's rule changes between levels (Sdc::Crease::ComputeFractionalWeightAtVertex).
float transition_weight(CreaseMethod method, float parent_vertex_sharpness, float child_vertex_sharpness,
                        const float* parent_edge_sharpness, const float* child_edge_sharpness, int edge_count);

inline bool is_sharp(float sharpness) { return sharpness > 0.0f; }
inline bool is_infinite(float sharpness) { return sharpness >= kInfiniteSharpness; }
inline bool is_semi_sharp(float sharpness) { return sharpness > 0.0f && sharpness < kInfiniteSharpness; }

// ---- Hoppe 94's vertex classes (docs/rules.md, "Vertex classes"), reported under both rule sets ---------------
// What the regular-crease test reads of the fan around a crease vertex.
struct CreaseFan {
    int valence;
    bool has_fin;              // one of its edges has more than two faces
    bool on_boundary;          // one of its edges has a single face
    bool creases_on_boundary;  // both its crease edges have a single face
    int faces_on_one_side;     // faces met walking round from one crease edge to the other (interior fans only)
};
// Interior with valence 6 and three faces on each side of its crease, or on the boundary with valence 4 and its
// two crease edges the boundary edges.
inline bool is_regular_crease(const CreaseFan& fan) {
    if (fan.has_fin) return false;
    if (fan.on_boundary) return fan.valence == 4 && fan.creases_on_boundary;
    return fan.valence == 6 && fan.faces_on_one_side == 3;
}
// The class from OpenSubdiv's rule for the vertex (its own sharpness and its sharp-edge count) and its cone tag;
// `crease_fan()` is called for a crease vertex only.
template <typename CreaseFanOf>
VertexType hoppe94_vertex_type(SdcRule rule, bool tagged_cone, CreaseFanOf crease_fan) {
    switch (rule) {
        case SdcRule::Smooth: return tagged_cone ? VertexType::Cone : VertexType::Smooth;
        case SdcRule::Dart: return tagged_cone ? VertexType::Cone : VertexType::Dart;
        case SdcRule::Crease:
            if (tagged_cone) return VertexType::Corner;
            return is_regular_crease(crease_fan()) ? VertexType::RegularCrease : VertexType::IrregularCrease;
        case SdcRule::Corner: break;
    }
    return VertexType::Corner;
}

}  // namespace loopsub::detail
