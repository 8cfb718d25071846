// Writing Wavefront OBJ with OpenSubdiv's tags: numbers in the shortest form that reads back exactly (so write -> read
// is exact), lines formatted straight into blocks, and the v, vt, vn and f lines on several threads if asked (the same
// bytes for any number).
#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <vector>

#include "obj_file.h"
#include "obj_io.h"
#include "base/parallel.h"
#include "shortest_float.h"

namespace loopsub::obj {

namespace {

// Integers: std::to_chars is as fast as anything tried here (their lengths vary little from line to line), and
// faster on 32 bits: face indices (1-based, so up to 2^31) are written as such.
char* put_int(char* out, std::int64_t value) { return std::to_chars(out, out + 24, value).ptr; }
char* put_index(char* out, std::int32_t index) {
    return index >= 0 ? std::to_chars(out, out + 16, std::uint32_t(index) + 1).ptr
                      : put_int(out, std::int64_t(index) + 1);
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
        if (used_ > 0 && std::fwrite(block_.get(), 1, used_, file_) != used_)
            throw std::runtime_error("cannot write " + path_);
        used_ = 0;
    }

    std::FILE* file_;
    const std::string& path_;
    std::unique_ptr<char[]> block_;
    std::size_t used_ = 0;
};

// The v, vt, vn and f lines, numbered from 0 in the order they are written: first to last - 1 formatted at out.
char* format_lines(char* out, const ObjLines& mesh, std::size_t first, std::size_t last) {
    std::size_t start = 0;  // of the current kind of line
    // The lines of this kind in [first, last), each by line(out, k) with k counted within the kind.
    auto lines = [&](std::size_t count, const auto& line) {
        for (std::size_t k = std::max(first, start); k < std::min(last, start + count); ++k) out = line(out, k - start);
        start += count;
    };
    lines(mesh.num_positions,
          [&](char* p, std::size_t k) { return put_floats<3>(put_text(p, "v "), &mesh.positions[3 * k]); });
    lines(mesh.num_uvs, [&](char* p, std::size_t k) { return put_floats<2>(put_text(p, "vt "), &mesh.uvs[2 * k]); });
    lines(mesh.num_normals,
          [&](char* p, std::size_t k) { return put_floats<3>(put_text(p, "vn "), &mesh.normals[3 * k]); });
    const bool with_uvs = mesh.triangle_uvs != nullptr, with_normals = mesh.triangle_normals != nullptr;
    lines(mesh.num_triangles, [&](char* p, std::size_t k) {
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

// The v, vt, vn and f lines. One thread formats them into the writer's block, which is written whenever full. More
// (the core's team, parallel.h) format chunks of consecutive lines in rounds, eight chunks per thread: one of them
// first writes the previous round's chunks, in order, while the others start on this round's, then helps them. Two
// rounds of chunks are in memory at a time, each chunk a 1 MiB buffer holding about 0.25 MB of text.
void write_lines(Writer& out, const ObjLines& mesh, int threads) {
    constexpr std::size_t kChunkLines = 1 << 13;  // times kLongestLine: 1 MiB
    struct Chunk {
        std::unique_ptr<char[]> text;  // room for kChunkLines lines, made by the caller when first needed
        std::size_t size = 0;
    };
    const std::size_t lines = mesh.num_positions + mesh.num_uvs + mesh.num_normals + mesh.num_triangles;
    const std::size_t chunks = (lines + kChunkLines - 1) / kChunkLines;
    threads =
        int(std::clamp<std::size_t>(chunks, 1, std::size_t(std::max(threads, 1))));  // a small file: the caller alone
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
    const detail::TeamScope scope(threads);
    for (std::size_t round = 0; round < num_rounds; ++round) {
        const std::size_t first_chunk = round * per_round;
        std::vector<Chunk>& now = rounds[round % 2];
        now.resize(std::min(per_round, chunks - first_chunk));  // the last round may have fewer
        for (Chunk& chunk : now)
            if (!chunk.text) chunk.text.reset(new char[kChunkLines * Writer::kLongestLine]);
        // Piece 0, the first taken, writes the previous round; each other piece formats a chunk of this one.
        detail::TeamScope::current()->run(
            [&](int piece, int) {
                if (piece == 0) {
                    if (round > 0) write_round(rounds[(round - 1) % 2]);
                    return;
                }
                const std::size_t part = std::size_t(piece - 1);
                if (part >= now.size()) return;  // more threads than this round has chunks
                const std::size_t first = (first_chunk + part) * kChunkLines,
                                  last = std::min(lines, first + kChunkLines);
                now[part].size =
                    std::size_t(format_lines(now[part].text.get(), mesh, first, last) - now[part].text.get());
            },
            int(now.size()) + 1);
    }
    if (num_rounds > 0) write_round(rounds[(num_rounds - 1) % 2]);
}

}  // namespace

ObjLines ObjLines::of(const ObjMesh& mesh) {
    ObjLines lines;
    lines.positions = mesh.positions.data(), lines.num_positions = mesh.positions.size() / 3;
    lines.uvs = mesh.uvs.data(), lines.num_uvs = mesh.uvs.size() / 2;
    lines.normals = mesh.normals.data(), lines.num_normals = mesh.normals.size() / 3;
    lines.triangles = mesh.triangles.data(), lines.num_triangles = mesh.triangles.size() / 3;
    lines.triangle_uvs = mesh.triangle_uvs.empty() ? nullptr : mesh.triangle_uvs.data();
    lines.triangle_normals = mesh.triangle_normals.empty() ? nullptr : mesh.triangle_normals.data();
    return lines;
}

void write_obj(const std::string& path, const ObjMesh& mesh, int threads) {
    write_obj(path, mesh, ObjLines::of(mesh), threads);
}

void write_obj(const std::string& path, const ObjMesh& mesh, const ObjLines& lines, int threads) {
    File file(std::fopen(path.c_str(), "wb"));
    if (!file) throw std::runtime_error(path + ": cannot open for writing");
    Writer out(file.get(), path);

    write_lines(out, lines, threads);
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
