// Wavefront OBJ with OpenSubdiv's tags. The reader scans the text in place (from_chars, no stream per token) so
// that a million-triangle file loads in a fraction of a second; the writer formats into a buffer with to_chars,
// whose shortest round-trip form makes write -> read exact.
#include "obj_io.h"

#include <map>

#include "triangulate.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <string_view>
#include <unordered_set>

namespace loopsub::obj {

namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r'; }

// Vertex indices in tags are checked once the whole file is read (a tag may precede the vertices it names), so
// each tagged index remembers the line it came from.
struct TaggedIndex {
    std::int64_t value;
    int line;
};

class Reader {
public:
    Reader(std::string_view text, const std::string& name) : text_(text), name_(name) {}

    ObjMesh read() {
        if (const std::size_t nul = text_.find('\0'); nul != std::string_view::npos) {
            line_ = 1 + int(std::count(text_.begin(), text_.begin() + std::ptrdiff_t(nul), '\n'));
            fail("the file is not plain text (it holds a NUL byte; save UTF-16 files as UTF-8)");
        }
        std::size_t pos = 0;
        while (pos < text_.size()) {
            std::size_t end = text_.find('\n', pos);
            if (end == std::string_view::npos) end = text_.size();
            ++line_;
            cursor_ = text_.data() + pos;
            line_end_ = text_.data() + end;
            read_line();
            pos = end + 1;
        }
        check_tag_indices();
        fill_missing_uvs();
        note_skipped();
        return std::move(mesh_);
    }

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
        const bool any_uv = std::any_of(mesh_.triangle_uvs.begin(), mesh_.triangle_uvs.end(), [](std::int32_t uv) { return uv >= 0; });
        if (!any_uv) {
            mesh_.triangle_uvs.clear();
            return;
        }
        if (faces_without_uvs_ == 0) return;
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
        for (std::size_t corner : face_triangles_) {
            mesh_.triangles.push_back(corner_vertices_[corner]);
            mesh_.triangle_uvs.push_back(face_has_uvs ? corner_uvs_[corner] : -1);  // -1: filled or dropped at the end
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
                case 1: mesh_.boundary = Boundary::EdgesAndCorners; break;
                case 2: mesh_.boundary = Boundary::EdgesOnly; break;
                case 0:
                    fail("interpolateboundary 0 (boundary faces not interpolated) is not supported; use 1 (edges and "
                         "corners) or 2 (edges only)");
                default: fail("interpolateboundary " + std::to_string(ints[0]) + " is unknown; use 1 (edges and corners) or 2 (edges only)");
            }
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
            // Ignoring a tag such as "hole" would silently change the surface.
            fail("unsupported tag '" + name + "' (loopsub reads crease, corner, cone, interpolateboundary and creasemethod)");
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

    std::string_view text_;
    const std::string& name_;
    int line_ = 0;
    const char* cursor_ = nullptr;
    const char* line_end_ = nullptr;
    ObjMesh mesh_;
    std::vector<std::int32_t> corner_vertices_, corner_uvs_;  // of the face being read; reused across faces
    std::vector<std::size_t> face_triangles_;
    int faces_without_uvs_ = 0;
    std::map<std::string, int> skipped_;  // statements read past, by keyword
    std::vector<TaggedIndex> crease_indices_, corner_indices_, cone_indices_;
};

struct FileCloser {
    void operator()(std::FILE* file) const { std::fclose(file); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

// Buffered formatting into a file: text and to_chars straight into a block, one fwrite per block. (Appending to a
// std::string cost a third of the CLI's time on a million-triangle output.)
class Writer {
public:
    Writer(std::FILE* file, const std::string& path) : file_(file), path_(path), block_(new char[kBlock]) {}

    Writer& text(std::string_view s) {
        make_room(s.size());
        std::memcpy(block_.get() + used_, s.data(), s.size());
        used_ += s.size();
        return *this;
    }
    Writer& number(float value) { return format(value); }
    Writer& number(std::int64_t value) { return format(value); }

    void finish() {
        flush();
        if (std::fflush(file_) != 0 || std::ferror(file_)) throw std::runtime_error("cannot write " + path_);
    }

private:
    static constexpr std::size_t kBlock = 1 << 20;
    static constexpr std::size_t kLongestNumber = 64;

    template <typename T>
    Writer& format(T value) {
        make_room(kLongestNumber);
        used_ = std::size_t(std::to_chars(block_.get() + used_, block_.get() + kBlock, value).ptr - block_.get());
        return *this;
    }

    // Every piece written is a short keyword or one number, far below the block size.
    void make_room(std::size_t bytes) {
        if (used_ + bytes > kBlock) flush();
    }

    void flush() {
        if (used_ > 0 && std::fwrite(block_.get(), 1, used_, file_) != used_) throw std::runtime_error("cannot write " + path_);
        used_ = 0;
    }

    std::FILE* file_;
    const std::string& path_;
    std::unique_ptr<char[]> block_;
    std::size_t used_ = 0;
};

}  // namespace

ObjMesh parse_obj(const std::string& text, const std::string& name) { return Reader(text, name).read(); }

ObjMesh read_obj(const std::string& path) {
    File file(std::fopen(path.c_str(), "rb"));
    if (!file) throw InputError(path + ": cannot open for reading");
    std::string text;
    // One allocation for a regular file; the block loop still reads a pipe, whose size is unknown.
    if (std::fseek(file.get(), 0, SEEK_END) == 0) {
        long size = std::ftell(file.get());
        if (size > 0) text.reserve(std::size_t(size));
        std::rewind(file.get());
    }
    char block[1 << 16];
    for (std::size_t n; (n = std::fread(block, 1, sizeof block, file.get())) > 0;) text.append(block, n);
    if (std::ferror(file.get())) throw InputError(path + ": read error");
    return parse_obj(text, path);
}

void write_obj(const std::string& path, const ObjMesh& mesh) {
    File file(std::fopen(path.c_str(), "wb"));
    if (!file) throw std::runtime_error(path + ": cannot open for writing");
    Writer out(file.get(), path);

    for (std::size_t k = 0; k < mesh.positions.size(); k += 3) {
        out.text("v ").number(mesh.positions[k]).text(" ").number(mesh.positions[k + 1]).text(" ").number(mesh.positions[k + 2]).text("\n");
    }
    for (std::size_t k = 0; k < mesh.uvs.size(); k += 2) {
        out.text("vt ").number(mesh.uvs[k]).text(" ").number(mesh.uvs[k + 1]).text("\n");
    }
    const bool with_uvs = !mesh.triangle_uvs.empty();
    for (std::size_t k = 0; k < mesh.triangles.size(); k += 3) {
        out.text("f");
        for (std::size_t c = k; c < k + 3; ++c) {
            out.text(" ").number(std::int64_t(mesh.triangles[c]) + 1);
            if (with_uvs) out.text("/").number(std::int64_t(mesh.triangle_uvs[c]) + 1);
        }
        out.text("\n");
    }
    for (std::size_t e = 0; e < mesh.crease_sharpness.size(); ++e) {
        out.text("t crease 2/1/0 ").number(std::int64_t(mesh.crease_edges[2 * e])).text(" ");
        out.number(std::int64_t(mesh.crease_edges[2 * e + 1])).text(" ").number(mesh.crease_sharpness[e]).text("\n");
    }
    for (std::size_t k = 0; k < mesh.corner_sharpness.size(); ++k) {
        out.text("t corner 1/1/0 ").number(std::int64_t(mesh.corner_vertices[k])).text(" ");
        out.number(mesh.corner_sharpness[k]).text("\n");
    }
    for (std::int32_t v : mesh.cone_vertices) out.text("t cone 1/0/0 ").number(std::int64_t(v)).text("\n");
    if (mesh.boundary) {
        out.text(*mesh.boundary == Boundary::EdgesAndCorners ? "t interpolateboundary 1/0/0 1\n" : "t interpolateboundary 1/0/0 2\n");
    }
    if (mesh.crease_method) {
        out.text(*mesh.crease_method == CreaseMethod::Chaikin ? "t creasemethod 0/0/1 chaikin\n" : "t creasemethod 0/0/1 normal\n");
    }
    out.finish();
    if (std::fclose(file.release()) != 0) throw std::runtime_error("cannot write " + path);
}

}  // namespace loopsub::obj
