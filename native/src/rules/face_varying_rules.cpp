#include "rules/face_varying_rules.h"

namespace loopsub::detail {

using Mode = FaceVaryingInterpolation;

bool face_varying_mismatched(Mode mode, Boundary boundary, const FaceVaryingVertex& vertex) {
    const bool sharpened_corner = vertex.one_face_corner && mode != Mode::None && boundary != Boundary::EdgesAndCorners;
    return vertex.seam || (linear_boundaries(mode) && vertex.boundary) || sharpened_corner ||
           (vertex.non_manifold && vertex.values >= 2);
}

void face_varying_base_tags(Mode mode, const FaceVaryingVertex& vertex, const FaceVaryingSpan* spans,
                            FaceVaryingTag* tags) {
    const int n = vertex.values;
    for (int i = 0; i < n; ++i) tags[i] = {true, false, false, false};
    if (vertex.non_manifold) return;  // every value stays
    const bool linear_b = linear_boundaries(mode), dependent = dependent_sharpness(mode),
               plus2 = mode == Mode::CornersPlus2;
    const bool sharp_darts = plus2 || linear_b, sharp_fan_corners = mode != Mode::None;
    bool all_sharp = linear_b || is_infinite(vertex.sharpness) || (dependent && n > 2) ||
                     (sharp_darts && n == 1 && !vertex.boundary);
    bool sharpen_dependent = false;
    if (!all_sharp && dependent && n == 2) {
        all_sharp = spans[0].infinite || spans[1].infinite || spans[0].disjoint || spans[1].disjoint;
        if (plus2) all_sharp |= spans[0].faces == 1 || spans[1].faces == 1;
        sharpen_dependent = (spans[0].semi > 0) != (spans[1].semi > 0);
    }
    for (int i = 0; i < n; ++i) {
        FaceVaryingTag& tag = tags[i];
        const FaceVaryingSpan& span = spans[i];
        if (span.disjoint || all_sharp || span.infinite > 0 || (span.faces == 1 && sharp_fan_corners)) continue;
        if (span.semi > 0 || is_semi_sharp(vertex.sharpness)) tag.semi_sharp = true;
        else if (sharpen_dependent) tag.semi_sharp = tag.dep_sharp = true;
        else tag.crease = true;
    }
}

FaceVaryingValueClass face_varying_value_class(const FaceVaryingTag& tag) {
    return !tag.mismatch                     ? FaceVaryingValueClass::Vertex
           : tag.crease                      ? FaceVaryingValueClass::Seam
           : tag.semi_sharp || tag.dep_sharp ? FaceVaryingValueClass::Held
                                             : FaceVaryingValueClass::Stays;
}

VertexMask face_varying_seam_mask(bool held, double hold_weight) {
    const VertexMask crease = crease_vertex_mask();
    return held ? blend(corner_vertex_mask(), hold_weight, crease) : crease;
}

LimitMask face_varying_held_limit_mask(bool released) { return released ? crease_limit_mask() : corner_limit_mask(); }

FaceVaryingLayerTag face_varying_layer_tag(FaceVaryingValueClass value_class, float vertex_corner_sharpness,
                                           bool vertex_cone, bool vertex_kept_corner) {
    switch (value_class) {
        case FaceVaryingValueClass::Stays: return {kInfiniteSharpness, false};
        case FaceVaryingValueClass::Vertex:
            return {vertex_kept_corner ? kInfiniteSharpness : vertex_corner_sharpness, vertex_cone};
        case FaceVaryingValueClass::Held: return {vertex_corner_sharpness, false};
        case FaceVaryingValueClass::Seam: break;
    }
    return {0.0f, false};
}

}  // namespace loopsub::detail
