// The fast paths of the CLI's OBJ reader and writer. The writer formats lines straight into blocks and must write
// numbers exactly as std::to_chars writes them, the shortest form that reads back exactly; the reader reads the
// common lines on a fast path in one pass and must read them exactly as its general path, token by token, does;
// read_obj reads a file in blocks and must read it, errors included, as parse_obj reads its whole text.
#include <gtest/gtest.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "obj_io.h"
#include "test_files.h"

namespace {

using loopsub::obj::ObjMesh;
using loopsub::obj::parse_obj;
using loopsub::testing::read_text;
using loopsub::testing::temp_path;
using loopsub::testing::to_chars_text;
using loopsub::testing::write_text;

float from_bits(std::uint32_t bits) {
    float value;
    std::memcpy(&value, &bits, sizeof value);
    return value;
}

std::uint32_t to_bits(float value) {
    std::uint32_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    return bits;
}

// Floats where formatting changes form: every power of two and of ten, the neighbours of both, whole numbers around
// 2^24 and where fixed notation gives way to scientific, subnormals, the extremes; then a spread of bit patterns.
std::vector<float> awkward_floats() {
    std::vector<float> values = {0.0f,
                                 -0.0f,
                                 0.1f,
                                 0.2f,
                                 0.3f,
                                 1.0f / 3.0f,
                                 2.0f / 3.0f,
                                 123456.789f,
                                 9.999999e-5f,
                                 1e-4f,
                                 1.0001e-4f,
                                 std::numeric_limits<float>::denorm_min(),
                                 std::numeric_limits<float>::min(),
                                 std::numeric_limits<float>::max(),
                                 std::numeric_limits<float>::epsilon()};
    for (int e = -149; e <= 127; ++e) {
        const float p = std::ldexp(1.0f, e);
        values.insert(values.end(), {p, std::nextafter(p, 0.0f), std::nextafter(p, 1e38f)});
    }
    for (int e = -45; e <= 38; ++e) {
        const float p = std::strtof(("1e" + std::to_string(e)).c_str(), nullptr);
        values.insert(values.end(), {p, std::nextafter(p, 0.0f), std::nextafter(p, 1e38f)});
    }
    for (double base : {1.0, 12.0, 123.0, 1234.0, 12345.0, 123456.0, 1234567.0, 12345678.0, 123456789.0}) {
        for (int e = 0; e <= 8; ++e) values.push_back(float(base * std::pow(10.0, e)));
    }
    for (std::uint32_t v = (1u << 24) - 40; v <= (1u << 24) + 40; ++v) values.push_back(float(v));
    for (std::uint32_t bits = 0; bits < 0x7f800000u; bits += 7919) values.push_back(from_bits(bits));
    const std::size_t positive = values.size();
    for (std::size_t k = 0; k < positive; ++k) values.push_back(-values[k]);
    while (values.size() % 3) values.push_back(1.0f);
    return values;
}

TEST(ObjFast, FloatsAreWrittenAsToCharsWritesThemAndReadBackExactly) {
    ObjMesh mesh;
    mesh.positions = awkward_floats();
    mesh.uvs = {0.1f, 1e-10f, 3e38f, -7.0f};
    const std::string path = temp_path("floats.obj");
    loopsub::obj::write_obj(path, mesh);

    std::string expected;
    for (std::size_t k = 0; k < mesh.positions.size(); k += 3) {
        expected += "v " + to_chars_text(mesh.positions[k]) + " " + to_chars_text(mesh.positions[k + 1]) + " " +
                    to_chars_text(mesh.positions[k + 2]) + "\n";
    }
    expected += "vt 0.1 1e-10\nvt 3e+38 -7\n";
    const std::string text = read_text(path);
    ASSERT_EQ(text.size(), expected.size());
    // One failure per differing line rather than one for the whole file.
    for (std::size_t start = 0, failures = 0; start < text.size() && failures < 10;) {
        const std::size_t end = text.find('\n', start) + 1;
        if (text.compare(start, end - start, expected, start, end - start) != 0) {
            ADD_FAILURE() << "wrote " << text.substr(start, end - start) << "expected "
                          << expected.substr(start, end - start);
            ++failures;
        }
        start = end;
    }

    const ObjMesh back = loopsub::obj::read_obj(path);
    ASSERT_EQ(back.positions.size(), mesh.positions.size());
    for (std::size_t k = 0; k < mesh.positions.size(); ++k) {
        ASSERT_EQ(to_bits(back.positions[k]), to_bits(mesh.positions[k]))
            << "coordinate " << k << ": " << to_chars_text(mesh.positions[k]);
    }
    EXPECT_EQ(back.uvs, mesh.uvs);
    std::remove(path.c_str());
}

TEST(ObjFast, NonFiniteValuesAreWrittenAsToCharsWritesThem) {
    ObjMesh mesh;
    mesh.positions = {std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                      std::numeric_limits<float>::quiet_NaN()};
    const std::string path = temp_path("non_finite.obj");
    loopsub::obj::write_obj(path, mesh);
    EXPECT_EQ(read_text(path), "v inf -inf " + to_chars_text(mesh.positions[2]) + "\n");
    std::remove(path.c_str());
}

TEST(ObjFast, IndicesOfEveryLength) {
    ObjMesh mesh;
    mesh.positions = {0, 0, 0};
    for (std::int32_t v :
         {0,     8,      9,      98,      99,      998,      999,      9998,      9999,      99998,
          99999, 999998, 999999, 9999998, 9999999, 99999998, 99999999, 999999998, 999999999, 2147483646}) {
        mesh.triangles.insert(mesh.triangles.end(), {v, v, v});
    }
    mesh.triangle_uvs = mesh.triangles;
    mesh.crease_edges = {0, 2147483647};
    mesh.crease_sharpness = {1.5f};
    mesh.corner_vertices = {1234567};
    mesh.corner_sharpness = {10.0f};
    mesh.cone_vertices = {7};
    const std::string path = temp_path("indices.obj");
    loopsub::obj::write_obj(path, mesh);
    std::string expected = "v 0 0 0\n";
    for (const char* n : {"1",        "9",        "10",        "99",        "100",        "999",       "1000",
                          "9999",     "10000",    "99999",     "100000",    "999999",     "1000000",   "9999999",
                          "10000000", "99999999", "100000000", "999999999", "1000000000", "2147483647"}) {
        const std::string corner = std::string(n) + "/" + n;
        expected += "f " + corner + " " + corner + " " + corner + "\n";
    }
    expected += "t crease 2/1/0 0 2147483647 1.5\nt corner 1/1/0 1234567 10\nt cone 1/0/0 7\n";
    EXPECT_EQ(read_text(path), expected);
    std::remove(path.c_str());
}

// "v x y z" is read on the fast path; with a fourth value (w) the same line goes through the general path, which
// parses with std::from_chars. Both must give the same floats, or the same error.
TEST(ObjFast, FastAndGeneralPathsReadNumbersAlike) {
    const std::vector<std::string> numbers = {
        "0", "-0", "1", "-1", "0.5", "-0.5", "1.", ".5", "-.5", "+1.5", "00012.5000", "1e3", "1E3", "1e+3", "1e-3",
        "1e003", "1e0003", "1e", "1e+", "1.5e", "0.1", "0.30000001", "3.4028235e38", "3.4028236e38", "3.5e38",
        "1.1754944e-38", "1.1754942e-38", "1e-40", "1e-46", "1e39", "1.00000005960464477539062500001",
        "1.0000000596046447753906250", "1.00000005960464477539062499999", "16777217", "16777216.5", "33554434",
        // Within half a double's spacing of the midpoint between two floats, on the side the tie does not round to:
        // rounded to double first, they would land on the midpoint, then on the wrong float.
        "5.000000298023224e-01", "1.024000288452953e-03", "8.000003337860107", "8.000004291534424", "9007199254740993",
        "123456789012345678901234567890", "0.000000000000000000000000000000001", "1234567.1234567", "4.9999998e-8",
        "nan", "inf", "-inf", "infinity", "0x1p3", "1..5", "1e5x", "--1", "x"};
    for (const std::string& number : numbers) {
        SCOPED_TRACE(number);
        const std::string fast = "v " + number + " 2 " + number + "\n";
        const std::string general = "v " + number + " 2 " + number + " 1\n";
        std::string fast_error, general_error;
        ObjMesh a, b;
        try {
            a = parse_obj(fast, "n.obj");
        } catch (const loopsub::InputError& e) { fast_error = e.what(); }
        try {
            b = parse_obj(general, "n.obj");
        } catch (const loopsub::InputError& e) { general_error = e.what(); }
        EXPECT_EQ(fast_error, general_error);
        ASSERT_EQ(a.positions.size(), b.positions.size());
        for (std::size_t k = 0; k < a.positions.size(); ++k)
            EXPECT_EQ(to_bits(a.positions[k]), to_bits(b.positions[k]));
    }
}

// Face lines the fast path reads, and the same faces through the general path (a '+' sign sends a line there).
TEST(ObjFast, FastAndGeneralPathsReadFacesAlike) {
    const std::string head = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n";
    const std::vector<std::pair<std::string, std::string>> faces = {
        {"f 1 2 3", "f +1 2 3"},
        {"f\t1\t2\t3\r", "f\t+1\t2\t3\r"},
        {"f 1 2 3   ", "f +1 2 3   "},
        {"f -4 -3 -2", "f -4 -3 +3"},
        {"f 1/1 2/2 3/3", "f 1/+1 2/2 3/3"},
        {"f 1/-3 2/-2 3/-1", "f +1/-3 2/-2 3/-1"},
        {"f 1//1 2//2 3//3", "f +1//1 2//2 3//3"},
        {"f 1/1/1 2/2/2 3/3/3", "f +1/1/1 2/2/2 3/3/3"},
        {"f 1/1/x 2/2/ 3/3/junk/more", "f +1/1/x 2/2/ 3/3/junk/more"},
        {"f 1/ 2/ 3/", "f +1/ 2/ 3/"},
        {"f 1// 2// 3//", "f +1// 2// 3//"},
        {"f 2 3 4\nf 1/1 2/2 3/3", "f 2 3 +4\nf 1/1 2/2 3/+3"},
        {"f 1 1 2", "f +1 1 2"},  // degenerate: the core refuses it, by the line both paths keep
    };
    for (const auto& [fast, general] : faces) {
        SCOPED_TRACE(fast);
        const ObjMesh a = parse_obj(head + fast + "\n");
        const ObjMesh b = parse_obj(head + general + "\n");
        EXPECT_EQ(a.triangles, b.triangles);
        EXPECT_EQ(a.triangle_uvs, b.triangle_uvs);
        EXPECT_EQ(a.uvs, b.uvs);
        EXPECT_EQ(a.notes, b.notes);
        EXPECT_EQ(a.face_lines, b.face_lines);
        EXPECT_EQ(a.face_first_triangle, b.face_first_triangle);
    }
    // Lines the fast path leaves to the general path keep their messages.
    for (const auto& [face, message] :
         std::vector<std::pair<std::string, std::string>>{{"f 1 2 5", "n.obj:8: vertex index 5 is out of range"},
                                                          {"f 1 2 0", "start at 1"},
                                                          {"f 1/1 2 3/3", "some corners"},
                                                          {"f 1/4 2/1 3/1", "texture index 4 is out of range"},
                                                          {"f 1 2 3x", "got '3x'"},
                                                          {"f 1/x 2 3", "got 'x'"},
                                                          {"f 1 2", "at least 3 corners"},
                                                          {"f 1 2 99999999999999999999", "vertex index"}}) {
        SCOPED_TRACE(face);
        try {
            parse_obj(head + face + "\n", "n.obj");
            ADD_FAILURE() << "no error";
        } catch (const loopsub::InputError& e) {
            EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
        }
    }
}

// read_obj's result, or its error message.
std::string read_error(const std::string& path) {
    try {
        loopsub::obj::read_obj(path);
    } catch (const loopsub::InputError& e) { return e.what(); }
    return "";
}

// Files larger than the reader's block (1 MiB): lines across block edges, a line longer than a block, and errors in
// the same order as for the text read whole: a NUL byte anywhere before the first bad line.
TEST(ObjFast, FilesAreReadInBlocksAsTheirWholeText) {
    std::string text;
    for (int k = 0; text.size() < 3'500'000; ++k) {
        text += "v " + std::to_string(k % 1000) + ".25 " + std::to_string(k) + " -0.125\n";
        if (k % 1000 == 999) text += "# " + std::string(std::size_t(k % 7), 'x') + "\n";
    }
    text += "vt 0.5 0.5\n# " + std::string(2'500'000, 'c') + "\n";  // a line longer than a block
    for (int k = 1; k + 2 < 100000; k += 3) {
        text += "f " + std::to_string(k) + "/1 " + std::to_string(k + 1) + "/1 " + std::to_string(k + 2) + "/1\n";
    }
    text += "t crease 2/1/0 0 1 2.5\nt corner 1/1/0 7 3\n";
    const std::string path = temp_path("blocks.obj");
    write_text(path, text);
    const ObjMesh whole = parse_obj(text, path);
    const ObjMesh blocks = loopsub::obj::read_obj(path);
    EXPECT_GT(whole.num_vertices(), 100000);
    EXPECT_EQ(blocks.positions, whole.positions);
    EXPECT_EQ(blocks.triangles, whole.triangles);
    EXPECT_EQ(blocks.triangle_uvs, whole.triangle_uvs);
    EXPECT_EQ(blocks.uvs, whole.uvs);
    EXPECT_EQ(blocks.crease_edges, whole.crease_edges);
    EXPECT_EQ(blocks.corner_vertices, whole.corner_vertices);
    EXPECT_EQ(blocks.notes, whole.notes);

    // The same file without its last newline, then with errors: the messages must be parse_obj's.
    const int lines = int(std::count(text.begin(), text.end(), '\n'));
    std::vector<std::string> broken = {text.substr(0, text.size() - 1)};
    broken.push_back(std::string(text).insert(text.size() / 2, "f 1 2\n"));  // a bad line in the middle
    broken.push_back(text + "f 1 2 0\n");                                    // on the last line
    broken.push_back(text + "\nv 1 2");                                      // the last line, unfinished
    broken.push_back("v 1 2 x\n" + text + std::string(1, '\0'));             // a NUL byte after a bad line
    broken.push_back("v 1 2 x\n" + std::string(text).insert(text.size() / 3, std::string(1, '\0')));
    broken.push_back(std::string(text).replace(2000, 1, std::string(1, '\0')));  // in the first block
    {
        // A bad line in the second block, a NUL byte in the third.
        std::string both = text;
        both.replace(both.find('\n', 2'600'000) + 1, 0, std::string(1, '\0'));
        both.replace(both.find('\n', 1'500'000) + 1, 0, "v 1 2 x\n");
        broken.push_back(both);
    }
    broken.push_back(text + "t hole 1/0/0 500000\n");  // found after the last line
    for (std::size_t k = 0; k < broken.size(); ++k) {
        SCOPED_TRACE("case " + std::to_string(k));
        write_text(path, broken[k]);
        std::string expected;
        try {
            parse_obj(broken[k], path);
        } catch (const loopsub::InputError& e) { expected = e.what(); }
        EXPECT_EQ(read_error(path), expected);
        if (k > 0) { EXPECT_FALSE(expected.empty()); }
    }
    EXPECT_NE(read_error(path).find(":" + std::to_string(lines + 1) + ": "), std::string::npos);
    std::remove(path.c_str());
}

}  // namespace
