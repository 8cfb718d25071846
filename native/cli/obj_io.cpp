// Wavefront OBJ with OpenSubdiv's tags. The reader scans the text in place, with one pass over the common "v x y z"
// and "f a b c" lines and the general per-token reader for everything else; the writer formats into blocks with
// a shortest round-trip float formatter (what std::to_chars writes, at a fraction of its cost), so write -> read is
// exact, and can format its v, vt, vn and f lines on several threads (the same bytes for any number).
#include "obj_io.h"

#include <map>

#include "triangulate.h"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <string_view>
#include <system_error>
#include <thread>
#include <unordered_set>

namespace loopsub::obj {

namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// ---- Numbers in -----------------------------------------------------------------------------------------------
// libstdc++ 12's std::from_chars takes about 8 ns for an integer and 13 ns for a float. The fast paths of the reader
// first try these, which read only the plain forms (what this writer and most exporters write) and give the same
// value and end as from_chars, and leave everything else to from_chars: nullptr means "ask std::from_chars".

bool is_digit(char c) { return static_cast<unsigned>(c - '0') < 10; }

// The number parsers run once or twice per number: inlined into the line readers, they save a call's register
// saves and restores, about a third of their instructions.
#if defined(__GNUC__) || defined(__clang__)
#define LOOPSUB_OBJ_INLINE inline __attribute__((always_inline))
#else
#define LOOPSUB_OBJ_INLINE inline
#endif

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_BIG_ENDIAN__
constexpr bool kLittleEndian = false;
#else
constexpr bool kLittleEndian = true;
#endif

constexpr std::uint64_t kPowersOf10[] = {1, 10, 100, 1000, 10000, 100000, 1000000, 10000000, 100000000};

// The index of the lowest set bit of x (x is not 0).
int lowest_set_bit(std::uint64_t x) {
#if defined(__GNUC__) || defined(__clang__)
    return __builtin_ctzll(x);
#else
    int n = 0;
    for (; !(x & 1); x >>= 1) ++n;
    return n;
#endif
}

int lowest_nonzero_byte(std::uint64_t x) { return lowest_set_bit(x) / 8; }

// Reads the run of decimal digits at p into `value` (value * 10^n + the n digits) and adds n to `digits`; returns the
// end of the run, or nullptr once `digits` would pass max_digits (at most 19, so that value cannot overflow). Where 8
// bytes can be read, it takes up to 8 digits at once from a little-endian word.
LOOPSUB_OBJ_INLINE const char* read_digit_run(const char* p, const char* end, std::uint64_t& value, int& digits, int max_digits) {
    if constexpr (kLittleEndian) {
        while (end - p >= 8) {
            std::uint64_t word;
            std::memcpy(&word, p, sizeof word);
            // A byte's top bit is set here when it is not '0'-'9' (carries and borrows reach only later bytes).
            const std::uint64_t flags =
                ((word + 0x4646464646464646u) | (word - 0x3030303030303030u)) & 0x8080808080808080u;
            // The number of digit bytes before the first flagged one, 8 if none (the bit at 63 stands for byte 8).
            const int n = (lowest_set_bit((flags >> 7) | (std::uint64_t(1) << 63)) + 1) / 8;
            if (n == 0) return p;
            digits += n;
            if (digits > max_digits) return nullptr;
            // The n digit values moved to the top bytes, with zeros (leading zeros) below: one 8-digit number.
            std::uint64_t v = (word - 0x3030303030303030u) << (8 * (8 - n));
            v = v * 10 + (v >> 8);
            v = (((v & 0x000000ff000000ffu) * 0x000f424000000064u) + (((v >> 16) & 0x000000ff000000ffu) * 0x0000271000000001u)) >> 32;
            value = value * kPowersOf10[n] + std::uint32_t(v);
            p += n;
            if (n < 8) return p;
        }
    }
    for (; p < end && is_digit(*p); ++p) {
        if (++digits > max_digits) return nullptr;
        value = 10 * value + std::uint64_t(*p - '0');
    }
    return p;
}

// An optional '-' and 1 to 18 digits (no overflow possible).
LOOPSUB_OBJ_INLINE const char* parse_plain_integer(const char* p, const char* end, std::int64_t& value) {
    const bool negative = p < end && *p == '-';
    const char* const start = p + negative;
    std::uint64_t n = 0;
    int digits = 0;
    p = read_digit_run(start, end, n, digits, 18);
    if (!p || p == start) return nullptr;
    value = negative ? -std::int64_t(n) : std::int64_t(n);
    return p;
}

constexpr double kExactPowersOf10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                       1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

// An optional '-', digits, optionally '.' and digits, optionally an exponent (e or E, an optional sign, 1 to 3
// digits), at most 19 digits in all; its value a normal float. The value is Clinger's: a significand below 2^53
// times or over an exact power of ten (at most 10^22) is one correctly rounded double operation. Rounding that
// double to float gives the float nearest the decimal, except when the double fell exactly on the midpoint
// between two floats (the decimal may lie on either side of it): then from_chars decides.
LOOPSUB_OBJ_INLINE const char* parse_plain_float(const char* p, const char* end, float& value) {
    // Where double arithmetic is carried out in a wider type (x87), the one rounding is not to double.
    if constexpr (FLT_EVAL_METHOD != 0 && FLT_EVAL_METHOD != 1) return nullptr;
    const bool negative = p < end && *p == '-';
    p += negative;
    std::uint64_t significand = 0;
    int digits = 0;
    int exponent = 0;
    const char* const whole = p;
    p = read_digit_run(whole, end, significand, digits, 19);
    if (!p || p == whole) return nullptr;  // too many digits; ".5", "inf", "nan", "+1"...
    if (p < end && *p == '.') {
        const char* const fraction = p + 1;
        p = read_digit_run(fraction, end, significand, digits, 19);
        if (!p || p == fraction) return nullptr;  // too many digits; "1."
        exponent = -int(p - fraction);
    }
    if (p < end && (*p == 'e' || *p == 'E')) {
        ++p;
        const bool negative_exponent = p < end && *p == '-';
        if (p < end && (*p == '-' || *p == '+')) ++p;
        const char* const exponent_digits = p;
        int e = 0;
        for (; p < end && is_digit(*p); ++p) {
            if (p - exponent_digits == 3) return nullptr;
            e = 10 * e + (*p - '0');
        }
        if (p == exponent_digits) return nullptr;  // "1e", where from_chars stops before the 'e'
        exponent += negative_exponent ? -e : e;
    }
    if (significand > (std::uint64_t(1) << 53) || exponent < -22 || exponent > 22) return nullptr;
    double x = double(significand);
    x = exponent < 0 ? x / kExactPowersOf10[-exponent] : x * kExactPowersOf10[exponent];
    if (x != 0.0 && !(x >= double(std::numeric_limits<float>::min()) && x <= double(std::numeric_limits<float>::max()))) {
        return nullptr;  // subnormal or out of range
    }
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    if ((bits & 0x1fffffff) == 0x10000000) return nullptr;  // the 29 bits below a float's precision: one half
    value = float(negative ? -x : x);
    return p;
}

LOOPSUB_OBJ_INLINE std::from_chars_result read_float(const char* p, const char* end, float& value) {
    if (const char* next = parse_plain_float(p, end, value)) return {next, std::errc()};
    return std::from_chars(p, end, value);
}

LOOPSUB_OBJ_INLINE std::from_chars_result read_integer(const char* p, const char* end, std::int64_t& value) {
    if (const char* next = parse_plain_integer(p, end, value)) return {next, std::errc()};
    return std::from_chars(p, end, value);
}

// Vertex indices in tags are checked once the whole file is read (a tag may precede the vertices it names), so
// each tagged index remembers the line it came from.
struct TaggedIndex {
    std::int64_t value;
    int line;
};

constexpr const char* kNotPlainText = "the file is not plain text (it holds a NUL byte; save UTF-16 files as UTF-8)";

// Reads a text line by line, given whole lines at a time: the text of a string in one piece, a file block by block.
class Reader {
public:
    explicit Reader(const std::string& name) : name_(name) {}

    // Room for a closed triangle mesh (twice as many faces as vertices) of as many lines as `sample`, the start of
    // a text of `size` bytes, promises, and half as many again: the arrays of a large file are then not copied as
    // they grow (a few ms for a million triangles). Only what is filled becomes memory; other files grow them.
    void reserve_for(std::string_view sample, std::size_t size) {
        if (sample.empty()) return;
        const double lines = double(std::count(sample.begin(), sample.end(), '\n') + 1) *
                             (double(std::max(size, sample.size())) / double(sample.size())) * 1.5;
        const std::size_t vertices = std::size_t(lines / 3);
        mesh_.positions.reserve(3 * vertices);
        mesh_.triangles.reserve(3 * 2 * vertices);
    }

    // Reads the lines of `text`, which ends with a '\n' or at the end of the file. A NUL byte anywhere in it is
    // reported before any of its lines is read.
    void read_lines(std::string_view text) {
        end_ = text.data() + text.size();
        if (const void* nul = std::memchr(text.data(), '\0', text.size())) {
            line_ += 1 + int(std::count(text.data(), static_cast<const char*>(nul), '\n'));
            found_nul_ = true;
            fail(kNotPlainText);
        }
        for (const char* line = text.data(); line < end_;) {
            ++line_;
            const char* next = nullptr;
            if (end_ - line >= 2 && is_blank(line[1])) {
                if (line[0] == 'v') next = read_plain_vertex(line + 2);
                else if (line[0] == 'f') next = read_plain_triangle(line + 2);
            }
            if (!next) {
                const void* newline = std::memchr(line, '\n', std::size_t(end_ - line));
                cursor_ = line;
                line_end_ = newline ? static_cast<const char*>(newline) : end_;
                read_line();
                next = line_end_ == end_ ? end_ : line_end_ + 1;
            }
            line = next;
        }
    }

    ObjMesh finish() {
        check_tag_indices();
        fill_missing_uvs();
        note_skipped();
        return std::move(mesh_);
    }

    int lines_read() const { return line_; }
    bool found_nul() const { return found_nul_; }

private:
    [[noreturn]] void fail(const std::string& message) const { fail_at(line_, message); }
    [[noreturn]] void fail_at(int line, const std::string& message) const {
        throw InputError(name_ + ":" + std::to_string(line) + ": " + message);
    }

    // The next whitespace-separated token of the current line; empty at its end.
    std::string_view token() {
        while (cursor_ < line_end_ && is_blank(*cursor_)) ++cursor_;
        const char* start = cursor_;
        while (cursor_ < line_end_ && !is_blank(*cursor_)) ++cursor_;
        return {start, std::size_t(cursor_ - start)};
    }

    std::string_view required_token(const char* what) {
        std::string_view t = token();
        if (t.empty()) fail(std::string("missing ") + what);
        return t;
    }

    void expect_line_end() {
        std::string_view extra = token();
        if (!extra.empty()) fail("unexpected '" + std::string(extra) + "' at the end of the line");
    }

    float parse_float(std::string_view t, const char* what) {
        // from_chars rejects the leading '+' that some exporters write.
        std::string_view digits = !t.empty() && t[0] == '+' ? t.substr(1) : t;
        float value = 0.0f;
        auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
        if (error == std::errc::result_out_of_range) fail(std::string(what) + " '" + std::string(t) + "' is out of range");
        if (error != std::errc() || end != digits.data() + digits.size()) {
            fail("expected a number for " + std::string(what) + ", got '" + std::string(t) + "'");
        }
        return value;
    }

    float parse_finite(std::string_view t, const char* what) {
        float value = parse_float(t, what);
        if (!std::isfinite(value)) fail(std::string(what) + " is not finite: '" + std::string(t) + "'");
        return value;
    }

    std::int64_t parse_integer(std::string_view t, const char* what) {
        std::string_view digits = !t.empty() && t[0] == '+' ? t.substr(1) : t;
        std::int64_t value = 0;
        auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
        if (error != std::errc() || end != digits.data() + digits.size()) {
            fail("expected an integer for " + std::string(what) + ", got '" + std::string(t) + "'");
        }
        return value;
    }

    // The fast paths: "v x y z" and "f a b c" (each corner "v", "v/t", "v//n" or "v/t/n") read in one pass over
    // the line, from just after the keyword. They take only what is plainly valid and return the start of the next
    // line; for anything else (a '+' sign, a w, a polygon, an index out of range, a malformed number...) they change
    // nothing and return nullptr, and read_line() reads the line again with every rule and error message. Numbers
    // are read as from_chars reads the same characters, so both paths read a line alike.
    bool ends_token(const char* p) const { return p == end_ || *p == '\n' || is_blank(*p); }

    const char* skip_blanks(const char* p) const {
        while (p < end_ && is_blank(*p)) ++p;
        return p;
    }

    // After the last token: the next line's start, or nullptr if anything but blanks is left on this one.
    const char* line_after(const char* p) const {
        p = skip_blanks(p);
        if (p == end_) return p;
        return *p == '\n' ? p + 1 : nullptr;
    }

    const char* read_plain_vertex(const char* p) {
        float xyz[3];
        for (float& value : xyz) {
            p = skip_blanks(p);
            const auto [next, error] = read_float(p, end_, value);
            if (error != std::errc() || !ends_token(next) || !std::isfinite(value)) return nullptr;
            p = next;
        }
        const char* next_line = line_after(p);
        if (next_line) mesh_.positions.insert(mesh_.positions.end(), xyz, xyz + 3);
        return next_line;
    }

    // resolve() without the error: -1 for a reference out of range.
    static std::int32_t resolve_plain(std::int64_t reference, std::size_t defined) {
        const std::int64_t count = std::int64_t(defined);
        const std::int64_t index = reference > 0 ? reference - 1 : count + reference;
        return reference != 0 && index >= 0 && index < count ? std::int32_t(index) : -1;
    }

    const char* read_plain_triangle(const char* p) {
        std::int32_t vertices[3], uvs[3];
        int corners = 0;
        bool with_uvs = false;
        for (p = skip_blanks(p); !ends_token(p); p = skip_blanks(p)) {
            if (corners == 3) return nullptr;  // a polygon
            std::int64_t reference = 0;
            std::from_chars_result read = read_integer(p, end_, reference);
            if (read.ec != std::errc()) return nullptr;
            const std::int32_t vertex = resolve_plain(reference, mesh_.positions.size() / 3);
            if (vertex < 0) return nullptr;
            p = read.ptr;
            bool corner_uv = false;
            if (p < end_ && *p == '/') {
                ++p;
                if (!ends_token(p) && *p != '/') {
                    read = read_integer(p, end_, reference);
                    if (read.ec != std::errc() || !(ends_token(read.ptr) || *read.ptr == '/')) return nullptr;
                    uvs[corners] = resolve_plain(reference, mesh_.uvs.size() / 2);
                    if (uvs[corners] < 0) return nullptr;
                    corner_uv = true;
                    p = read.ptr;
                }
                // A normal index (or anything up to the next blank) is read past, as the general path does.
                while (!ends_token(p)) ++p;
            } else if (!ends_token(p)) {
                return nullptr;
            }
            if (corners == 0) {
                with_uvs = corner_uv;
            } else if (corner_uv != with_uvs) {
                return nullptr;
            }
            vertices[corners++] = vertex;
        }
        if (corners != 3 || vertices[0] == vertices[1] || vertices[1] == vertices[2] || vertices[2] == vertices[0]) {
            return nullptr;
        }
        if (!with_uvs) ++faces_without_uvs_;
        face_first_triangle_.push_back(mesh_.num_triangles());
        add_triangle(vertices, with_uvs ? uvs : nullptr);
        return p == end_ ? p : p + 1;
    }

    // uvs: the triangle's three texture indices, or nullptr. Texture indices are kept only once a face has had them.
    void add_triangle(const std::int32_t vertices[3], const std::int32_t* uvs) {
        if (uvs && !any_uvs_) {
            mesh_.triangle_uvs.assign(mesh_.triangles.size(), -1);  // -1: filled in at the end
            any_uvs_ = true;
        }
        mesh_.triangles.insert(mesh_.triangles.end(), vertices, vertices + 3);
        if (uvs) {
            mesh_.triangle_uvs.insert(mesh_.triangle_uvs.end(), uvs, uvs + 3);
        } else if (any_uvs_) {
            mesh_.triangle_uvs.insert(mesh_.triangle_uvs.end(), 3, -1);
        }
    }

    void read_line() {
        std::string_view keyword = token();
        if (keyword.empty() || keyword[0] == '#') return;
        if (keyword == "v") return read_vertex();
        if (keyword == "vt") return read_uv();
        if (keyword == "f") return read_face();
        if (keyword == "t") return read_tag();
        // Everything else describes no part of the surface (normals are recomputed from the refined surface; lines,
        // points, curves, groups, smoothing groups and materials do not change it): skipped, and said once per kind.
        ++skipped_[std::string(keyword)];
    }

    void note_skipped() {
        static const std::map<std::string, const char*> what = {
            {"vn", "normals, recomputed from the subdivided surface"},
            {"l", "polylines, not surfaces"},
            {"p", "points, not surfaces"},
            {"o", "object names"},
            {"g", "group names"},
            {"s", "smoothing groups"},
            {"usemtl", "materials"},
            {"mtllib", "material libraries"},
        };
        for (const auto& [keyword, count] : skipped_) {
            const auto known = what.find(keyword);
            mesh_.notes.push_back("skipped " + std::to_string(count) + " '" + keyword + "' statement" +
                                  (count == 1 ? "" : "s") + " (" +
                                  (known != what.end() ? known->second : "not part of the surface loopsub reads") + ")");
        }
    }

    // Faces without texture indices in a file where other faces have them get one texture coordinate (0, 0).
    void fill_missing_uvs() {
        if (!any_uvs_ || faces_without_uvs_ == 0) return;
        const std::int32_t filler = std::int32_t(mesh_.uvs.size() / 2);
        mesh_.uvs.insert(mesh_.uvs.end(), {0.0f, 0.0f});
        for (std::int32_t& uv : mesh_.triangle_uvs)
            if (uv < 0) uv = filler;
        mesh_.notes.push_back(std::to_string(faces_without_uvs_) + " face" + (faces_without_uvs_ == 1 ? "" : "s") +
                              " without texture coordinates got (0, 0), as other faces have them");
    }

    void read_vertex() {
        for (int axis = 0; axis < 3; ++axis) mesh_.positions.push_back(parse_finite(required_token("coordinate"), "coordinate"));
        // Extra values are a homogeneous w or the common "v x y z r g b" colour extension: read to validate them,
        // then dropped.
        for (std::string_view t = token(); !t.empty(); t = token()) parse_float(t, "vertex value");
    }

    void read_uv() {
        float u = parse_finite(required_token("texture coordinate"), "texture coordinate");
        float v = 0.0f;  // the OBJ default for a missing v
        if (std::string_view t = token(); !t.empty()) v = parse_finite(t, "texture coordinate");
        if (std::string_view t = token(); !t.empty()) parse_float(t, "texture coordinate");
        expect_line_end();
        mesh_.uvs.push_back(u);
        mesh_.uvs.push_back(v);
    }

    // An OBJ reference: 1-based, or negative counting back from the last element defined so far.
    std::int32_t resolve(std::int64_t reference, std::size_t defined, const char* what) {
        std::int64_t count = std::int64_t(defined);
        std::int64_t index = reference > 0 ? reference - 1 : count + reference;
        if (reference == 0 || index < 0 || index >= count) {
            fail(std::string(what) + " index " + std::to_string(reference) + " is out of range (" +
                 std::to_string(count) + " defined so far" + (reference == 0 ? "; OBJ indices start at 1)" : ")"));
        }
        return std::int32_t(index);
    }

    void read_face() {
        corner_vertices_.clear();
        corner_uvs_.clear();
        bool face_has_uvs = false;
        for (std::string_view t = token(); !t.empty(); t = token()) {
            std::size_t slash = t.find('/');
            corner_vertices_.push_back(resolve(parse_integer(t.substr(0, slash), "vertex index"),
                                               mesh_.positions.size() / 3, "vertex"));
            bool corner_has_uv = false;
            if (slash != std::string_view::npos) {
                std::string_view rest = t.substr(slash + 1);
                std::string_view uv = rest.substr(0, rest.find('/'));
                // "v//vn" names no texture coordinate.
                if (!uv.empty()) {
                    corner_uvs_.push_back(resolve(parse_integer(uv, "texture index"), mesh_.uvs.size() / 2, "texture"));
                    corner_has_uv = true;
                }
            }
            if (corner_vertices_.size() == 1) {
                face_has_uvs = corner_has_uv;
            } else if (corner_has_uv != face_has_uvs) {
                fail("some corners of this face have a texture index and some do not");
            }
        }
        if (corner_vertices_.size() < 3) fail("a face needs at least 3 corners, this one has " + std::to_string(corner_vertices_.size()));

        if (!face_has_uvs) ++faces_without_uvs_;

        // Loop subdivision is defined on triangles: a polygon is split by ear clipping, as Blender does.
        face_triangles_.clear();
        if (corner_vertices_.size() > 3) {
            ++mesh_.polygons_triangulated;
            triangulate_polygon(mesh_.positions, corner_vertices_, face_triangles_);
        } else {
            face_triangles_ = {0, 1, 2};
        }
        // A polygon may visit a vertex twice (around a hole, along the bridge to it) as long as no triangle does. The
        // core refuses degenerate triangles too, but only the reader can say on which line the face is.
        for (std::size_t t = 0; t < face_triangles_.size(); t += 3) {
            const std::int32_t a = corner_vertices_[face_triangles_[t]], b = corner_vertices_[face_triangles_[t + 1]],
                               c = corner_vertices_[face_triangles_[t + 2]];
            if (a == b || b == c || c == a) {
                fail("the face repeats vertex " + std::to_string((a == b || a == c ? a : b) + 1) +
                     (corner_vertices_.size() == 3 ? std::string(" (a degenerate face; every corner must be a different vertex)")
                                                   : std::string(" and cannot be split into triangles that do not")));
            }
        }
        face_first_triangle_.push_back(mesh_.num_triangles());
        for (std::size_t t = 0; t < face_triangles_.size(); t += 3) {
            std::int32_t vertices[3], uvs[3];
            for (int k = 0; k < 3; ++k) {
                vertices[k] = corner_vertices_[face_triangles_[t + std::size_t(k)]];
                if (face_has_uvs) uvs[k] = corner_uvs_[face_triangles_[t + std::size_t(k)]];
            }
            add_triangle(vertices, face_has_uvs ? uvs : nullptr);
        }
    }

    // OpenSubdiv's tag line: "t NAME I/F/S", then I integers, F floats and S strings.
    void read_tag() {
        std::string name(required_token("tag name"));
        std::string_view counts = required_token("argument counts I/F/S");
        int count[3] = {0, 0, 0};
        {
            const char* p = counts.data();
            const char* end = p + counts.size();
            for (int k = 0; k < 3; ++k) {
                auto result = std::from_chars(p, end, count[k]);
                bool separator_ok = k == 2 ? result.ptr == end : result.ptr < end && *result.ptr == '/';
                if (result.ec != std::errc() || count[k] < 0 || !separator_ok) {
                    fail("tag '" + name + "': expected argument counts like 2/1/0, got '" + std::string(counts) + "'");
                }
                p = result.ptr + 1;
            }
        }
        std::vector<std::int64_t> ints;
        std::vector<float> floats;
        std::vector<std::string> strings;
        for (int k = 0; k < count[0]; ++k) ints.push_back(parse_integer(required_token("tag integer"), "tag integer"));
        for (int k = 0; k < count[1]; ++k) floats.push_back(parse_float(required_token("tag value"), "tag value"));
        for (int k = 0; k < count[2]; ++k) strings.emplace_back(required_token("tag string"));
        expect_line_end();

        auto require_counts = [&](bool ok, const char* expected) {
            if (!ok) fail("tag '" + name + "' expects " + expected + ", got " + std::string(counts));
        };
        // A tag with one value applies it to every element it names; otherwise each element has its own.
        auto value_for = [&](std::size_t element) { return floats.size() == 1 ? floats[0] : floats[element]; };

        if (name == "crease") {
            std::size_t edges = ints.size() / 2;
            require_counts(edges > 0 && ints.size() % 2 == 0 && strings.empty() &&
                               (floats.size() == 1 || floats.size() == edges),
                           "vertex pairs and one sharpness or one per pair, as in 2/1/0");
            for (std::size_t e = 0; e < edges; ++e) {
                crease_indices_.push_back({ints[2 * e], line_});
                crease_indices_.push_back({ints[2 * e + 1], line_});
                mesh_.crease_sharpness.push_back(value_for(e));
            }
        } else if (name == "corner") {
            require_counts(!ints.empty() && strings.empty() && (floats.size() == 1 || floats.size() == ints.size()),
                           "vertices and one sharpness or one per vertex, as in 1/1/0");
            for (std::size_t k = 0; k < ints.size(); ++k) {
                corner_indices_.push_back({ints[k], line_});
                mesh_.corner_sharpness.push_back(value_for(k));
            }
        } else if (name == "cone") {
            require_counts(!ints.empty() && floats.empty() && strings.empty(), "vertices only, as in 1/0/0");
            for (std::int64_t v : ints) cone_indices_.push_back({v, line_});
        } else if (name == "interpolateboundary") {
            require_counts(ints.size() == 1 && floats.empty() && strings.empty(), "one integer, as in 1/0/0");
            // RenderMan's numbering.
            switch (ints[0]) {
                case 0: mesh_.boundary = Boundary::None; break;
                case 1: mesh_.boundary = Boundary::EdgesAndCorners; break;
                case 2: mesh_.boundary = Boundary::EdgesOnly; break;
                default:
                    fail("interpolateboundary " + std::to_string(ints[0]) +
                         " is unknown; use 0 (none: boundary faces become holes), 1 (edges and corners) or 2 (edges only)");
            }
        } else if (name == "facevaryinginterpolateboundary") {
            require_counts(ints.size() == 1 && floats.empty() && strings.empty(), "one integer, as in 1/0/0");
            // OpenSubdiv's Sdc::Options::FVarLinearInterpolation, in its order.
            if (ints[0] < 0 || ints[0] > 5)
                fail("facevaryinginterpolateboundary " + std::to_string(ints[0]) +
                     " is unknown; use 0 (smooth everywhere) to 5 (linear everywhere)");
            mesh_.face_varying = FaceVaryingInterpolation(ints[0]);
        } else if (name == "hole") {
            require_counts(!ints.empty() && floats.empty() && strings.empty(), "faces only, as in 1/0/0");
            for (std::int64_t f : ints) hole_indices_.push_back({f, line_});
        } else if (name == "creasemethod") {
            require_counts(ints.empty() && floats.empty() && strings.size() == 1, "one string, as in 0/0/1");
            // OpenSubdiv's shapes call the uniform method "normal".
            if (strings[0] == "chaikin") {
                mesh_.crease_method = CreaseMethod::Chaikin;
            } else if (strings[0] == "normal" || strings[0] == "uniform") {
                mesh_.crease_method = CreaseMethod::Uniform;
            } else {
                fail("creasemethod '" + strings[0] + "' is unknown; use chaikin, normal or uniform");
            }
        } else {
            // Ignoring a tag would silently change the surface.
            fail("unsupported tag '" + name + "' (loopsub reads crease, corner, cone, hole, interpolateboundary, "
                 "facevaryinginterpolateboundary and creasemethod)");
        }
    }

    std::int32_t checked_vertex(const TaggedIndex& index, const char* tag) const {
        if (index.value < 0 || index.value >= mesh_.num_vertices()) {
            fail_at(index.line, std::string(tag) + " vertex " + std::to_string(index.value) + " is out of range (" +
                                    std::to_string(mesh_.num_vertices()) + " vertices, tags count from 0)");
        }
        return std::int32_t(index.value);
    }

    static std::uint64_t edge_key(std::int32_t a, std::int32_t b) {
        if (a > b) std::swap(a, b);
        return std::uint64_t(std::uint32_t(a)) << 32 | std::uint32_t(b);
    }

    void check_tag_indices() {
        for (const TaggedIndex& index : crease_indices_) mesh_.crease_edges.push_back(checked_vertex(index, "crease"));
        for (const TaggedIndex& index : corner_indices_) mesh_.corner_vertices.push_back(checked_vertex(index, "corner"));
        for (const TaggedIndex& index : cone_indices_) mesh_.cone_vertices.push_back(checked_vertex(index, "cone"));
        // A hole names a face of the file: every triangle it was split into.
        face_first_triangle_.push_back(mesh_.num_triangles());
        const std::int64_t faces = std::int64_t(face_first_triangle_.size()) - 1;
        for (const TaggedIndex& index : hole_indices_) {
            if (index.value < 0 || index.value >= faces)
                fail_at(index.line, "hole face " + std::to_string(index.value) + " is out of range (" + std::to_string(faces) +
                                        " faces, tags count from 0)");
            for (std::int32_t t = face_first_triangle_[std::size_t(index.value)]; t < face_first_triangle_[std::size_t(index.value) + 1]; ++t)
                mesh_.hole_triangles.push_back(t);
        }
        if (mesh_.crease_edges.empty()) return;

        // Only the tagged edges are looked up, so the scan costs one hash probe per triangle edge.
        std::unordered_set<std::uint64_t> missing;
        for (std::size_t k = 0; k < mesh_.crease_edges.size(); k += 2) {
            missing.insert(edge_key(mesh_.crease_edges[k], mesh_.crease_edges[k + 1]));
        }
        const std::vector<std::int32_t>& tri = mesh_.triangles;
        for (std::size_t t = 0; t < tri.size() && !missing.empty(); t += 3) {
            for (int k = 0; k < 3; ++k) missing.erase(edge_key(tri[t + k], tri[t + (k + 1) % 3]));
        }
        for (std::size_t k = 0; k < mesh_.crease_edges.size(); k += 2) {
            std::int32_t a = mesh_.crease_edges[k], b = mesh_.crease_edges[k + 1];
            if (missing.count(edge_key(a, b))) {
                fail_at(crease_indices_[k].line,
                        "crease " + std::to_string(a) + "-" + std::to_string(b) + " is not an edge of the mesh");
            }
        }
    }

    const char* end_ = nullptr;  // of the text being read
    const std::string& name_;
    bool found_nul_ = false;
    int line_ = 0;
    const char* cursor_ = nullptr;
    const char* line_end_ = nullptr;
    ObjMesh mesh_;
    std::vector<std::int32_t> corner_vertices_, corner_uvs_;  // of the face being read; reused across faces
    std::vector<std::size_t> face_triangles_;
    int faces_without_uvs_ = 0;
    bool any_uvs_ = false;  // some face so far had texture indices
    std::map<std::string, int> skipped_;  // statements read past, by keyword
    std::vector<TaggedIndex> crease_indices_, corner_indices_, cone_indices_, hole_indices_;
    std::vector<std::int32_t> face_first_triangle_;  // per face read, its first triangle
};

// ---- Numbers out ----------------------------------------------------------------------------------------------
// std::to_chars(float) writes the shortest form that reads back exactly, but costs about 29 ns a call in libstdc++
// 12: 57 ms of the 114 ms that writing a 655,362-vertex mesh took. put_float writes the same characters (the same
// shortest digits, the same choice between fixed and scientific notation) in about 20 ns: it was compared with
// std::to_chars on every float, and tests/native/test_obj_io_fast.cpp compares a sample of them.

// Digits are made eight at a time in one 64-bit word: the eight digits of a number below 10^8 as byte values, the
// first in the lowest byte (Paul Khuong's method: 10^4, then 10^2, then 10 split off in 32-, 16- and 8-bit lanes
// with multiplications). Adding '0' to each byte and storing the word little-endian writes their text.
std::uint64_t eight_digits(std::uint32_t value) {
    const std::uint64_t merged = std::uint64_t(value / 10000) | (std::uint64_t(value % 10000) << 32);
    const std::uint64_t top = ((merged * 10486u) >> 20) & 0x0000007f0000007fu;  // / 100 in each 32-bit lane
    const std::uint64_t hundreds = ((merged - 100 * top) << 16) + top;
    std::uint64_t tens = ((hundreds * 103u) >> 10) & 0x000f000f000f000fu;  // / 10 in each 16-bit lane
    tens += (hundreds - 10 * tens) << 8;
    return tens;
}

constexpr std::uint64_t kZeroChars = 0x3030303030303030u;

// Writes the eight bytes of a digit word (lowest byte first) at out.
void store_digits(char* out, std::uint64_t word) {
    if constexpr (kLittleEndian) {
        std::memcpy(out, &word, sizeof word);
    } else {
        for (int k = 0; k < 8; ++k) out[k] = char(word >> (8 * k));
    }
}

// Integers: std::to_chars is as fast as anything tried here (their lengths vary little from line to line), and
// faster on 32 bits: face indices (1-based, so up to 2^31) are written as such.
char* put_int(char* out, std::int64_t value) { return std::to_chars(out, out + 24, value).ptr; }
char* put_index(char* out, std::int32_t index) {
    return index >= 0 ? std::to_chars(out, out + 16, std::uint32_t(index) + 1).ptr : put_int(out, std::int64_t(index) + 1);
}

// Schubfach (Raffaello Giulietti, 2020), for binary32 as in Alexander Bolz's Drachennest: the shortest decimal in
// the float's rounding interval, the nearest to it when several are as short (ties to even), as Ryu, the algorithm
// libstdc++ runs inside to_chars, finds it, but in three multiplications and no loop over digits.
// kPow10Single[k + 31] = ceil(10^k * 2^(63 - floor(log2(10^k)))) for -31 <= k <= 45.
constexpr std::uint64_t kPow10Single[77] = {
    0x81CEB32C4B43FCF5, 0xA2425FF75E14FC32, 0xCAD2F7F5359A3B3F, 0xFD87B5F28300CA0E, 0x9E74D1B791E07E49,
    0xC612062576589DDB, 0xF79687AED3EEC552, 0x9ABE14CD44753B53, 0xC16D9A0095928A28, 0xF1C90080BAF72CB2,
    0x971DA05074DA7BEF, 0xBCE5086492111AEB, 0xEC1E4A7DB69561A6, 0x9392EE8E921D5D08, 0xB877AA3236A4B44A,
    0xE69594BEC44DE15C, 0x901D7CF73AB0ACDA, 0xB424DC35095CD810, 0xE12E13424BB40E14, 0x8CBCCC096F5088CC,
    0xAFEBFF0BCB24AAFF, 0xDBE6FECEBDEDD5BF, 0x89705F4136B4A598, 0xABCC77118461CEFD, 0xD6BF94D5E57A42BD,
    0x8637BD05AF6C69B6, 0xA7C5AC471B478424, 0xD1B71758E219652C, 0x83126E978D4FDF3C, 0xA3D70A3D70A3D70B,
    0xCCCCCCCCCCCCCCCD, 0x8000000000000000, 0xA000000000000000, 0xC800000000000000, 0xFA00000000000000,
    0x9C40000000000000, 0xC350000000000000, 0xF424000000000000, 0x9896800000000000, 0xBEBC200000000000,
    0xEE6B280000000000, 0x9502F90000000000, 0xBA43B74000000000, 0xE8D4A51000000000, 0x9184E72A00000000,
    0xB5E620F480000000, 0xE35FA931A0000000, 0x8E1BC9BF04000000, 0xB1A2BC2EC5000000, 0xDE0B6B3A76400000,
    0x8AC7230489E80000, 0xAD78EBC5AC620000, 0xD8D726B7177A8000, 0x878678326EAC9000, 0xA968163F0A57B400,
    0xD3C21BCECCEDA100, 0x84595161401484A0, 0xA56FA5B99019A5C8, 0xCECB8F27F4200F3A, 0x813F3978F8940985,
    0xA18F07D736B90BE6, 0xC9F2C9CD04674EDF, 0xFC6F7C4045812297, 0x9DC5ADA82B70B59E, 0xC5371912364CE306,
    0xF684DF56C3E01BC7, 0x9A130B963A6C115D, 0xC097CE7BC90715B4, 0xF0BDC21ABB48DB21, 0x96769950B50D88F5,
    0xBC143FA4E250EB32, 0xEB194F8E1AE525FE, 0x92EFD1B8D0CF37BF, 0xB7ABC627050305AE, 0xE596B7B0C643C71A,
    0x8F7E32CE7BEA5C70, 0xB35DBF821AE4F38C,
};

struct Decimal {
    std::uint32_t digits;  // no trailing zeros
    int exponent;          // value = digits * 10^exponent
};

// The upper 32 bits of g * cp / 2^32, rounded to odd.
std::uint32_t round_to_odd(std::uint64_t g, std::uint32_t cp) {
#ifdef __SIZEOF_INT128__
    const std::uint64_t high = std::uint64_t((static_cast<unsigned __int128>(g) * cp) >> 32);
#else
    const std::uint64_t low = (g & 0xffffffffu) * cp;
    const std::uint64_t high = (g >> 32) * cp + (low >> 32);
#endif
    return std::uint32_t(high >> 32) | (std::uint32_t(high) > 1);
}

// The shortest decimal of c * 2^q, a float that is not a small whole number; its digits may end in zeros.
Decimal schubfach(std::uint32_t c, int q, bool lower_boundary_closer) {
    const bool even = c % 2 == 0;
    const std::uint32_t cbl = 4 * c - 2 + lower_boundary_closer, cb = 4 * c, cbr = 4 * c + 2;
    // floor(log10(2^q)), or floor(log10(3/4 * 2^q)) when the lower neighbour is nearer; arithmetic shifts.
    const int k = (q * 1262611 - (lower_boundary_closer ? 524031 : 0)) >> 22;
    const int h = q + ((-k * 1741647) >> 19) + 1;  // q + floor(log2(10^-k)) + 1, between 1 and 4
    const std::uint64_t pow10 = kPow10Single[-k + 31];
    const std::uint32_t vbl = round_to_odd(pow10, cbl << h);
    const std::uint32_t vb = round_to_odd(pow10, cb << h);
    const std::uint32_t vbr = round_to_odd(pow10, cbr << h);
    const std::uint32_t lower = vbl + !even, upper = vbr - !even;

    // One digit less when exactly one multiple of 10^(k+1) next to v lies in the interval (at most one can); else s
    // or s + 1 (times 10^k), whichever lies in it, or the nearer if both do (s on a tie if s is even). Both are
    // computed and one selected: which one it is varies at random from float to float.
    const std::uint32_t s = vb / 4, sp = s / 10;
    const bool up_inside = lower <= 40 * sp, wp_inside = 40 * sp + 40 <= upper;
    const bool u_inside = lower <= 4 * s, w_inside = 4 * s + 4 <= upper;
    const std::uint32_t mid = 4 * s + 2;
    const bool nearer_up = (vb > mid) | ((vb == mid) & ((s & 1) != 0));
    const bool up = (u_inside != w_inside) ? w_inside : nearer_up;
    const bool shorter = (s >= 10) & (up_inside != wp_inside);
    const std::uint32_t mask = 0u - std::uint32_t(shorter);  // a select the compiler cannot turn into a branch
    return {((sp + wp_inside) & mask) | ((s + up) & ~mask), k + shorter};
}

// The positive finite float with these IEEE fields.
Decimal shortest_decimal(std::uint32_t ieee_mantissa, std::uint32_t ieee_exponent) {
    Decimal result;
    if (ieee_exponent == 0) {
        result = schubfach(ieee_mantissa, -149, false);
    } else {
        const std::uint32_t c = (1u << 23) | ieee_mantissa;
        const int q = int(ieee_exponent) - 150;
        if (q <= 0 && q > -24 && (c & ((1u << -q) - 1)) == 0) {
            result = {c >> -q, 0};  // a whole number below 2^24 is its own shortest form
        } else {
            result = schubfach(c, q, ieee_mantissa == 0 && ieee_exponent > 1);
        }
    }
    while (result.digits % 10 == 0) {
        result.digits /= 10;
        ++result.exponent;
    }
    return result;
}

constexpr std::size_t kLongestFloat = 16;  // "-1.2345678e-38", "-0.00012345678", "-12345678900000"

// Writes what std::to_chars(out, end, value) writes: the shortest form that reads back exactly, in fixed notation
// unless scientific is shorter (fixed on a tie), a whole number in fixed notation written exactly. Writes up to
// 27 bytes; returns the end of the number.
char* put_float(char* out, float value) {
    std::uint32_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    const std::uint32_t ieee_exponent = (bits >> 23) & 0xff, ieee_mantissa = bits & 0x7fffff;
    if (ieee_exponent == 0xff) return std::to_chars(out, out + kLongestFloat, value).ptr;  // inf, nan
    *out = '-';
    out += bits >> 31;
    if (ieee_exponent == 0 && ieee_mantissa == 0) {
        *out = '0';
        return out + 1;
    }
    const Decimal decimal = shortest_decimal(ieee_mantissa, ieee_exponent);
    // The digits (at most 9) as 12 characters with leading zeros, then zeros, so that 16 bytes can be copied from
    // any of the first 16 positions.
    char padded[32] = {};
    const std::uint32_t first = decimal.digits / 100000000;
    const std::uint64_t rest = eight_digits(decimal.digits % 100000000);
    std::memcpy(padded, "000", 3);
    padded[3] = char('0' + first);
    store_digits(padded + 4, rest + kZeroChars);
    const int length = first ? 9 : 8 - lowest_nonzero_byte(rest | (std::uint64_t(1) << 56));
    const char* const digits = padded + 12 - length;
    const int exponent = decimal.exponent;
    // libstdc++'s bounds for the plain format: fixed notation is not longer than scientific.
    const int lower_bound = length == 1 ? -3 : -(length + 3);
    const int upper_bound = length == 1 ? 4 : 5;
    if (exponent < lower_bound || exponent > upper_bound) {
        // d.ddde+XX, or de+XX; a float's exponent has two digits.
        out[0] = digits[0];
        out[1] = '.';
        std::memcpy(out + 2, digits + 1, 8);
        out += length == 1 ? 1 : length + 1;
        const int scientific_exponent = std::abs(exponent + length - 1);
        out[0] = 'e';
        out[1] = exponent + length - 1 < 0 ? '-' : '+';
        out[2] = char('0' + scientific_exponent / 10);
        out[3] = char('0' + scientific_exponent % 10);
        return out + 4;
    }
    if (exponent >= 0) {
        // A whole number, below 10^14: printed exactly ("as if by printf"), not as the shortest digits and zeros.
        return std::to_chars(out, out + 24, std::uint64_t(std::fabs(value))).ptr;
    }
    const int fraction = -exponent;  // at most length + 3 <= 12
    if (length <= fraction) {
        // 0.000ddd: the zeros after the point are the padding's.
        std::memcpy(out, "0.", 2);
        std::memcpy(out + 2, padded + 12 - fraction, 16);
        return out + 2 + fraction;
    }
    const int whole = length - fraction;
    std::memcpy(out, digits, 16);
    out[whole] = '.';
    std::memcpy(out + whole + 1, padded + 12 - fraction, 16);
    return out + length + 1;
}

template <std::size_t N>
char* put_text(char* out, const char (&text)[N]) {
    std::memcpy(out, text, N - 1);
    return out + N - 1;
}

// N floats separated by blanks, and the line's end.
template <int N>
char* put_floats(char* out, const float* values) {
    for (int k = 0; k < N; ++k) {
        if (k > 0) *out++ = ' ';
        out = put_float(out, values[k]);
    }
    *out++ = '\n';
    return out;
}

// ---- The file -------------------------------------------------------------------------------------------------

struct FileCloser {
    void operator()(std::FILE* file) const { std::fclose(file); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

// Lines are formatted straight into a block, one fwrite per block.
class Writer {
public:
    // Longer than any line written (6 indices of 11 characters, 3 floats of 16, the tags' 64-bit integers) plus the
    // bytes that put_float writes past a number.
    static constexpr std::size_t kLongestLine = 128;

    Writer(std::FILE* file, const std::string& path) : file_(file), path_(path), block_(new char[kBlock]) {}

    // Where the next `count` lines go (at most kBlock / kLongestLine); at least count * kLongestLine bytes are free
    // there. `done` takes the lines' end.
    char* line(std::size_t count = 1) {
        if (used_ + count * kLongestLine > kBlock) flush();
        return block_.get() + used_;
    }
    void done(char* end) { used_ = std::size_t(end - block_.get()); }

    // Text formatted elsewhere, after the lines before it.
    void write(const char* text, std::size_t size) {
        flush();
        if (size > 0 && std::fwrite(text, 1, size, file_) != size) throw std::runtime_error("cannot write " + path_);
    }

    void finish() {
        flush();
        if (std::fflush(file_) != 0 || std::ferror(file_)) throw std::runtime_error("cannot write " + path_);
    }

private:
    static constexpr std::size_t kBlock = 1 << 20;

    void flush() {
        if (used_ > 0 && std::fwrite(block_.get(), 1, used_, file_) != used_) throw std::runtime_error("cannot write " + path_);
        used_ = 0;
    }

    std::FILE* file_;
    const std::string& path_;
    std::unique_ptr<char[]> block_;
    std::size_t used_ = 0;
};

// The v, vt, vn and f lines, numbered from 0 in the order they are written: first to last - 1 formatted at out.
char* format_lines(char* out, const ObjMesh& mesh, std::size_t first, std::size_t last) {
    std::size_t start = 0;  // of the current kind of line
    // The lines of this kind in [first, last), each by line(out, k) with k counted within the kind.
    auto lines = [&](std::size_t count, const auto& line) {
        for (std::size_t k = std::max(first, start); k < std::min(last, start + count); ++k) out = line(out, k - start);
        start += count;
    };
    lines(mesh.positions.size() / 3, [&](char* p, std::size_t k) { return put_floats<3>(put_text(p, "v "), &mesh.positions[3 * k]); });
    lines(mesh.uvs.size() / 2, [&](char* p, std::size_t k) { return put_floats<2>(put_text(p, "vt "), &mesh.uvs[2 * k]); });
    lines(mesh.normals.size() / 3, [&](char* p, std::size_t k) { return put_floats<3>(put_text(p, "vn "), &mesh.normals[3 * k]); });
    const bool with_uvs = !mesh.triangle_uvs.empty(), with_normals = !mesh.triangle_normals.empty();
    lines(mesh.triangles.size() / 3, [&](char* p, std::size_t k) {
        p = put_text(p, "f");
        for (std::size_t c = 3 * k; c < 3 * k + 3; ++c) {
            *p++ = ' ';
            p = put_index(p, mesh.triangles[c]);
            if (with_uvs || with_normals) *p++ = '/';
            if (with_uvs) p = put_index(p, mesh.triangle_uvs[c]);
            if (with_normals) {
                *p++ = '/';
                p = put_index(p, mesh.triangle_normals[c]);
            }
        }
        *p++ = '\n';
        return p;
    });
    return out;
}

// Runs before() on the calling thread, then work(part) for parts 0 to parts - 1, each taken by the next of the
// `threads` threads (the caller and threads - 1 others) to be free, and returns when all are done. A thread the
// system refuses to start costs parallelism only. work must not throw; if before() throws, no part is started after.
template <typename Before, typename Work>
void run_parts(int threads, std::size_t parts, const Before& before, const Work& work) {
    std::atomic<std::size_t> next{0};
    auto take_parts = [&] {
        for (std::size_t part; (part = next++) < parts;) work(part);
    };
    std::vector<std::thread> others;
    for (int t = 1; t < threads; ++t) {
        try {
            others.emplace_back(take_parts);
        } catch (const std::system_error&) {
            break;
        }
    }
    try {
        before();
    } catch (...) {
        next = parts;
        for (std::thread& thread : others) thread.join();
        throw;
    }
    take_parts();
    for (std::thread& thread : others) thread.join();
}

// The v, vt, vn and f lines. One thread formats them into the writer's block, which is written whenever full. More
// format chunks of consecutive lines in rounds, eight chunks per thread: the caller first writes the previous
// round's chunks, in order, while the other threads start on this round's, then helps them. Two rounds of chunks
// are in memory at a time, each chunk a 1 MiB buffer holding about 0.25 MB of text.
void write_lines(Writer& out, const ObjMesh& mesh, int threads) {
    constexpr std::size_t kChunkLines = 1 << 13;  // times kLongestLine: 1 MiB
    struct Chunk {
        std::unique_ptr<char[]> text;  // room for kChunkLines lines, made by the caller when first needed
        std::size_t size = 0;
    };
    const std::size_t lines = mesh.positions.size() / 3 + mesh.uvs.size() / 2 + mesh.normals.size() / 3 + mesh.triangles.size() / 3;
    const std::size_t chunks = (lines + kChunkLines - 1) / kChunkLines;
    threads = int(std::clamp<std::size_t>(chunks, 1, std::size_t(std::max(threads, 1))));  // a small file: the caller alone
    if (threads == 1) {
        // A thousand lines at a time: the block is written in pieces of about 1 MiB (smaller pieces cost more in
        // the kernel), each while it is still in the cache.
        constexpr std::size_t kLinesAtATime = 1024;
        for (std::size_t first = 0; first < lines; first += kLinesAtATime)
            out.done(format_lines(out.line(kLinesAtATime), mesh, first, std::min(lines, first + kLinesAtATime)));
        return;
    }
    // Eight chunks per thread and round, taken as threads come free: the threads finish a round at about the same
    // time (the last chunk taken is an eighth of a thread's share).
    const std::size_t per_round = 8 * std::size_t(threads);
    const std::size_t num_rounds = (chunks + per_round - 1) / per_round;
    std::vector<Chunk> rounds[2];
    auto write_round = [&](const std::vector<Chunk>& round) {
        for (const Chunk& chunk : round) out.write(chunk.text.get(), chunk.size);
    };
    for (std::size_t round = 0; round < num_rounds; ++round) {
        const std::size_t first_chunk = round * per_round;
        std::vector<Chunk>& now = rounds[round % 2];
        now.resize(std::min(per_round, chunks - first_chunk));  // the last round may have fewer
        for (Chunk& chunk : now)
            if (!chunk.text) chunk.text.reset(new char[kChunkLines * Writer::kLongestLine]);
        run_parts(
            threads, now.size(),
            [&] {
                if (round > 0) write_round(rounds[(round - 1) % 2]);
            },
            [&](std::size_t part) {
                const std::size_t first = (first_chunk + part) * kChunkLines, last = std::min(lines, first + kChunkLines);
                now[part].size = std::size_t(format_lines(now[part].text.get(), mesh, first, last) - now[part].text.get());
            });
    }
    if (num_rounds > 0) write_round(rounds[(num_rounds - 1) % 2]);
}

}  // namespace

// A file is read in blocks of this size into one buffer (larger when a line is longer), and its whole lines are
// handed to the reader block by block: reading it into a buffer of its own size cost as much again in first
// touches of fresh pages (44 ms against 12.5 ms for 52 MB). Tests set a small block to cross its edges often.
#ifndef LOOPSUB_OBJ_READ_BLOCK
#define LOOPSUB_OBJ_READ_BLOCK (1 << 20)
#endif
constexpr std::size_t kReadBlock = LOOPSUB_OBJ_READ_BLOCK;

ObjMesh parse_obj(const std::string& text, const std::string& name) {
    Reader reader(name);
    reader.reserve_for(std::string_view(text).substr(0, kReadBlock), text.size());
    reader.read_lines(text);
    return reader.finish();
}

ObjMesh read_obj(const std::string& path) {
    File file(std::fopen(path.c_str(), "rb"));
    if (!file) throw InputError(path + ": cannot open for reading");
    std::size_t size = 0;  // only to reserve the arrays; a pipe has none
    if (std::fseek(file.get(), 0, SEEK_END) == 0) {
        const long end = std::ftell(file.get());
        if (end > 0) size = std::size_t(end);
        std::rewind(file.get());
    }
    Reader reader(path);
    std::vector<char> buffer(kReadBlock);
    std::size_t filled = 0;  // bytes in the buffer
    std::size_t whole = 0;   // of which whole lines, handed to the reader
    int lines_before = 0;    // lines read before the buffer's
    try {
        for (bool at_end = false, first = true; !at_end; first = false) {
            // What follows the last whole line starts the next block.
            std::memmove(buffer.data(), buffer.data() + whole, filled - whole);
            filled -= whole;
            if (filled == buffer.size()) buffer.resize(2 * buffer.size());
            const std::size_t wanted = buffer.size() - filled;
            const std::size_t got = std::fread(buffer.data() + filled, 1, wanted, file.get());
            if (std::ferror(file.get())) throw InputError(path + ": read error");
            at_end = got < wanted;
            filled += got;
            whole = filled;
            if (!at_end) {
                while (whole > 0 && buffer[whole - 1] != '\n') --whole;
            }
            const std::string_view lines(buffer.data(), whole);
            if (first) reader.reserve_for(lines, size);
            lines_before = reader.lines_read();
            reader.read_lines(lines);
        }
    } catch (const InputError&) {
        if (std::ferror(file.get())) throw;
        // Errors come in the order of a file read whole, then checked for NUL bytes, then read line by line: a read
        // error, then a NUL byte anywhere, then the first error in the lines. The rest of the file is looked through.
        std::size_t newlines = std::size_t(lines_before) + std::size_t(std::count(buffer.data(), buffer.data() + whole, '\n'));
        std::size_t nul_line = 0;
        for (std::size_t from = whole;; from = 0) {
            if (!reader.found_nul() && nul_line == 0) {
                const char* const start = buffer.data() + from;
                const char* const stop = buffer.data() + filled;
                if (const void* nul = std::memchr(start, '\0', std::size_t(stop - start))) {
                    nul_line = 1 + newlines + std::size_t(std::count(start, static_cast<const char*>(nul), '\n'));
                } else {
                    newlines += std::size_t(std::count(start, stop, '\n'));
                }
            }
            if (filled < buffer.size()) break;  // the last read was short: the end of the file
            filled = std::fread(buffer.data(), 1, buffer.size(), file.get());
        }
        if (std::ferror(file.get())) throw InputError(path + ": read error");
        if (nul_line > 0) throw InputError(path + ":" + std::to_string(nul_line) + ": " + kNotPlainText);
        throw;
    }
    return reader.finish();
}

void write_obj(const std::string& path, const ObjMesh& mesh, int threads) {
    File file(std::fopen(path.c_str(), "wb"));
    if (!file) throw std::runtime_error(path + ": cannot open for writing");
    Writer out(file.get(), path);

    write_lines(out, mesh, threads);
    for (std::size_t e = 0; e < mesh.crease_sharpness.size(); ++e) {
        char* p = put_text(out.line(), "t crease 2/1/0 ");
        p = put_int(p, mesh.crease_edges[2 * e]);
        *p++ = ' ';
        p = put_int(p, mesh.crease_edges[2 * e + 1]);
        *p++ = ' ';
        p = put_float(p, mesh.crease_sharpness[e]);
        *p++ = '\n';
        out.done(p);
    }
    for (std::size_t k = 0; k < mesh.corner_sharpness.size(); ++k) {
        char* p = put_text(out.line(), "t corner 1/1/0 ");
        p = put_int(p, mesh.corner_vertices[k]);
        *p++ = ' ';
        p = put_float(p, mesh.corner_sharpness[k]);
        *p++ = '\n';
        out.done(p);
    }
    for (std::int32_t v : mesh.cone_vertices) {
        char* p = put_text(out.line(), "t cone 1/0/0 ");
        p = put_int(p, v);
        *p++ = '\n';
        out.done(p);
    }
    if (mesh.boundary) {
        // RenderMan's numbering.
        out.done(*mesh.boundary == Boundary::EdgesAndCorners ? put_text(out.line(), "t interpolateboundary 1/0/0 1\n")
                 : *mesh.boundary == Boundary::None          ? put_text(out.line(), "t interpolateboundary 1/0/0 0\n")
                                                             : put_text(out.line(), "t interpolateboundary 1/0/0 2\n"));
    }
    if (mesh.face_varying) {
        char* p = put_text(out.line(), "t facevaryinginterpolateboundary 1/0/0 ");
        p = put_int(p, int(*mesh.face_varying));
        *p++ = '\n';
        out.done(p);
    }
    if (mesh.crease_method) {
        out.done(*mesh.crease_method == CreaseMethod::Chaikin ? put_text(out.line(), "t creasemethod 0/0/1 chaikin\n")
                                                              : put_text(out.line(), "t creasemethod 0/0/1 normal\n"));
    }
    out.finish();
    if (std::fclose(file.release()) != 0) throw std::runtime_error("cannot write " + path);
}

}  // namespace loopsub::obj
