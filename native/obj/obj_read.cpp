// Reading Wavefront OBJ with OpenSubdiv's tags. The reader scans the text in place, with one pass over the common
// "v x y z" and "f a b c" lines and the general per-token reader for everything else.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <string_view>
#include <system_error>

#include "obj_file.h"
#include "obj_io.h"
#include "triangulate.h"

namespace loopsub::obj {

namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// Vertex indices in tags are checked once the whole file is read (a tag may precede the vertices it names), so
// each tagged index remembers the line it came from.
struct TaggedIndex {
    std::int64_t value;
    int line;
};

// A tag's vertex the mesh has not: "crease vertex 9 is out of range (4 vertices, tags count from 0)".
std::string vertex_out_of_range(const char* tag, std::int64_t vertex, int num_vertices) {
    return std::string(tag) + " vertex " + std::to_string(vertex) + " is out of range (" +
           std::to_string(num_vertices) + " vertices, tags count from 0)";
}

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
        if (error == std::errc::result_out_of_range)
            fail(std::string(what) + " '" + std::string(t) + "' is out of range");
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
    // nothing and return nullptr, and read_line() reads the line again with every rule and error message. Both read
    // numbers with std::from_chars, so they read a line alike.
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
            const auto [next, error] = std::from_chars(p, end_, value);
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
            std::from_chars_result read = std::from_chars(p, end_, reference);
            if (read.ec != std::errc()) return nullptr;
            const std::int32_t vertex = resolve_plain(reference, mesh_.positions.size() / 3);
            if (vertex < 0) return nullptr;
            p = read.ptr;
            bool corner_uv = false;
            if (p < end_ && *p == '/') {
                ++p;
                if (!ends_token(p) && *p != '/') {
                    read = std::from_chars(p, end_, reference);
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
        if (corners != 3) return nullptr;
        if (!with_uvs) ++faces_without_uvs_;
        start_face();
        add_triangle(vertices, with_uvs ? uvs : nullptr);
        return p == end_ ? p : p + 1;
    }

    // The face read from the current line starts at the next triangle.
    void start_face() {
        mesh_.face_first_triangle.push_back(mesh_.num_triangles());
        mesh_.face_lines.push_back(line_);
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
            mesh_.notes.push_back(
                "skipped " + std::to_string(count) + " '" + keyword + "' statement" + (count == 1 ? "" : "s") + " (" +
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
        for (int axis = 0; axis < 3; ++axis)
            mesh_.positions.push_back(parse_finite(required_token("coordinate"), "coordinate"));
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
            corner_vertices_.push_back(
                resolve(parse_integer(t.substr(0, slash), "vertex index"), mesh_.positions.size() / 3, "vertex"));
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
        if (corner_vertices_.size() < 3)
            fail("a face needs at least 3 corners, this one has " + std::to_string(corner_vertices_.size()));

        if (!face_has_uvs) ++faces_without_uvs_;

        // Loop subdivision is defined on triangles: a polygon is split by ear clipping, as Blender does.
        face_triangles_.clear();
        if (corner_vertices_.size() > 3) {
            ++mesh_.polygons_triangulated;
            triangulate_polygon(mesh_.positions, corner_vertices_, face_triangles_);
        } else {
            face_triangles_ = {0, 1, 2};
        }
        // A polygon may visit a vertex twice (around a hole, along the bridge to it) as long as no triangle does: the
        // core refuses a degenerate triangle, and locate() says on which line its face is.
        start_face();
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
    struct Tag {
        std::string name;
        std::string_view counts;  // as written
        std::vector<std::int64_t> ints;
        std::vector<float> floats;
        std::vector<std::string> strings;
    };

    void read_tag() {
        const Tag tag = read_tag_arguments();
        if (tag.name == "crease") return read_crease(tag);
        if (tag.name == "corner") return read_corner(tag);
        if (tag.name == "cone") return read_cone(tag);
        if (tag.name == "interpolateboundary") return read_interpolate_boundary(tag);
        if (tag.name == "facevaryinginterpolateboundary") return read_face_varying_interpolation(tag);
        if (tag.name == "hole") return read_hole(tag);
        if (tag.name == "creasemethod") return read_crease_method(tag);
        // Ignoring a tag would silently change the surface.
        fail("unsupported tag '" + tag.name +
             "' (loopsub reads crease, corner, cone, hole, interpolateboundary, "
             "facevaryinginterpolateboundary and creasemethod)");
    }

    // The name, the counts I/F/S and as many integers, floats and strings, to the end of the line.
    Tag read_tag_arguments() {
        Tag tag;
        tag.name = std::string(required_token("tag name"));
        tag.counts = required_token("argument counts I/F/S");
        int count[3] = {0, 0, 0};
        const char* p = tag.counts.data();
        const char* end = p + tag.counts.size();
        for (int k = 0; k < 3; ++k) {
            auto result = std::from_chars(p, end, count[k]);
            bool separator_ok = k == 2 ? result.ptr == end : result.ptr < end && *result.ptr == '/';
            if (result.ec != std::errc() || count[k] < 0 || !separator_ok) {
                fail("tag '" + tag.name + "': expected argument counts like 2/1/0, got '" + std::string(tag.counts) +
                     "'");
            }
            p = result.ptr + 1;
        }
        for (int k = 0; k < count[0]; ++k)
            tag.ints.push_back(parse_integer(required_token("tag integer"), "tag integer"));
        for (int k = 0; k < count[1]; ++k) tag.floats.push_back(parse_float(required_token("tag value"), "tag value"));
        for (int k = 0; k < count[2]; ++k) tag.strings.emplace_back(required_token("tag string"));
        expect_line_end();
        return tag;
    }

    void require_counts(const Tag& tag, bool ok, const char* expected) const {
        if (!ok) fail("tag '" + tag.name + "' expects " + expected + ", got " + std::string(tag.counts));
    }

    // A tag with one value applies it to every element it names; otherwise each element has its own. The core checks
    // each sharpness, and locate() names the tag's line.
    static float value_for(const Tag& tag, std::size_t element) {
        return tag.floats.size() == 1 ? tag.floats[0] : tag.floats[element];
    }

    void read_crease(const Tag& tag) {
        const std::size_t edges = tag.ints.size() / 2;
        require_counts(tag,
                       edges > 0 && tag.ints.size() % 2 == 0 && tag.strings.empty() &&
                           (tag.floats.size() == 1 || tag.floats.size() == edges),
                       "vertex pairs and one sharpness or one per pair, as in 2/1/0");
        for (std::size_t e = 0; e < edges; ++e) {
            crease_indices_.push_back({tag.ints[2 * e], line_});
            crease_indices_.push_back({tag.ints[2 * e + 1], line_});
            mesh_.crease_sharpness.push_back(value_for(tag, e));
            mesh_.crease_lines.push_back(line_);
        }
    }

    void read_corner(const Tag& tag) {
        require_counts(tag,
                       !tag.ints.empty() && tag.strings.empty() &&
                           (tag.floats.size() == 1 || tag.floats.size() == tag.ints.size()),
                       "vertices and one sharpness or one per vertex, as in 1/1/0");
        for (std::size_t k = 0; k < tag.ints.size(); ++k) {
            corner_indices_.push_back({tag.ints[k], line_});
            mesh_.corner_sharpness.push_back(value_for(tag, k));
            mesh_.corner_lines.push_back(line_);
        }
    }

    void read_cone(const Tag& tag) {
        require_counts(tag, !tag.ints.empty() && tag.floats.empty() && tag.strings.empty(),
                       "vertices only, as in 1/0/0");
        for (std::int64_t v : tag.ints) {
            cone_indices_.push_back({v, line_});
            mesh_.cone_lines.push_back(line_);
        }
    }

    void read_interpolate_boundary(const Tag& tag) {
        require_counts(tag, tag.ints.size() == 1 && tag.floats.empty() && tag.strings.empty(),
                       "one integer, as in 1/0/0");
        // RenderMan's numbering.
        switch (tag.ints[0]) {
            case 0: mesh_.boundary = Boundary::None; break;
            case 1: mesh_.boundary = Boundary::EdgesAndCorners; break;
            case 2: mesh_.boundary = Boundary::EdgesOnly; break;
            default:
                fail("interpolateboundary " + std::to_string(tag.ints[0]) +
                     " is unknown; use 0 (none: boundary faces become holes), 1 (edges and corners) or 2 (edges "
                     "only)");
        }
    }

    void read_face_varying_interpolation(const Tag& tag) {
        require_counts(tag, tag.ints.size() == 1 && tag.floats.empty() && tag.strings.empty(),
                       "one integer, as in 1/0/0");
        // OpenSubdiv's Sdc::Options::FVarLinearInterpolation, in its order.
        if (tag.ints[0] < 0 || tag.ints[0] > 5)
            fail("facevaryinginterpolateboundary " + std::to_string(tag.ints[0]) +
                 " is unknown; use 0 (smooth everywhere) to 5 (linear everywhere)");
        mesh_.face_varying = FaceVaryingInterpolation(tag.ints[0]);
    }

    void read_hole(const Tag& tag) {
        require_counts(tag, !tag.ints.empty() && tag.floats.empty() && tag.strings.empty(), "faces only, as in 1/0/0");
        for (std::int64_t f : tag.ints) hole_indices_.push_back({f, line_});
    }

    void read_crease_method(const Tag& tag) {
        require_counts(tag, tag.ints.empty() && tag.floats.empty() && tag.strings.size() == 1,
                       "one string, as in 0/0/1");
        // The option's names, and "normal", what OpenSubdiv's shapes call the uniform method.
        CreaseMethod method = CreaseMethod::Uniform;
        if (tag.strings[0] != "normal" && !parse_option(tag.strings[0], method))
            fail("creasemethod '" + tag.strings[0] + "' is unknown; use chaikin, normal or uniform");
        mesh_.crease_method = method;
    }

    // A tag's vertex as the core reads it. The core checks that it is one of the mesh's (locate() names the line);
    // here only what 32 bits cannot hold is refused, in the same words.
    std::int32_t tagged_vertex(const TaggedIndex& index, const char* tag) const {
        if (index.value < std::numeric_limits<std::int32_t>::min() ||
            index.value > std::numeric_limits<std::int32_t>::max())
            fail_at(index.line, vertex_out_of_range(tag, index.value, mesh_.num_vertices()));
        return std::int32_t(index.value);
    }

    void check_tag_indices() {
        for (const TaggedIndex& index : crease_indices_) mesh_.crease_edges.push_back(tagged_vertex(index, "crease"));
        for (const TaggedIndex& index : corner_indices_)
            mesh_.corner_vertices.push_back(tagged_vertex(index, "corner"));
        for (const TaggedIndex& index : cone_indices_) mesh_.cone_vertices.push_back(tagged_vertex(index, "cone"));
        // A hole names a face of the file: every triangle it was split into.
        mesh_.face_first_triangle.push_back(mesh_.num_triangles());
        const std::int64_t faces = std::int64_t(mesh_.face_first_triangle.size()) - 1;
        for (const TaggedIndex& index : hole_indices_) {
            if (index.value < 0 || index.value >= faces)
                fail_at(index.line, "hole face " + std::to_string(index.value) + " is out of range (" +
                                        std::to_string(faces) + " faces, tags count from 0)");
            for (std::int32_t t = mesh_.face_first_triangle[std::size_t(index.value)];
                 t < mesh_.face_first_triangle[std::size_t(index.value) + 1]; ++t)
                mesh_.hole_triangles.push_back(t);
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
    bool any_uvs_ = false;                // some face so far had texture indices
    std::map<std::string, int> skipped_;  // statements read past, by keyword
    std::vector<TaggedIndex> crease_indices_, corner_indices_, cone_indices_, hole_indices_;
};

}  // namespace

std::string locate(const ObjMesh& mesh, const std::string& name, const InputProblem& problem) {
    using Kind = InputProblem::Kind;
    using Element = InputProblem::Element;
    auto at = [&name](int line, const std::string& message) {
        return name + ":" + std::to_string(line) + ": " + message;
    };
    const std::size_t k = std::size_t(problem.index);
    auto tag_line = [&](const std::vector<int>& lines) { return k < lines.size() ? lines[k] : 0; };
    const char* tag = problem.element == Element::CreaseEdge     ? "crease"
                      : problem.element == Element::CornerVertex ? "corner"
                                                                 : "cone";
    const std::vector<int>& lines = problem.element == Element::CreaseEdge     ? mesh.crease_lines
                                    : problem.element == Element::CornerVertex ? mesh.corner_lines
                                                                               : mesh.cone_lines;
    const bool tagged = problem.element == Element::CreaseEdge || problem.element == Element::CornerVertex ||
                        problem.element == Element::Cone;
    if (tagged && tag_line(lines) > 0) {
        const int line = tag_line(lines);
        if (problem.kind == Kind::VertexOutOfRange)
            return at(line, vertex_out_of_range(tag, problem.refers_to, problem.other));
        if (problem.kind == Kind::NotAnEdge)
            return at(line, "crease " + std::to_string(problem.refers_to) + "-" + std::to_string(problem.other) +
                                " is not an edge of the mesh");
        if (problem.kind == Kind::BadSharpness)
            return at(line, "tag '" + std::string(tag) + "' gives sharpness " + std::to_string(problem.value) +
                                "; a sharpness is a finite number >= 0");
        return at(line, problem.message());
    }
    if (problem.element == Element::Triangle && problem.layer < 0 && !mesh.face_lines.empty()) {
        // The face the triangle was cut from: the last whose first triangle is not after it.
        const auto& first = mesh.face_first_triangle;
        const std::size_t face = std::size_t(
            std::upper_bound(first.begin(), first.begin() + std::ptrdiff_t(mesh.face_lines.size()), problem.index) -
            first.begin() - 1);
        const bool polygon = first[face + 1] - first[face] > 1;
        if (problem.kind == Kind::DegenerateTriangle)
            return at(mesh.face_lines[face], "the face repeats vertex " + std::to_string(problem.refers_to + 1) +
                                                 (polygon ? " and cannot be split into triangles that do not"
                                                          : " (a degenerate face; every corner must be a different "
                                                            "vertex)"));
        return at(mesh.face_lines[face],
                  "the face (triangle " + std::to_string(problem.index) + " of the mesh): " + problem.message());
    }
    return problem.message();
}

// A file is read in blocks of this size into one buffer (larger when a line is longer), and its whole lines are
// handed to the reader block by block: reading it into a buffer of its own size cost more in first touches of fresh
// pages than the copy itself (docs/benchmark.md, "CLI I/O").
constexpr std::size_t kReadBlock = 1 << 20;

ObjMesh parse_obj(const std::string& text, const std::string& name) {
    Reader reader(name);
    reader.reserve_for(std::string_view(text).substr(0, kReadBlock), text.size());
    reader.read_lines(text);
    return reader.finish();
}

ObjMesh read_obj(const std::string& path) {
    std::error_code ignored;
    if (std::filesystem::is_directory(path, ignored)) throw InputError(path + ": is a directory, not an OBJ file");
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
        std::size_t newlines =
            std::size_t(lines_before) + std::size_t(std::count(buffer.data(), buffer.data() + whole, '\n'));
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

}  // namespace loopsub::obj
