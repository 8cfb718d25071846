// The face-varying seam rules (native/src/rules/face_varying_rules.h) on summaries of a vertex and its values' spans.
// Every expected class is OpenSubdiv's documented behaviour of Sdc::Options::FVarLinearInterpolation (sdc/options.h and
// the "Face-Varying Interpolation Rules" of its subdivision surfaces documentation):
//   LINEAR_NONE          smooth everywhere the mesh is smooth;
//   LINEAR_CORNERS_ONLY  sharpen (pin) corners only: a value whose span is one face;
//   LINEAR_CORNERS_PLUS1 CORNERS_ONLY, and junctions of three or more regions;
//   LINEAR_CORNERS_PLUS2 CORNERS_PLUS1, and darts and concave corners;
//   LINEAR_BOUNDARIES    linear along every boundary and seam;
//   LINEAR_ALL           linear everywhere;
// semi-sharp features hold a seam value until they decay (Vtr::FVarRefinement::reclassifySemisharpValues), and the
// masks are Loop's crease and corner masks (Sdc::Scheme<SCHEME_LOOP>), blended by Sdc's transition weight. Expected
// weights are written out here, never computed by the project's code.
#include <gtest/gtest.h>

#include <vector>

#include "rules/face_varying_rules.h"

namespace {

using loopsub::Boundary;
using loopsub::FaceVaryingValueClass;
using Mode = loopsub::FaceVaryingInterpolation;
using loopsub::detail::FaceVaryingSpan;
using loopsub::detail::FaceVaryingTag;
using loopsub::detail::FaceVaryingVertex;

constexpr Mode kModes[] = {Mode::None,         Mode::CornersOnly, Mode::CornersPlus1,
                           Mode::CornersPlus2, Mode::Boundaries,  Mode::All};

FaceVaryingVertex interior(int values, bool seam = true) { return {values, seam, false, false, false, 0.0f}; }
FaceVaryingVertex on_boundary(int values, bool seam = true) { return {values, seam, true, false, false, 0.0f}; }
FaceVaryingSpan span(int faces, int infinite = 0, int semi = 0, bool disjoint = false) {
    return {faces, infinite, semi, disjoint};
}

// The classes of the values at a mismatched vertex.
std::vector<FaceVaryingValueClass> classes(Mode mode, const FaceVaryingVertex& vertex,
                                           const std::vector<FaceVaryingSpan>& spans) {
    std::vector<FaceVaryingTag> tags(std::size_t(vertex.values), FaceVaryingTag{});
    loopsub::detail::face_varying_base_tags(mode, vertex, spans.data(), tags.data());
    std::vector<FaceVaryingValueClass> out;
    for (const FaceVaryingTag& tag : tags) out.push_back(loopsub::detail::face_varying_value_class(tag));
    return out;
}

constexpr auto kSeam = FaceVaryingValueClass::Seam;
constexpr auto kStays = FaceVaryingValueClass::Stays;
constexpr auto kHeld = FaceVaryingValueClass::Held;
using Classes = std::vector<FaceVaryingValueClass>;

TEST(FaceVaryingRules, ASeamMismatchesItsVertexInEveryMode) {
    for (Mode mode : kModes)
        EXPECT_TRUE(loopsub::detail::face_varying_mismatched(mode, Boundary::EdgesOnly, interior(2)));
}

TEST(FaceVaryingRules, ABoundaryWithoutASeamIsTheVertexsUnlessBoundariesAreLinear) {
    for (Mode mode : kModes) {
        const bool linear = mode == Mode::Boundaries || mode == Mode::All;
        EXPECT_EQ(loopsub::detail::face_varying_mismatched(mode, Boundary::EdgesOnly, on_boundary(1, false)), linear);
    }
}

TEST(FaceVaryingRules, ACornerOfOneFaceIsSharpenedWhereTheVertexRulesLeaveItSmooth) {
    FaceVaryingVertex corner = on_boundary(1, false);
    corner.one_face_corner = true;
    // VTX_BOUNDARY_EDGE_ONLY leaves the corner smooth: every mode but LINEAR_NONE pins it (makeSmoothCornersSharp).
    EXPECT_FALSE(loopsub::detail::face_varying_mismatched(Mode::None, Boundary::EdgesOnly, corner));
    EXPECT_TRUE(loopsub::detail::face_varying_mismatched(Mode::CornersOnly, Boundary::EdgesOnly, corner));
    // VTX_BOUNDARY_EDGE_AND_CORNER already makes it a corner of the vertex's own.
    EXPECT_FALSE(loopsub::detail::face_varying_mismatched(Mode::CornersOnly, Boundary::EdgesAndCorners, corner));
}

TEST(FaceVaryingRules, ANonManifoldVertexMismatchesWithTwoValuesAndPinsThemAll) {
    FaceVaryingVertex vertex = interior(1, false);
    vertex.non_manifold = true;
    EXPECT_FALSE(loopsub::detail::face_varying_mismatched(Mode::CornersOnly, Boundary::EdgesOnly, vertex));
    vertex.values = 2;
    EXPECT_TRUE(loopsub::detail::face_varying_mismatched(Mode::CornersOnly, Boundary::EdgesOnly, vertex));
    EXPECT_EQ(classes(Mode::None, vertex, {span(3), span(3)}), (Classes{kStays, kStays}));
}

TEST(FaceVaryingRules, ASeamThroughAVertexIsSmoothInTheSmoothModes) {
    for (Mode mode : {Mode::None, Mode::CornersOnly, Mode::CornersPlus1, Mode::CornersPlus2})
        EXPECT_EQ(classes(mode, interior(2), {span(3), span(3)}), (Classes{kSeam, kSeam}));
    for (Mode mode : {Mode::Boundaries, Mode::All})
        EXPECT_EQ(classes(mode, interior(2), {span(3), span(3)}), (Classes{kStays, kStays}));
}

TEST(FaceVaryingRules, AnIslandsCornerOfOneFaceIsPinnedByEveryModeButNone) {
    // A UV island's corner: one value spans a single face, the other the five faces beyond it.
    EXPECT_EQ(classes(Mode::None, interior(2), {span(1), span(5)}), (Classes{kSeam, kSeam}));
    EXPECT_EQ(classes(Mode::CornersOnly, interior(2), {span(1), span(5)}), (Classes{kStays, kSeam}));
    EXPECT_EQ(classes(Mode::CornersPlus1, interior(2), {span(1), span(5)}), (Classes{kStays, kSeam}));
    // CORNERS_PLUS2 pins the concave corner beside it too.
    EXPECT_EQ(classes(Mode::CornersPlus2, interior(2), {span(1), span(5)}), (Classes{kStays, kStays}));
}

TEST(FaceVaryingRules, AJunctionOfThreeRegionsIsPinnedFromCornersPlus1) {
    const std::vector<FaceVaryingSpan> spans{span(2), span(2), span(2)};
    EXPECT_EQ(classes(Mode::None, interior(3), spans), (Classes{kSeam, kSeam, kSeam}));
    EXPECT_EQ(classes(Mode::CornersOnly, interior(3), spans), (Classes{kSeam, kSeam, kSeam}));
    EXPECT_EQ(classes(Mode::CornersPlus1, interior(3), spans), (Classes{kStays, kStays, kStays}));
    EXPECT_EQ(classes(Mode::CornersPlus2, interior(3), spans), (Classes{kStays, kStays, kStays}));
}

TEST(FaceVaryingRules, ADartIsPinnedByCornersPlus2AndLinearBoundariesOnly) {
    // A seam that ends inside the mesh: one value all round its end.
    const std::vector<FaceVaryingSpan> spans{span(6)};
    for (Mode mode : {Mode::None, Mode::CornersOnly, Mode::CornersPlus1})
        EXPECT_EQ(classes(mode, interior(1), spans), Classes{kSeam});
    for (Mode mode : {Mode::CornersPlus2, Mode::Boundaries})
        EXPECT_EQ(classes(mode, interior(1), spans), Classes{kStays});
    // Where a seam meets the boundary, the one value there is no dart.
    EXPECT_EQ(classes(Mode::CornersPlus2, on_boundary(1), {span(3)}), Classes{kSeam});
}

TEST(FaceVaryingRules, InfiniteSharpnessPinsTheValuesItTouches) {
    FaceVaryingVertex corner = interior(2);
    corner.sharpness = loopsub::kInfiniteSharpness;
    EXPECT_EQ(classes(Mode::None, corner, {span(3), span(3)}), (Classes{kStays, kStays}));
    // An infinitely sharp edge inside one span pins that value, and under CORNERS_PLUS1/2 its sibling too.
    EXPECT_EQ(classes(Mode::CornersOnly, interior(2), {span(3, 1), span(3)}), (Classes{kStays, kSeam}));
    EXPECT_EQ(classes(Mode::CornersPlus1, interior(2), {span(3, 1), span(3)}), (Classes{kStays, kStays}));
    // A span that is no single fan pins its value alone, and its sibling under CORNERS_PLUS1/2.
    EXPECT_EQ(classes(Mode::CornersOnly, interior(2), {span(3, 0, 0, true), span(3)}), (Classes{kStays, kSeam}));
    EXPECT_EQ(classes(Mode::CornersPlus2, interior(2), {span(3, 0, 0, true), span(3)}), (Classes{kStays, kStays}));
}

TEST(FaceVaryingRules, SemiSharpFeaturesHoldTheirValuesAndUnderCornersPlus1TheSibling) {
    EXPECT_EQ(classes(Mode::CornersOnly, interior(2), {span(3, 0, 1), span(3)}), (Classes{kHeld, kSeam}));
    FaceVaryingVertex semi_sharp_vertex = interior(2);
    semi_sharp_vertex.sharpness = 2.0f;
    EXPECT_EQ(classes(Mode::CornersOnly, semi_sharp_vertex, {span(3), span(3)}), (Classes{kHeld, kHeld}));
    // Dependent sharpness: the sibling without semi-sharp edges is held for the other's.
    std::vector<FaceVaryingTag> tags(2, FaceVaryingTag{});
    const std::vector<FaceVaryingSpan> spans{span(3, 0, 1), span(3)};
    loopsub::detail::face_varying_base_tags(Mode::CornersPlus1, interior(2), spans.data(), tags.data());
    EXPECT_TRUE(tags[0].semi_sharp && !tags[0].dep_sharp);
    EXPECT_TRUE(tags[1].semi_sharp && tags[1].dep_sharp);
    // Both spans semi-sharp: each holds for its own.
    EXPECT_EQ(classes(Mode::CornersPlus1, interior(2), {span(3, 0, 1), span(3, 0, 2)}), (Classes{kHeld, kHeld}));
}

TEST(FaceVaryingRules, ValueClassesReadTheTags) {
    using loopsub::detail::face_varying_value_class;
    EXPECT_EQ(face_varying_value_class({false, false, false, false}), FaceVaryingValueClass::Vertex);
    EXPECT_EQ(face_varying_value_class({true, true, false, false}), FaceVaryingValueClass::Seam);
    EXPECT_EQ(face_varying_value_class({true, false, true, false}), FaceVaryingValueClass::Held);
    EXPECT_EQ(face_varying_value_class({true, false, true, true}), FaceVaryingValueClass::Held);
    EXPECT_EQ(face_varying_value_class({true, false, false, false}), FaceVaryingValueClass::Stays);
}

TEST(FaceVaryingRules, SeamMidpointsFollowTheSeamUnlessSeamsAreLinear) {
    using loopsub::detail::face_varying_edge_on_seam;
    using loopsub::detail::face_varying_midpoint_tag;
    EXPECT_FALSE(face_varying_edge_on_seam(Mode::CornersOnly, false));
    EXPECT_TRUE(face_varying_edge_on_seam(Mode::CornersOnly, true));
    EXPECT_TRUE(face_varying_edge_on_seam(Mode::All, false));
    for (Mode mode : kModes) {
        const FaceVaryingTag tag = face_varying_midpoint_tag(mode);
        EXPECT_TRUE(tag.mismatch);
        EXPECT_EQ(tag.crease, mode != Mode::Boundaries && mode != Mode::All);
        EXPECT_FALSE(tag.semi_sharp || tag.dep_sharp);
    }
}

TEST(FaceVaryingRules, HeldValuesAreReleasedOnlyOnceTheVertexIsSpent) {
    EXPECT_TRUE(loopsub::detail::face_varying_may_release(true, 0.0f));
    EXPECT_FALSE(loopsub::detail::face_varying_may_release(true, 0.5f));
    EXPECT_FALSE(loopsub::detail::face_varying_may_release(false, 0.0f));
}

TEST(FaceVaryingRules, AHeldValueTurnsIntoACreaseWhenItsSpanIsSpent) {
    FaceVaryingTag held{true, false, true, false};
    FaceVaryingTag* tags[] = {&held};
    // Semi-sharp edges remain at the vertex, one inside its span: still held.
    loopsub::detail::release_held_values(Mode::CornersOnly, tags, 1, true, [](int) { return true; });
    EXPECT_TRUE(held.semi_sharp && !held.crease);
    // They remain, but none inside its span: released.
    loopsub::detail::release_held_values(Mode::CornersOnly, tags, 1, true, [](int) { return false; });
    EXPECT_TRUE(held.crease && !held.semi_sharp);
    // None remains: released without asking about its span.
    FaceVaryingTag other{true, false, true, false};
    FaceVaryingTag* others[] = {&other};
    bool asked = false;
    loopsub::detail::release_held_values(Mode::CornersOnly, others, 1, false, [&](int) { return asked = true; });
    EXPECT_TRUE(other.crease && !other.semi_sharp);
    EXPECT_FALSE(asked);
}

TEST(FaceVaryingRules, AValueHeldForItsSiblingFollowsTheSibling) {
    FaceVaryingTag own{true, false, true, false}, dependent{true, false, true, true};
    FaceVaryingTag* tags[] = {&own, &dependent};
    // Semi-sharp edges remain inside the first span: both stay held.
    loopsub::detail::release_held_values(Mode::CornersPlus1, tags, 2, true, [](int i) { return i == 0; });
    EXPECT_TRUE(own.semi_sharp && dependent.semi_sharp && dependent.dep_sharp);
    // The first span is spent while semi-sharp edges remain elsewhere: the first is released, the dependent one
    // stays held but no longer for its sibling.
    loopsub::detail::release_held_values(Mode::CornersPlus1, tags, 2, true, [](int) { return false; });
    EXPECT_TRUE(own.crease && !own.semi_sharp);
    EXPECT_TRUE(dependent.semi_sharp && !dependent.dep_sharp);
    // A value held for its sibling weighs its release by the sibling's span.
    const FaceVaryingTag held_for_sibling{true, false, true, true};
    EXPECT_EQ(loopsub::detail::face_varying_weight_span(held_for_sibling, 0, 2), 1);
    EXPECT_EQ(loopsub::detail::face_varying_weight_span(held_for_sibling, 1, 2), 0);
    EXPECT_EQ(loopsub::detail::face_varying_weight_span(own, 1, 2), 1);
}

TEST(FaceVaryingRules, ASeamValueTakesLoopsCreaseMaskBlendedWithItsHold) {
    using loopsub::detail::face_varying_seam_mask;
    const auto crease = face_varying_seam_mask(false, 0.7);  // not held: the weight is not read
    EXPECT_DOUBLE_EQ(crease.self, 0.75);
    EXPECT_DOUBLE_EQ(crease.ring, 0.0);
    EXPECT_DOUBLE_EQ(crease.crease, 0.125);
    // Held by w = 1/4: a quarter of the corner (1) and three quarters of the crease.
    const auto blended = face_varying_seam_mask(true, 0.25);
    EXPECT_DOUBLE_EQ(blended.self, 0.25 + 0.75 * 0.75);
    EXPECT_DOUBLE_EQ(blended.crease, 0.75 * 0.125);
    auto has_ends = [] { return true; };
    auto no_ends = [] { return false; };
    EXPECT_TRUE(loopsub::detail::face_varying_follows_seam({true, true, false, false}, has_ends));
    EXPECT_FALSE(loopsub::detail::face_varying_follows_seam({true, true, false, false}, no_ends));
    EXPECT_FALSE(loopsub::detail::face_varying_follows_seam({true, false, true, false}, has_ends));
}

TEST(FaceVaryingRules, LimitsGoWhereTheValuesRun) {
    using loopsub::detail::face_varying_limit;
    using Limit = loopsub::detail::FaceVaryingLimit;
    auto has_ends = [] { return true; };
    auto no_ends = [] { return false; };
    const FaceVaryingTag vertex{false, false, false, false}, seam{true, true, false, false},
        stays{true, false, false, false};
    EXPECT_EQ(face_varying_limit(Mode::CornersOnly, vertex, no_ends), Limit::Vertex);
    EXPECT_EQ(face_varying_limit(Mode::CornersOnly, seam, has_ends), Limit::Seam);
    EXPECT_EQ(face_varying_limit(Mode::CornersOnly, seam, no_ends), Limit::Stays);
    EXPECT_EQ(face_varying_limit(Mode::CornersOnly, stays, has_ends), Limit::Stays);
    EXPECT_EQ(face_varying_limit(Mode::All, vertex, has_ends), Limit::Stays);
    // The seam's limit is the cubic B-spline's (1, 4, 1) / 6; a value held for good stays.
    const auto released = loopsub::detail::face_varying_held_limit_mask(true);
    EXPECT_DOUBLE_EQ(released.self, 4.0 / 6.0);
    EXPECT_DOUBLE_EQ(released.end_a, 1.0 / 6.0);
    EXPECT_DOUBLE_EQ(released.end_b, 1.0 / 6.0);
    const auto held = loopsub::detail::face_varying_held_limit_mask(false);
    EXPECT_DOUBLE_EQ(held.self, 1.0);
    EXPECT_DOUBLE_EQ(held.end_a + held.end_b + held.ring, 0.0);
}

// Not OpenSubdiv's own rule but how a tessellation's layer mesh states each class to the vertex rules
// (docs/rules.md, "Tessellation"); the layers it makes are checked against Bfr's face-varying surfaces
// (TessellationLayerAgainstBfr).
TEST(FaceVaryingRules, ATessellationsLayerMeshCarriesTheTagsEachClassKeeps) {
    using loopsub::detail::face_varying_layer_tag;
    const float inf = loopsub::kInfiniteSharpness;
    // Stays: an infinitely sharp corner, whatever its vertex.
    EXPECT_EQ(face_varying_layer_tag(FaceVaryingValueClass::Stays, 0.0f, true, false).sharpness, inf);
    EXPECT_FALSE(face_varying_layer_tag(FaceVaryingValueClass::Stays, 0.0f, true, false).cone);
    // Without a seam: the vertex's corner sharpness and cone, and a corner of one face the boundary rule keeps.
    EXPECT_EQ(face_varying_layer_tag(FaceVaryingValueClass::Vertex, 2.5f, false, false).sharpness, 2.5f);
    EXPECT_TRUE(face_varying_layer_tag(FaceVaryingValueClass::Vertex, 0.0f, true, false).cone);
    EXPECT_EQ(face_varying_layer_tag(FaceVaryingValueClass::Vertex, 0.0f, false, true).sharpness, inf);
    // Held: the vertex's sharpness, no cone; on a seam: nothing.
    EXPECT_EQ(face_varying_layer_tag(FaceVaryingValueClass::Held, 2.5f, true, true).sharpness, 2.5f);
    EXPECT_FALSE(face_varying_layer_tag(FaceVaryingValueClass::Held, 2.5f, true, true).cone);
    EXPECT_EQ(face_varying_layer_tag(FaceVaryingValueClass::Seam, 2.5f, true, true).sharpness, 0.0f);
    EXPECT_FALSE(face_varying_layer_tag(FaceVaryingValueClass::Seam, 2.5f, true, true).cone);
}

}  // namespace
