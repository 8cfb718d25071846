// The OBJ reader and writer of the CLI: statement forms, OpenSubdiv's tags, fan triangulation, errors that name
// the file and line, and an exact write -> read round trip.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "mesh_gen.h"
#include "obj_io.h"
#include "test_files.h"

namespace {

using loopsub::obj::ObjMesh;
using loopsub::obj::parse_obj;
using loopsub::testing::read_text;
using loopsub::testing::temp_path;
using loopsub::testing::to_chars_text;
using Indices = std::vector<std::int32_t>;
using Floats = std::vector<float>;

constexpr const char* kFourVertices =
    "v 0 0 0\n"
    "v 1 0 0\n"
    "v 1 1 0\n"
    "v 0 1 0\n";

// The message of the InputError that parsing `text` (named "bad.obj") throws; a test failure when none is thrown.
std::string parse_error(const std::string& text) {
    try {
        parse_obj(text, "bad.obj");
    } catch (const loopsub::InputError& e) { return e.what(); }
    ADD_FAILURE() << "no InputError for:\n" << text;
    return "";
}

// The message of the core's refusal of the mesh `text` (named "bad.obj") reads, said where the file has it
// (loopsub::obj::locate); a test failure when the file does not read or the core takes the mesh.
std::string core_error(const std::string& text) {
    const ObjMesh mesh = parse_obj(text, "bad.obj");
    try {
        loopsub::Plan(mesh.view(), loopsub::Options{});
    } catch (const loopsub::InputError& e) {
        if (e.problem()) return loopsub::obj::locate(mesh, "bad.obj", *e.problem());
        ADD_FAILURE() << "an InputError without a problem: " << e.what();
        return e.what();
    }
    ADD_FAILURE() << "no InputError for:\n" << text;
    return "";
}

void expect_message(const std::string& message, int line, const std::string& fragment) {
    std::string location = "bad.obj:" + std::to_string(line) + ": ";
    EXPECT_EQ(message.rfind(location, 0), 0u) << "expected the message to start with '" << location << "': " << message;
    EXPECT_NE(message.find(fragment), std::string::npos) << "expected '" << fragment << "' in: " << message;
}

void expect_error(const std::string& text, int line, const std::string& fragment) {
    expect_message(parse_error(text), line, fragment);
}
void expect_core_error(const std::string& text, int line, const std::string& fragment) {
    expect_message(core_error(text), line, fragment);
}

TEST(ObjRead, VerticesUvsAndEveryFaceForm) {
    ObjMesh mesh = parse_obj(std::string(kFourVertices) +
                             "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
                             "vn 0 0 1\n"
                             "f 1/1 2/2 3/3\n"
                             "f 1/1/1 3/3/1 4/4/1\n"
                             "f -4/-4/1 -2/-2/1 -1/-1/1\n");
    EXPECT_EQ(mesh.num_vertices(), 4);
    EXPECT_EQ(mesh.positions, (Floats{0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}));
    EXPECT_EQ(mesh.uvs, (Floats{0, 0, 1, 0, 1, 1, 0, 1}));
    EXPECT_EQ(mesh.triangles, (Indices{0, 1, 2, 0, 2, 3, 0, 2, 3}));
    EXPECT_EQ(mesh.triangle_uvs, (Indices{0, 1, 2, 0, 2, 3, 0, 2, 3}));
    EXPECT_EQ(mesh.polygons_triangulated, 0);

    ObjMesh plain = parse_obj(std::string(kFourVertices) + "vn 0 0 1\nf 1 2 3\nf 1//1 3//1 4//1\nf -4 -2 -1\n");
    EXPECT_EQ(plain.triangles, (Indices{0, 1, 2, 0, 2, 3, 0, 2, 3}));
    EXPECT_TRUE(plain.triangle_uvs.empty()) << "v//vn names no texture coordinate";
}

TEST(ObjRead, NegativeIndicesCountBackFromTheVerticesDefinedSoFar) {
    ObjMesh mesh = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 1 1 0\nf -3 -1 -2\n");
    EXPECT_EQ(mesh.triangles, (Indices{0, 1, 2, 1, 3, 2}));
}

TEST(ObjRead, IgnoresNormalsGroupsMaterialsCommentsAndCarriageReturns) {
    ObjMesh mesh = parse_obj(
        "# a comment\r\n"
        "mtllib scene.mtl\r\n"
        "o thing\r\n"
        "g group\r\n"
        "\r\n"
        "   \t\r\n"
        "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\n"
        "vn 0 0 1\r\n"
        "s off\r\n"
        "usemtl red\r\n"
        "f 1 2 3\r\n");
    EXPECT_EQ(mesh.num_vertices(), 3);
    EXPECT_EQ(mesh.triangles, (Indices{0, 1, 2}));
}

TEST(ObjRead, NumberForms) {
    // A leading '+', exponents, a homogeneous w and the "v x y z r g b" colour extension.
    ObjMesh mesh = parse_obj("v +1.5 -2e-3 3E2\nv 1 2 3 1\nv 1 2 3 0.5 0.5 0.5\nvt 0.25\nvt 0.5 0.75 0\n");
    EXPECT_EQ(mesh.positions, (Floats{1.5f, -2e-3f, 300.0f, 1, 2, 3, 1, 2, 3}));
    EXPECT_EQ(mesh.uvs, (Floats{0.25f, 0.0f, 0.5f, 0.75f}));
}

TEST(ObjRead, ConvexPolygonsAreTriangulatedAsFansAndCounted) {
    ObjMesh mesh = parse_obj(std::string(kFourVertices) +
                             "v 0.5 2 0\n"
                             "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 1\n"
                             "f 1/1 2/2 3/3 4/4\n"
                             "f 1/1 2/2 3/3\n"
                             "f 1/1 2/2 3/3 5/5 4/4\n");
    EXPECT_EQ(mesh.polygons_triangulated, 2);
    EXPECT_EQ(mesh.triangles, (Indices{0, 1, 2, 0, 2, 3,  //
                                       0, 1, 2,           //
                                       0, 1, 2, 0, 2, 4, 0, 4, 3}));
    EXPECT_EQ(mesh.triangle_uvs, mesh.triangles) << "each fan corner keeps its own texture index";
}

// Signed area of triangle (a, b, c) of the xy plane.
double area(const Floats& p, std::int32_t a, std::int32_t b, std::int32_t c) {
    return 0.5 * ((p[3 * b] - p[3 * a]) * (p[3 * c + 1] - p[3 * a + 1]) -
                  (p[3 * b + 1] - p[3 * a + 1]) * (p[3 * c] - p[3 * a]));
}

TEST(ObjRead, ConcavePolygonsAreTriangulatedInside) {
    // An arrow whose corner 4 points inwards, and a comb of five teeth: the fan from the first corner would fold
    // over itself. Every triangle must turn the polygon's way and together they must cover its area exactly.
    const std::string arrow = "v 0 0 0\nv 2 0 0\nv 2 2 0\nv 1 0.5 0\nv 0 2 0\nf 1 2 3 4 5\n";
    // The comb: a 10 x 3 rectangle whose top edge runs down to y = 1 between peaks at x = 10, 8, ..., 0.
    std::string comb = "v 0 0 0\nv 10 0 0\n";
    for (int x = 10; x >= 0; --x) comb += "v " + std::to_string(x) + (x % 2 ? " 1 0\n" : " 3 0\n");
    comb += "f";
    for (int k = 1; k <= 13; ++k) comb += " " + std::to_string(k);
    comb += "\n";
    for (const auto& [text, polygon_area] : {std::pair<std::string, double>{arrow, 2.5}, {comb, 30.0 - 5 * 2.0}}) {
        ObjMesh mesh = parse_obj(text);
        const std::size_t corners = mesh.positions.size() / 3;
        ASSERT_EQ(mesh.triangles.size(), 3 * (corners - 2));
        double total = 0.0;
        for (std::size_t t = 0; t < mesh.triangles.size(); t += 3) {
            const double a = area(mesh.positions, mesh.triangles[t], mesh.triangles[t + 1], mesh.triangles[t + 2]);
            EXPECT_GT(a, 0.0) << "triangle " << t / 3 << " folds over";
            total += a;
        }
        EXPECT_NEAR(total, polygon_area, 1e-9);
    }
}

TEST(ObjRead, FacesWithAndWithoutUvsMix) {
    ObjMesh mesh = parse_obj("vt 0.5 0.25\n" + std::string(kFourVertices) + "f 1 2 3\nf 1/1 3/1 4/1\n");
    EXPECT_EQ(mesh.triangle_uvs, (Indices{1, 1, 1, 0, 0, 0})) << "the face without gets an added (0, 0)";
    EXPECT_EQ(mesh.uvs, (Floats{0.5f, 0.25f, 0.0f, 0.0f}));
    ASSERT_EQ(mesh.notes.size(), 1u);
    EXPECT_NE(mesh.notes[0].find("1 face without texture coordinates got (0, 0)"), std::string::npos) << mesh.notes[0];
    EXPECT_TRUE(parse_obj("vt 0 0\n" + std::string(kFourVertices) + "f 1 2 3\n").triangle_uvs.empty());
}

TEST(ObjRead, StatementsThatDescribeNoSurfaceAreSkippedWithOneNoteEach) {
    ObjMesh mesh = parse_obj(std::string(kFourVertices) + "l 1 2 3\nl 3 4\np 1\nvp 0.5\nf 1 2 3\ncstype bezier\n");
    EXPECT_EQ(mesh.triangles, (Indices{0, 1, 2}));
    EXPECT_EQ(mesh.notes,
              (std::vector<std::string>{"skipped 1 'cstype' statement (not part of the surface loopsub reads)",
                                        "skipped 2 'l' statements (polylines, not surfaces)",
                                        "skipped 1 'p' statement (points, not surfaces)",
                                        "skipped 1 'vp' statement (not part of the surface loopsub reads)"}));
}

TEST(ObjRead, CreaseTags) {
    ObjMesh mesh = parse_obj(std::string(kFourVertices) +
                             "f 1 2 3\nf 1 3 4\n"
                             "t crease 2/1/0 0 1 2.8\n"
                             "t crease 2/1/0  1  2   10\n"
                             "t crease 4/1/0 2 3 3 0 0.5\n"
                             "t crease 4/2/0 0 2 3 0 1.5 2.5\n");
    EXPECT_EQ(mesh.crease_edges, (Indices{0, 1, 1, 2, 2, 3, 3, 0, 0, 2, 3, 0}));
    EXPECT_EQ(mesh.crease_sharpness, (Floats{2.8f, 10.0f, 0.5f, 0.5f, 1.5f, 2.5f}));
    loopsub::MeshView view = mesh.view();
    EXPECT_EQ(view.num_crease_edges, 6);
    EXPECT_EQ(view.crease_edges, mesh.crease_edges.data());
    EXPECT_EQ(view.crease_sharpness, mesh.crease_sharpness.data());
}

TEST(ObjRead, CornerAndConeTags) {
    ObjMesh mesh = parse_obj(std::string(kFourVertices) +
                             "f 1 2 3\nf 1 3 4\n"
                             "t corner 1/1/0   2   2.5\n"
                             "t corner 2/1/0 0 1 10\n"
                             "t corner 2/2/0 3 2 1 4\n"
                             "t cone 1/0/0 3\n"
                             "t cone 2/0/0 0 1\n");
    EXPECT_EQ(mesh.corner_vertices, (Indices{2, 0, 1, 3, 2}));
    EXPECT_EQ(mesh.corner_sharpness, (Floats{2.5f, 10.0f, 10.0f, 1.0f, 4.0f}));
    EXPECT_EQ(mesh.cone_vertices, (Indices{3, 0, 1}));
    loopsub::MeshView view = mesh.view();
    EXPECT_EQ(view.num_vertices, 4);
    EXPECT_EQ(view.num_triangles, 2);
    EXPECT_EQ(view.num_corners, 5);
    EXPECT_EQ(view.num_cones, 3);
    EXPECT_EQ(view.cone_vertices, mesh.cone_vertices.data());
}

TEST(ObjRead, TagsMayComeBeforeTheVerticesTheyName) {
    ObjMesh mesh = parse_obj("t corner 1/1/0 2 1\nt crease 2/1/0 0 1 3\n" + std::string(kFourVertices) + "f 1 2 3\n");
    EXPECT_EQ(mesh.corner_vertices, (Indices{2}));
    EXPECT_EQ(mesh.crease_edges, (Indices{0, 1}));
}

TEST(ObjRead, InterpolateBoundaryUsesRenderMansNumbering) {
    EXPECT_FALSE(parse_obj(kFourVertices).boundary.has_value());
    EXPECT_EQ(parse_obj("t interpolateboundary 1/0/0 1\n").boundary, loopsub::Boundary::EdgesAndCorners);
    EXPECT_EQ(parse_obj("t interpolateboundary 1/0/0 2\n").boundary, loopsub::Boundary::EdgesOnly);
    EXPECT_EQ(parse_obj("t interpolateboundary 1/0/0 0\n").boundary, loopsub::Boundary::None);
    expect_error("t interpolateboundary 1/0/0 3\n", 1, "unknown");
}

TEST(ObjRead, FaceVaryingInterpolationUsesOpenSubdivsNumbering) {
    EXPECT_FALSE(parse_obj(kFourVertices).face_varying.has_value());
    for (int m = 0; m <= 5; ++m)
        EXPECT_EQ(parse_obj("t facevaryinginterpolateboundary 1/0/0 " + std::to_string(m) + "\n").face_varying,
                  loopsub::FaceVaryingInterpolation(m));
    expect_error("\nt facevaryinginterpolateboundary 1/0/0 6\n", 2, "unknown");
    expect_error("t facevaryinginterpolateboundary 1/0/0 -1\n", 1, "unknown");
}

// A hole names a face of the file, 0-based: all the triangles a polygon was split into.
TEST(ObjRead, HolesNameFacesOfTheFile) {
    const std::string mesh = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nf 1 2 3 4\nf 2 5 3\n";
    EXPECT_EQ(parse_obj(mesh + "t hole 1/0/0 0\n").hole_triangles, (std::vector<std::int32_t>{0, 1}));
    EXPECT_EQ(parse_obj(mesh + "t hole 1/0/0 1\n").hole_triangles, (std::vector<std::int32_t>{2}));
    EXPECT_EQ(parse_obj(mesh + "t hole 2/0/0 1 0\n").hole_triangles, (std::vector<std::int32_t>{2, 0, 1}));
    expect_error(mesh + "t hole 1/0/0 2\n", 8, "hole face 2 is out of range (2 faces");
    expect_error(mesh + "t hole 1/1/0 0 1.5\n", 8, "faces only");
}

TEST(ObjRead, CreaseMethod) {
    EXPECT_FALSE(parse_obj(kFourVertices).crease_method.has_value());
    EXPECT_EQ(parse_obj("t creasemethod 0/0/1 chaikin\n").crease_method, loopsub::CreaseMethod::Chaikin);
    // OpenSubdiv's shapes (loop_chaikin0) name the uniform method "normal".
    EXPECT_EQ(parse_obj("t creasemethod 0/0/1 normal\n").crease_method, loopsub::CreaseMethod::Uniform);
    EXPECT_EQ(parse_obj("t creasemethod 0/0/1 uniform\n").crease_method, loopsub::CreaseMethod::Uniform);
    expect_error("t creasemethod 0/0/1 wobbly\n", 1, "wobbly");
}

TEST(ObjRead, EmptyText) {
    ObjMesh mesh = parse_obj("");
    EXPECT_EQ(mesh.num_vertices(), 0);
    EXPECT_EQ(mesh.num_triangles(), 0);
}

TEST(ObjReadErrors, FaceIndicesOutOfRange) {
    std::string mesh = kFourVertices;  // lines 1-4
    expect_error(mesh + "f 1 2 5\n", 5, "vertex index 5 is out of range");
    expect_error(mesh + "f 1 2 0\n", 5, "start at 1");
    expect_error(mesh + "f 1 2 -5\n", 5, "vertex index -5 is out of range");
    expect_error(mesh + "vt 0 0\nf 1/1 2/2 3/2\n", 6, "texture index 2 is out of range");
    expect_error(mesh + "f 1 2 99999999999999999999\n", 5, "vertex index");
}

TEST(ObjReadErrors, MalformedStatements) {
    std::string mesh = kFourVertices;
    expect_error("v 1 2\n", 1, "missing coordinate");
    expect_error("v 1 2 x3\n", 1, "x3");
    expect_error("v 1 2 3 4 oops\n", 1, "oops");
    expect_error("\nvt\n", 2, "missing texture coordinate");
    expect_error("vt 0 0 0 7\n", 1, "unexpected '7'");
    expect_error(mesh + "f 1 2\n", 5, "at least 3 corners");
    expect_error(mesh + "f 1 2 3a\n", 5, "3a");
    expect_error(mesh + "f 1 2 /3\n", 5, "vertex index");
    expect_error("vt 0 0\n" + mesh + "f 1/1 2 3/1\n", 6, "some corners");
    expect_error(std::string("v 0 0 0\n\0v", 10), 2, "not plain text");
}

// Degenerate faces read (the core refuses them), and the core's refusal names the face's line, in OBJ's numbering: a
// triangle, and a polygon whose triangles would repeat a vertex.
TEST(ObjReadErrors, TheCoresRefusalOfAFaceNamesItsLine) {
    std::string mesh = kFourVertices;  // lines 1-4
    EXPECT_EQ(parse_obj(mesh + "f 1 2 3\nf 2 2 3\n").triangles, (Indices{0, 1, 2, 1, 1, 2}));
    expect_core_error(mesh + "f 1 2 3\nf 2 2 3\n", 6,
                      "the face repeats vertex 2 (a degenerate face; every corner must be a different vertex)");
    expect_core_error(mesh + "f 1 2 3 -4\n", 5,
                      "the face repeats vertex 1 and cannot be split into triangles that do not");
    // After a polygon of two triangles, the triangle of the next line is still the next face.
    expect_core_error(mesh + "f 1 2 3 4\n\nf 3 3 1\n", 7, "the face repeats vertex 3 (a degenerate face");
}

TEST(ObjReadErrors, NonFiniteCoordinates) {
    expect_error("v 0 nan 0\n", 1, "not finite");
    expect_error("v 0 0 0\nv inf 0 0\n", 2, "not finite");
    expect_error("v 1e39 0 0\n", 1, "out of range");
    expect_error("vt 0 -inf\n", 1, "not finite");
}

TEST(ObjReadErrors, MalformedTags) {
    std::string mesh = std::string(kFourVertices) + "f 1 2 3\nf 1 3 4\n";  // lines 1-6
    expect_error(mesh + "t bumpiness 1/0/0 0\n", 7, "unsupported tag 'bumpiness'");
    expect_error(mesh + "t crease 2/1 0 1 3\n", 7, "argument counts");
    expect_error(mesh + "t crease two/1/0 0 1 3\n", 7, "argument counts");
    expect_error(mesh + "t crease 2/1/0 0 1\n", 7, "missing tag value");
    expect_error(mesh + "t crease 2/1/0 0 1 3 4\n", 7, "unexpected '4'");
    expect_error(mesh + "t crease 2/1/0 0 one 3\n", 7, "one");
    expect_error(mesh + "t crease 3/1/0 0 1 2 3\n", 7, "vertex pairs");
    expect_error(mesh + "t crease 4/3/0 0 1 1 2 3 3 3\n", 7, "vertex pairs");
    expect_error(mesh + "t corner 1/0/0 0\n", 7, "one sharpness");
    expect_error(mesh + "t cone 1/1/0 0 1\n", 7, "vertices only");
    expect_error(mesh + "t creasemethod 0/0/0\n", 7, "one string");
}

// The core checks the tags' vertices and sharpness; its refusal names the tag's line.
TEST(ObjReadErrors, TagIndicesNameTheTagsLine) {
    std::string mesh = std::string(kFourVertices) + "f 1 2 3\nf 1 3 4\n";  // lines 1-6
    expect_core_error(mesh + "t crease 2/1/0 0 4 3\n", 7,
                      "crease vertex 4 is out of range (4 vertices, tags count from 0)");
    expect_core_error(mesh + "t crease 2/1/0 -1 0 3\n", 7, "crease vertex -1 is out of range");
    expect_core_error(mesh + "t corner 1/1/0 9 1\n", 7, "corner vertex 9 is out of range");
    expect_core_error(mesh + "t corner 1/1/0 1 1\nt cone 1/0/0 -2\n", 8, "cone vertex -2 is out of range");
    // The second crease of a tag of two on line 8.
    expect_core_error(mesh + "t crease 2/1/0 0 1 3\nt crease 4/1/0 0 1 2 9 1\n", 8, "crease vertex 9 is out of range");
    // 1-3 is a diagonal that no triangle has.
    expect_core_error(mesh + "t crease 2/1/0 0 1 3\n\nt crease 2/1/0 1 3 3\n", 9,
                      "crease 1-3 is not an edge of the mesh");
    expect_core_error(mesh + "t crease 2/1/0 0 1 -1\n", 7,
                      "tag 'crease' gives sharpness -1.000000; a sharpness is a finite number >= 0");
    expect_core_error(mesh + "t corner 1/1/0 0 1\nt corner 1/1/0 2 nan\n", 8, "tag 'corner' gives sharpness nan");
    // What 32 bits cannot hold the reader refuses itself, in the same words.
    expect_error(mesh + "t cone 1/0/0 5000000000\n", 7, "cone vertex 5000000000 is out of range (4 vertices");
}

TEST(ObjReadErrors, MissingFile) {
    std::string path = temp_path("does_not_exist.obj");
    std::remove(path.c_str());
    try {
        loopsub::obj::read_obj(path);
        FAIL() << "no InputError for a missing file";
    } catch (const loopsub::InputError& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
}

TEST(ObjWrite, RoundTripIsExact) {
    ObjMesh mesh;
    // Values whose shortest decimal form is long or extreme: the writer must not round them.
    mesh.positions = {0.1f,        -1.0f / 3.0f, 1e-7f, 3.4028235e38f,   -0.0f, 123456.789f,
                      2.0f / 7.0f, 5.0f,         -6.5f, 1.17549435e-38f, 7.0f,  8.0f};
    mesh.uvs = {0.0f, 0.0f, 1.0f, 0.0f, 0.3f, 0.7f};
    mesh.triangles = {0, 1, 2, 0, 2, 3};
    mesh.triangle_uvs = {0, 1, 2, 0, 2, 1};
    mesh.crease_edges = {0, 1, 2, 0};
    mesh.crease_sharpness = {10.0f, 2.8f};
    mesh.corner_vertices = {3};
    mesh.corner_sharpness = {0.25f};
    mesh.cone_vertices = {1, 2};
    mesh.boundary = loopsub::Boundary::EdgesAndCorners;
    mesh.crease_method = loopsub::CreaseMethod::Chaikin;

    std::string path = temp_path("round_trip.obj");
    loopsub::obj::write_obj(path, mesh);
    ObjMesh back = loopsub::obj::read_obj(path);
    EXPECT_EQ(back.positions, mesh.positions);
    EXPECT_EQ(back.uvs, mesh.uvs);
    EXPECT_EQ(back.triangles, mesh.triangles);
    EXPECT_EQ(back.triangle_uvs, mesh.triangle_uvs);
    EXPECT_EQ(back.crease_edges, mesh.crease_edges);
    EXPECT_EQ(back.crease_sharpness, mesh.crease_sharpness);
    EXPECT_EQ(back.corner_vertices, mesh.corner_vertices);
    EXPECT_EQ(back.corner_sharpness, mesh.corner_sharpness);
    EXPECT_EQ(back.cone_vertices, mesh.cone_vertices);
    EXPECT_EQ(back.boundary, mesh.boundary);
    EXPECT_EQ(back.crease_method, mesh.crease_method);
    EXPECT_EQ(back.polygons_triangulated, 0);
    std::remove(path.c_str());
}

TEST(ObjWrite, TagLinesInOpenSubdivsFormat) {
    ObjMesh mesh;
    mesh.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    mesh.triangles = {0, 1, 2};
    mesh.crease_edges = {1, 2};
    mesh.crease_sharpness = {2.5f};
    mesh.corner_vertices = {0};
    mesh.corner_sharpness = {10.0f};
    mesh.cone_vertices = {2};
    mesh.boundary = loopsub::Boundary::EdgesOnly;
    mesh.crease_method = loopsub::CreaseMethod::Uniform;
    std::string path = temp_path("tags.obj");
    loopsub::obj::write_obj(path, mesh);

    std::ifstream file(path);
    std::vector<std::string> lines;
    for (std::string line; std::getline(file, line);) lines.push_back(line);
    EXPECT_EQ(lines, (std::vector<std::string>{"v 0 0 0", "v 1 0 0", "v 0 1 0", "f 1 2 3", "t crease 2/1/0 1 2 2.5",
                                               "t corner 1/1/0 0 10", "t cone 1/0/0 2", "t interpolateboundary 1/0/0 2",
                                               "t creasemethod 0/0/1 normal"}));
    std::remove(path.c_str());
}

TEST(ObjWrite, FacesWithUvsUseVertexSlashTexture) {
    ObjMesh mesh;
    mesh.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    mesh.uvs = {0.5f, 0.25f};
    mesh.triangles = {0, 1, 2};
    mesh.triangle_uvs = {0, 0, 0};
    std::string path = temp_path("uvs.obj");
    loopsub::obj::write_obj(path, mesh);
    const std::string text = read_text(path);
    EXPECT_NE(text.find("vt 0.5 0.25\n"), std::string::npos) << text;
    EXPECT_NE(text.find("f 1/1 2/1 3/1\n"), std::string::npos) << text;
    std::remove(path.c_str());
}

// Formatting on several threads: chunks of 8,192 lines, eight per thread and round, written in order. The mesh (not
// a surface, only lines to write) has 210,000 v, vt, vn and f lines in 26 chunks: chunks start inside each kind of
// line, 1, 2 and 3 threads take several rounds (the last one short), 8 threads one, and 64 more threads than there
// are chunks. Every thread count must write the text a plain loop writes.
TEST(ObjWrite, ThreadsWriteTheSameBytes) {
    ObjMesh mesh;
    std::uint32_t state = 12345;
    auto next = [&] { return state = state * 1664525u + 1013904223u; };
    // Floats of every size and sign (no NaN or infinity), and small whole numbers.
    auto any_float = [&] {
        const std::uint32_t bits = next();
        float value;
        if (bits % 8 == 0) return float(int(next() % 2001) - 1000);
        const std::uint32_t finite = (bits & 0x807fffffu) | ((bits >> 23) % 255) << 23;
        std::memcpy(&value, &finite, sizeof value);
        return value;
    };
    for (int k = 0; k < 3 * 60000; ++k) mesh.positions.push_back(any_float());
    for (int k = 0; k < 2 * 30000; ++k) mesh.uvs.push_back(any_float());
    for (int k = 0; k < 3 * 20000; ++k) mesh.normals.push_back(any_float());
    for (int k = 0; k < 3 * 100000; ++k) {
        mesh.triangles.push_back(std::int32_t(next() % 60000));
        mesh.triangle_uvs.push_back(std::int32_t(next() % 30000));
        mesh.triangle_normals.push_back(std::int32_t(next() % 20000));
    }
    mesh.crease_edges = {0, 1};
    mesh.crease_sharpness = {2.5f};
    mesh.boundary = loopsub::Boundary::EdgesOnly;

    std::string expected;
    for (std::size_t k = 0; k < mesh.positions.size(); k += 3) {
        expected += "v " + to_chars_text(mesh.positions[k]) + " " + to_chars_text(mesh.positions[k + 1]) + " " +
                    to_chars_text(mesh.positions[k + 2]) + "\n";
    }
    for (std::size_t k = 0; k < mesh.uvs.size(); k += 2)
        expected += "vt " + to_chars_text(mesh.uvs[k]) + " " + to_chars_text(mesh.uvs[k + 1]) + "\n";
    for (std::size_t k = 0; k < mesh.normals.size(); k += 3) {
        expected += "vn " + to_chars_text(mesh.normals[k]) + " " + to_chars_text(mesh.normals[k + 1]) + " " +
                    to_chars_text(mesh.normals[k + 2]) + "\n";
    }
    for (std::size_t k = 0; k < mesh.triangles.size(); k += 3) {
        expected += "f";
        for (std::size_t c = k; c < k + 3; ++c) {
            expected += " " + std::to_string(mesh.triangles[c] + 1) + "/" + std::to_string(mesh.triangle_uvs[c] + 1) +
                        "/" + std::to_string(mesh.triangle_normals[c] + 1);
        }
        expected += "\n";
    }
    expected += "t crease 2/1/0 0 1 2.5\nt interpolateboundary 1/0/0 2\n";

    for (int threads : {1, 2, 3, 8, 64}) {
        SCOPED_TRACE(threads);
        const std::string path = temp_path("ThreadsWriteTheSameBytes_" + std::to_string(threads) + ".obj");
        loopsub::obj::write_obj(path, mesh, threads);
        const std::string text = read_text(path);
        std::remove(path.c_str());
        EXPECT_EQ(text.size(), expected.size());
        EXPECT_TRUE(text == expected)
            << "the text differs first at byte "
            << std::mismatch(text.begin(), text.end(), expected.begin(), expected.end()).first - text.begin();
    }
    const std::string empty = temp_path("ThreadsWriteTheSameBytes_empty.obj");
    loopsub::obj::write_obj(empty, ObjMesh{}, 3);
    EXPECT_EQ(read_text(empty), "");
    std::remove(empty.c_str());
}

TEST(ObjWrite, UnwritablePathThrows) {
    EXPECT_THROW(loopsub::obj::write_obj("/nonexistent-directory/out.obj", ObjMesh{}), std::runtime_error);
}

// OpenSubdiv's own shapes load with the tags their headers declare.
TEST(ObjPeerShapes, LoadWithTheirTags) {
    SKIP_WITHOUT_PEER_SHAPES();
    const std::string dir = LOOPSUB_PEER_SHAPES;
    ObjMesh cube = loopsub::obj::read_obj(dir + "/loop_cube_creases0.obj");
    EXPECT_EQ(cube.num_vertices(), 8);
    EXPECT_EQ(cube.num_triangles(), 12);
    EXPECT_EQ(cube.uvs.size(), 2u * 14);
    EXPECT_EQ(cube.triangle_uvs.size(), 3u * 12);
    EXPECT_EQ(cube.crease_edges, (Indices{1, 3, 3, 2}));
    EXPECT_EQ(cube.crease_sharpness, (Floats{2.8f, 2.8f}));
    EXPECT_EQ(cube.boundary, loopsub::Boundary::EdgesOnly);
    EXPECT_EQ(cube.polygons_triangulated, 0);

    ObjMesh icos = loopsub::obj::read_obj(dir + "/loop_icos_semisharp.obj");
    EXPECT_EQ(icos.corner_vertices, (Indices{4, 16}));
    EXPECT_EQ(icos.corner_sharpness, (Floats{2.5f, 4.5f}));
    EXPECT_EQ(icos.crease_sharpness.size(), 15u);

    ObjMesh chaikin = loopsub::obj::read_obj(dir + "/loop_chaikin0.obj");
    EXPECT_EQ(chaikin.crease_sharpness.size(), 28u);
    EXPECT_EQ(chaikin.crease_method, loopsub::CreaseMethod::Uniform);

    ObjMesh saddle = loopsub::obj::read_obj(dir + "/loop_saddle_edgecorner.obj");
    EXPECT_EQ(saddle.num_triangles(), 4);
    EXPECT_EQ(saddle.boundary, loopsub::Boundary::EdgesAndCorners);

    // loop_nonman_edges holds degenerate triangles (OpenSubdiv accepts them, loopsub does not): the first is on
    // line 193, "f 46/59 46/59 49/62".
    const ObjMesh nonmanifold = loopsub::obj::read_obj(dir + "/loop_nonman_edges.obj");
    try {
        loopsub::Plan(nonmanifold.view(), loopsub::Options{});
        ADD_FAILURE() << "loop_nonman_edges.obj planned without an error";
    } catch (const loopsub::InputError& e) {
        ASSERT_NE(e.problem(), nullptr);
        EXPECT_NE(loopsub::obj::locate(nonmanifold, "loop_nonman_edges.obj", *e.problem())
                      .find("loop_nonman_edges.obj:193: the face repeats vertex 46"),
                  std::string::npos)
            << e.what();
    }
    for (const char* name : {"loop_chaikin0", "loop_cube", "loop_fvar_bound0", "loop_icosahedron", "loop_pole8",
                             "loop_tetrahedron", "loop_triangle_edgecorner", "loop_xord_interior"}) {
        SCOPED_TRACE(name);
        ObjMesh mesh = loopsub::obj::read_obj(dir + "/" + name + ".obj");
        EXPECT_GT(mesh.num_triangles(), 0);
        EXPECT_EQ(mesh.polygons_triangulated, 0);
    }
}

}  // namespace
