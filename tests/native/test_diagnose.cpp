// The core's input checks as data (loopsub::InputProblem): diagnose() lists every problem of a mesh and its notes, a
// Plan (or an evaluation, or welding) throws the first as an InputError that carries it. Every expected field below is
// worked out by hand from the small meshes here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "loopsub/loopsub.h"

namespace {

using loopsub::InputProblem;
using Kind = InputProblem::Kind;
using Element = InputProblem::Element;

// A tetrahedron: closed, 4 vertices, 6 edges, 4 triangles.
struct Tetrahedron : loopsub::MeshData {
    Tetrahedron() {
        positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
        triangles = {0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2};
    }
};

// What a problem says, field by field, for one comparison.
struct Fields {
    Kind kind;
    Element element;
    int index, corner, refers_to, other, layer, channel;
};

void expect_fields(const InputProblem& p, const Fields& expected) {
    EXPECT_EQ(int(p.kind), int(expected.kind)) << loopsub::problem_name(p.kind);
    EXPECT_EQ(int(p.element), int(expected.element)) << loopsub::problem_name(p.element);
    EXPECT_EQ(p.index, expected.index);
    EXPECT_EQ(p.corner, expected.corner);
    EXPECT_EQ(p.refers_to, expected.refers_to);
    EXPECT_EQ(p.other, expected.other);
    EXPECT_EQ(p.layer, expected.layer);
    EXPECT_EQ(p.channel, expected.channel);
}

// The problem the plan of `mesh` throws; a test failure when it throws none, or one without a problem.
InputProblem plan_problem(const loopsub::MeshView& mesh, const loopsub::Options& options = {}) {
    try {
        loopsub::Plan plan(mesh, options);
        ADD_FAILURE() << "no InputError";
    } catch (const loopsub::InputError& e) {
        if (e.problem()) {
            EXPECT_EQ(std::string(e.what()), e.problem()->message());
            return *e.problem();
        }
        ADD_FAILURE() << "an InputError without a problem: " << e.what();
    }
    return {};
}

// diagnose() finds exactly `expected` (errors, then notes), and a plan throws the first of them.
void expect_diagnosis(const loopsub::MeshView& mesh, const std::vector<Fields>& expected) {
    const std::vector<InputProblem> found = loopsub::diagnose(mesh);
    ASSERT_EQ(found.size(), expected.size());
    for (std::size_t k = 0; k < found.size(); ++k) {
        SCOPED_TRACE("problem " + std::to_string(k) + ": " + found[k].message());
        expect_fields(found[k], expected[k]);
    }
    if (!expected.empty() && !found[0].is_note()) expect_fields(plan_problem(mesh), expected[0]);
}

// The problem a plan of one level throws evaluating the mesh's positions; a test failure when it throws none.
InputProblem evaluate_problem(const loopsub::MeshData& mesh) {
    loopsub::Plan plan(mesh.view(), loopsub::Options{});
    std::vector<float> out(3 * std::size_t(plan.num_output_vertices()));
    try {
        plan.evaluate(loopsub::interleaved(mesh.positions.data(), 3), loopsub::interleaved(out.data(), 3));
        ADD_FAILURE() << "no InputError";
    } catch (const loopsub::InputError& e) {
        if (e.problem()) return *e.problem();
        ADD_FAILURE() << "an InputError without a problem: " << e.what();
    }
    return {};
}

TEST(Diagnose, ASoundMeshHasNoProblem) {
    const Tetrahedron mesh;
    EXPECT_TRUE(loopsub::diagnose(mesh.view(), loopsub::interleaved(mesh.positions.data(), 3)).empty());
    const loopsub::Plan plan(mesh.view(), loopsub::Options{});
    EXPECT_TRUE(plan.notes().empty());
}

TEST(Diagnose, VertexOutOfRangeAndDegenerateTriangles) {
    Tetrahedron mesh;
    mesh.triangles[4] = 7;                                   // triangle 1, corner 1
    mesh.triangles.insert(mesh.triangles.end(), {1, 2, 1});  // triangle 4: corner 2 repeats corner 0
    mesh.triangles.insert(mesh.triangles.end(), {3, 3, 0});  // triangle 5: corner 1 repeats corner 0
    mesh.triangles.insert(mesh.triangles.end(), {0, 2, 2});  // triangle 6: corner 2 repeats corner 1
    expect_diagnosis(mesh.view(), {{Kind::VertexOutOfRange, Element::Triangle, 1, 1, 7, 4, -1, -1},
                                   {Kind::DegenerateTriangle, Element::Triangle, 4, 2, 1, -1, -1, -1},
                                   {Kind::DegenerateTriangle, Element::Triangle, 5, 1, 3, -1, -1, -1},
                                   {Kind::DegenerateTriangle, Element::Triangle, 6, 2, 2, -1, -1, -1}});
    const InputProblem first = loopsub::diagnose(mesh.view())[0];
    EXPECT_EQ(first.message(), "triangle 1 refers to vertex 7, outside 0..3 (the mesh has 4 vertices)");
    EXPECT_EQ(loopsub::diagnose(mesh.view())[1].message(),
              "triangle 4 is degenerate: it repeats vertex 1 (every corner must be a different vertex)");
}

TEST(Diagnose, TagsAndHolesOutOfRange) {
    Tetrahedron mesh;
    mesh.add_crease(0, 1);
    mesh.add_crease(0, 9);
    mesh.add_corner(-1);
    mesh.cone_vertices = {2, 4};
    mesh.hole_triangles = {5};
    expect_diagnosis(mesh.view(), {{Kind::TriangleOutOfRange, Element::Hole, 0, -1, 5, 4, -1, -1},
                                   {Kind::VertexOutOfRange, Element::CreaseEdge, 1, -1, 9, 4, -1, -1},
                                   {Kind::VertexOutOfRange, Element::CornerVertex, 0, -1, -1, 4, -1, -1},
                                   {Kind::VertexOutOfRange, Element::Cone, 1, -1, 4, 4, -1, -1}});
    EXPECT_EQ(loopsub::diagnose(mesh.view())[0].message(), "hole 0 refers to triangle 5, outside 0..3");
}

TEST(Diagnose, BadSharpness) {
    Tetrahedron mesh;
    mesh.add_crease(0, 1, -1.0f);
    mesh.add_crease(1, 2, std::numeric_limits<float>::quiet_NaN());
    mesh.add_corner(3, std::numeric_limits<float>::infinity());
    expect_diagnosis(mesh.view(), {{Kind::BadSharpness, Element::CreaseEdge, 0, -1, -1, -1, -1, -1},
                                   {Kind::BadSharpness, Element::CreaseEdge, 1, -1, -1, -1, -1, -1},
                                   {Kind::BadSharpness, Element::CornerVertex, 0, -1, -1, -1, -1, -1}});
    const std::vector<InputProblem> found = loopsub::diagnose(mesh.view());
    EXPECT_EQ(found[0].value, -1.0f);
    EXPECT_TRUE(std::isnan(found[1].value));
    EXPECT_EQ(found[0].message(), "crease edge 0 has sharpness -1.000000; it must be a finite number >= 0");
}

// MeshView::triangle_edges: each number below 3 * num_triangles, one pair of vertices to a number. The tetrahedron's
// edges numbered by hand (triangle 0's first), then one number out of range and one on other ends.
TEST(Diagnose, TriangleEdgesOutOfRangeOrOnOtherEnds) {
    const Tetrahedron mesh;
    std::vector<std::int32_t> edges = {0, 1, 2, 2, 3, 4, 1, 5, 3, 4, 5, 0};
    loopsub::MeshView view = mesh.view();
    view.triangle_edges = edges.data();
    EXPECT_TRUE(loopsub::diagnose(view).empty());
    edges[4] = 12;  // triangle 1, corner 1
    edges[7] = 0;   // triangle 2's edge from vertex 2 to 3, numbered as triangle 0's from 0 to 2
    expect_diagnosis(view, {{Kind::EdgeOutOfRange, Element::Triangle, 1, 1, 12, 12, -1, -1},
                            {Kind::EdgeEndsDiffer, Element::Triangle, 2, 1, 0, 0, -1, -1}});
    const std::vector<InputProblem> found = loopsub::diagnose(view);
    EXPECT_EQ(found[0].message(), "triangle 1, corner 1 numbers its edge 12, outside 0..11 (triangle_edges)");
    EXPECT_EQ(found[1].message(),
              "triangle 2, corner 1 numbers its edge 0, which joins other vertices in triangle 0 (triangle_edges: one "
              "number, one pair of vertices)");
}

TEST(Diagnose, CreaseThatIsNoEdge) {
    // A quad of two triangles: 0-2 is its diagonal, 1-3 is not an edge; nor is a vertex to itself.
    loopsub::MeshData quad;
    quad.positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    quad.triangles = {0, 1, 2, 0, 2, 3};
    quad.add_crease(0, 2);
    quad.add_crease(1, 3);
    quad.add_crease(2, 2);
    expect_diagnosis(quad.view(), {{Kind::NotAnEdge, Element::CreaseEdge, 1, -1, 1, 3, -1, -1},
                                   {Kind::NotAnEdge, Element::CreaseEdge, 2, -1, 2, 2, -1, -1}});
    EXPECT_EQ(loopsub::diagnose(quad.view())[0].message(), "crease edge 1 (1, 3) is not an edge of the mesh");
    // Where a crease's end is out of range, whether it is an edge is not asked.
    quad.crease_edges = {0, 2, 1, 9};
    quad.crease_sharpness = {10, 10};
    expect_diagnosis(quad.view(), {{Kind::VertexOutOfRange, Element::CreaseEdge, 1, -1, 9, 4, -1, -1}});
}

TEST(Diagnose, FaceVaryingValueIndices) {
    Tetrahedron mesh;
    const std::vector<std::int32_t> corners = {0, 1, 2, 0, 2, 3, 1, 4, 3, 0, 3, -1};
    const loopsub::FaceVaryingLayer layers[] = {{corners.data(), 4}};
    loopsub::MeshView view = mesh.view();
    view.face_varying = layers, view.num_face_varying = 1;
    expect_diagnosis(view, {{Kind::ValueOutOfRange, Element::Triangle, 2, 1, 4, 4, 0, -1},
                            {Kind::ValueOutOfRange, Element::Triangle, 3, 2, -1, 4, 0, -1}});
    EXPECT_EQ(loopsub::diagnose(view)[0].message(),
              "face-varying layer 0: corner 1 of triangle 2 refers to value 4, outside 0..3");
}

TEST(Diagnose, NonFiniteVertexValues) {
    Tetrahedron mesh;
    mesh.positions[2 * 3 + 1] = std::numeric_limits<float>::quiet_NaN();  // vertex 2, channel 1
    mesh.positions[3 * 3 + 2] = -std::numeric_limits<float>::infinity();  // vertex 3, channel 2
    const std::vector<InputProblem> found =
        loopsub::diagnose(mesh.view(), loopsub::interleaved(mesh.positions.data(), 3));
    ASSERT_EQ(found.size(), 2u);
    expect_fields(found[0], {Kind::NonFiniteValue, Element::Vertex, 2, -1, -1, -1, -1, 1});
    expect_fields(found[1], {Kind::NonFiniteValue, Element::Vertex, 3, -1, -1, -1, -1, 2});
    EXPECT_EQ(found[1].message(), "vertex 3 has a non-finite value (-inf) in channel 2");

    // Plan::evaluate throws the first.
    expect_fields(evaluate_problem(mesh), {Kind::NonFiniteValue, Element::Vertex, 2, -1, -1, -1, -1, 1});
}

TEST(Diagnose, ValuesTooLargeToRefine) {
    Tetrahedron mesh;
    mesh.positions[1 * 3 + 0] = 3.0e38f;  // vertex 1, channel 0: finite, but its sums are not
    {
        const InputProblem p = evaluate_problem(mesh);
        EXPECT_EQ(int(p.kind), int(Kind::ValueTooLarge));
        EXPECT_EQ(int(p.element), int(Element::Vertex));
        EXPECT_EQ(p.index, 1);
        EXPECT_EQ(p.channel, 0);
        EXPECT_EQ(p.value, 3.0e38f);
        EXPECT_GT(p.limit, 0.0f);
        EXPECT_LT(p.limit, 3.0e38f);
        // The bound is what keeps a sum of `other` values and one more finite.
        EXPECT_GT(p.other, 0);
        EXPECT_NEAR(double(p.limit) * (p.other + 1), double(std::numeric_limits<float>::max()), 1e32);
    }
    // diagnose() knows no plan, so no bound: a finite value is no problem to it.
    EXPECT_TRUE(loopsub::diagnose(mesh.view(), loopsub::interleaved(mesh.positions.data(), 3)).empty());
}

TEST(Diagnose, FaceVaryingValuesOfALayerAndPerCorner) {
    Tetrahedron mesh;
    const std::vector<std::int32_t> corners = {0, 1, 2, 0, 2, 3, 1, 2, 3, 0, 3, 2};
    const loopsub::FaceVaryingLayer layers[] = {{corners.data(), 4}};
    loopsub::MeshView view = mesh.view();
    view.face_varying = layers, view.num_face_varying = 1;
    loopsub::Plan plan(view, loopsub::Options{});
    std::vector<float> uvs(8, 0.5f), out(2 * std::size_t(plan.num_output_face_varying_values(0)));
    uvs[2 * 3 + 1] = std::numeric_limits<float>::infinity();  // value 3, channel 1
    try {
        plan.evaluate_face_varying(0, loopsub::interleaved(uvs.data(), 2), loopsub::interleaved(out.data(), 2));
        ADD_FAILURE() << "no InputError";
    } catch (const loopsub::InputError& e) {
        ASSERT_NE(e.problem(), nullptr);
        expect_fields(*e.problem(), {Kind::NonFiniteValue, Element::FaceVaryingValue, 3, -1, -1, -1, 0, 1});
        EXPECT_EQ(std::string(e.what()), "face-varying value 3 of layer 0 has a non-finite value (inf) in channel 1");
    }

    // Per corner (4 triangles x 3 corners x 2 channels): triangle 2, corner 1, channel 0.
    std::vector<float> per_corner(24, 0.25f), per_corner_out(2 * 3 * std::size_t(plan.num_output_triangles()));
    per_corner[(2 * 3 + 1) * 2 + 0] = std::numeric_limits<float>::quiet_NaN();
    try {
        plan.evaluate_face_varying(per_corner.data(), per_corner_out.data(), 2);
        ADD_FAILURE() << "no InputError";
    } catch (const loopsub::InputError& e) {
        ASSERT_NE(e.problem(), nullptr);
        expect_fields(*e.problem(), {Kind::NonFiniteValue, Element::Triangle, 2, 1, -1, -1, -1, 0});
        EXPECT_EQ(std::string(e.what()).rfind("evaluate_face_varying: triangle 2, corner 1 has a non-finite", 0), 0u)
            << e.what();
    }

    // diagnose_corner_values lists it, by the same check, with the caller's layer number.
    per_corner[(3 * 3 + 2) * 2 + 1] = -std::numeric_limits<float>::infinity();  // triangle 3, corner 2, channel 1
    const std::vector<InputProblem> found = loopsub::diagnose_corner_values(per_corner.data(), 4, 2, 5);
    ASSERT_EQ(found.size(), 2u);
    expect_fields(found[0], {Kind::NonFiniteValue, Element::Triangle, 2, 1, -1, -1, 5, 0});
    expect_fields(found[1], {Kind::NonFiniteValue, Element::Triangle, 3, 2, -1, -1, 5, 1});
    EXPECT_EQ(found[1].message(),
              "triangle 3, corner 2 (face-varying layer 5) has a non-finite value (-inf) in channel 1");
}

// An octahedron whose triangle 0 is wound against its three neighbours (1, 2 and 6): three edges that two triangles
// run along the same way, each noted once, by the later triangle and the side it runs along.
TEST(Diagnose, EdgesRunTheSameWayAreNotes) {
    loopsub::MeshData octahedron;
    octahedron.positions = {1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    octahedron.triangles = {4, 1, 0, 1, 0, 5, 1, 2, 4, 2, 1, 5, 2, 3, 4, 3, 2, 5, 3, 0, 4, 0, 3, 5};
    // Triangle 0 runs 4-1, 1-0 and 0-4; triangle 1 runs 1-0 (its side 0), 2 runs 4-1 (side 2), 6 runs 0-4 (side 1).
    const std::vector<Fields> expected = {{Kind::RunsTheSameWay, Element::Triangle, 1, 0, -1, 0, -1, -1},
                                          {Kind::RunsTheSameWay, Element::Triangle, 2, 2, -1, 0, -1, -1},
                                          {Kind::RunsTheSameWay, Element::Triangle, 6, 1, -1, 0, -1, -1}};
    auto sorted = [](std::vector<InputProblem> notes) {
        std::sort(notes.begin(), notes.end(),
                  [](const InputProblem& a, const InputProblem& b) { return a.index < b.index; });
        return notes;
    };
    const std::vector<InputProblem> found = sorted(loopsub::diagnose(octahedron.view()));
    ASSERT_EQ(found.size(), expected.size());
    for (std::size_t k = 0; k < found.size(); ++k) {
        EXPECT_TRUE(found[k].is_note());
        expect_fields(found[k], expected[k]);
    }
    // A plan takes the mesh, and keeps the same notes; so does a tessellation.
    const loopsub::Plan plan(octahedron.view(), loopsub::Options{});
    const std::vector<InputProblem> kept = sorted(plan.notes());
    ASSERT_EQ(kept.size(), expected.size());
    for (std::size_t k = 0; k < kept.size(); ++k) expect_fields(kept[k], expected[k]);

    // An edge of three triangles, two of them running it 0 -> 1: noted once, by the second of those.
    loopsub::MeshData book;
    book.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1};
    book.triangles = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    const std::vector<InputProblem> pages = loopsub::diagnose(book.view());
    ASSERT_EQ(pages.size(), 1u);
    expect_fields(pages[0], {Kind::RunsTheSameWay, Element::Triangle, 2, 0, -1, 0, -1, -1});
}

TEST(Diagnose, NamesOfKindsAndElements) {
    EXPECT_STREQ(loopsub::problem_name(Kind::VertexOutOfRange), "vertex_out_of_range");
    EXPECT_STREQ(loopsub::problem_name(Kind::DegenerateTriangle), "degenerate_triangle");
    EXPECT_STREQ(loopsub::problem_name(Kind::NotAnEdge), "not_an_edge");
    EXPECT_STREQ(loopsub::problem_name(Kind::RunsTheSameWay), "runs_the_same_way");
    EXPECT_STREQ(loopsub::problem_name(Element::CreaseEdge), "crease_edge");
    EXPECT_STREQ(loopsub::problem_name(Element::FaceVaryingValue), "face_varying_value");
}

// Errors of the call rather than the data carry no problem; a view no plan could read is refused by diagnose() too.
TEST(Diagnose, ErrorsOfTheCallCarryNoProblem) {
    Tetrahedron mesh;
    loopsub::Options options;
    options.levels = -1;
    try {
        loopsub::Plan plan(mesh.view(), options);
        ADD_FAILURE() << "no InputError";
    } catch (const loopsub::InputError& e) { EXPECT_EQ(e.problem(), nullptr); }
    loopsub::MeshView view = mesh.view();
    view.triangles = nullptr;
    EXPECT_THROW(loopsub::diagnose(view), loopsub::InputError);
}

}  // namespace
