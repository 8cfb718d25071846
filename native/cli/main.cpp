// loopsub: Loop subdivision of an OBJ triangle mesh with OpenSubdiv's crease tags.
// Exit codes: 0 success, 1 the input or the refinement failed, 2 the command line is wrong.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <memory>
#include <new>
#include <string>
#include <vector>

#include "command_line.h"
#include "loopsub/loopsub.h"
#include "loopsub/tessellation.h"
#include "obj/obj_io.h"

namespace {

using loopsub::cli::Command;
using loopsub::cli::kUsage;
using loopsub::cli::parse_command_line;
using loopsub::cli::UsageError;

// The camera of --camera (the core's look_at_camera; parse_command_line checked that the flags make a view).
loopsub::Camera camera_of(const loopsub::cli::LookAt& look) {
    return loopsub::look_at_camera(look.eye, look.target, look.up, look.fov_degrees, float(look.width),
                                   float(look.height));
}

// Where --stats prints: standard output, unless the OBJ goes there.
std::FILE* stats_stream(const Command& command) {
    return command.output == "/dev/stdout" || command.output == "/proc/self/fd/1" ? stderr : stdout;
}

// The core's notes of the input (Plan::notes): the edges along which two faces run the same way, as a face wound
// against its neighbours (flipped) leaves them: the rules make them infinitely sharp (docs/rules.md, Sharpness), where
// the artist most often wants the face turned.
void print_notes(const Command& command, const std::vector<loopsub::InputProblem>& notes) {
    const auto same_way = std::count_if(notes.begin(), notes.end(), [](const loopsub::InputProblem& note) {
        return note.kind == loopsub::InputProblem::Kind::RunsTheSameWay;
    });
    if (same_way > 0)
        std::fprintf(stderr,
                     "loopsub: note: %s: %d edge(s) along which two faces run the same way (a face wound against its "
                     "neighbours), infinitely sharp\n",
                     command.input.c_str(), int(same_way));
}

// The mesh the core reads: the input's, and its vt indices as the UV layer's topology (where a vertex's corners name
// different vt, a seam runs). `layer` holds the layer while the view is read.
loopsub::MeshView with_uv_layer(const loopsub::obj::ObjMesh& in, loopsub::FaceVaryingLayer& layer) {
    loopsub::MeshView mesh = in.view();
    layer = {in.triangle_uvs.data(), int(in.uvs.size() / 2)};
    if (!in.triangle_uvs.empty()) mesh.face_varying = &layer, mesh.num_face_varying = 1;
    return mesh;
}

// --tessellate and --camera: the points and their normals (one vn per face point), and the UVs (one vt per face
// point) refined by the face-varying interpolation as levels refine them.
void tessellate(const Command& command, const loopsub::obj::ObjMesh& in, const loopsub::Options& options) {
    loopsub::TessellationRates rates;
    rates.uniform_rate = std::max(command.tessellate, 1);
    const auto started = std::chrono::steady_clock::now();
    loopsub::ScreenRates screen;
    if (command.camera) {
        screen =
            loopsub::screen_space_rates(in.view(), in.positions.data(), camera_of(*command.camera),
                                        command.camera->dicing_rate, command.camera->max_rate, command.camera->measure);
        rates = screen.view();
    }
    loopsub::FaceVaryingLayer uv_layer;
    const loopsub::Tessellation tessellation(with_uv_layer(in, uv_layer), options, rates);
    print_notes(command, tessellation.notes());
    const auto planned = std::chrono::steady_clock::now();
    // A one-shot job: the points and normals in arrays the evaluation fills (in huge pages, not zeroed first), the
    // faces written straight from the tessellation's arrays (not copied into an ObjMesh).
    const std::size_t num_points = std::size_t(tessellation.num_points()),
                      num_face_points = std::size_t(tessellation.num_face_points());
    loopsub::obj::OutputFloats points, normals;
    points.resize(3 * num_points), normals.resize(3 * num_face_points);
    tessellation.evaluate(in.positions.data(), points.data(), normals.data());
    const auto evaluated = std::chrono::steady_clock::now();
    loopsub::obj::ObjLines lines;
    lines.positions = points.data(), lines.num_positions = num_points;
    lines.normals = normals.data(), lines.num_normals = num_face_points;
    lines.triangles = tessellation.triangles(), lines.num_triangles = std::size_t(tessellation.num_triangles());
    lines.triangle_normals = tessellation.corner_face_points();
    std::vector<float> uvs;
    if (!in.triangle_uvs.empty()) {
        uvs.resize(2 * num_face_points);
        tessellation.evaluate_face_varying(0, in.uvs.data(), 2, uvs.data());
        lines.uvs = uvs.data(), lines.num_uvs = num_face_points;
        lines.triangle_uvs = lines.triangle_normals;
    }
    loopsub::obj::write_obj(command.output, loopsub::obj::ObjMesh(), lines, options.threads);
    const auto written = std::chrono::steady_clock::now();
    if (command.stats) {
        using ms = std::chrono::duration<double, std::milli>;
        std::fprintf(stats_stream(command),
                     "topology_ms=%.3f evaluate_ms=%.3f write_ms=%.3f rate=%d levels=%d vertices_in=%d triangles_in=%d "
                     "vertices_out=%d triangles_out=%d threads=%d\n",
                     ms(planned - started).count(), ms(evaluated - planned).count(), ms(written - evaluated).count(),
                     command.camera
                         ? (screen.rates.empty() ? 1 : *std::max_element(screen.rates.begin(), screen.rates.end()))
                         : command.tessellate,
                     tessellation.levels(), in.num_vertices(), in.num_triangles(), tessellation.num_points(),
                     tessellation.num_triangles(), options.threads);
    }
}

// What the reader skipped or filled in, and the polygons it split.
void print_file_notes(const Command& command, const loopsub::obj::ObjMesh& in) {
    if (in.polygons_triangulated > 0) {
        std::fprintf(stderr, "loopsub: note: %s: triangulated %d polygon(s) with more than 3 corners\n",
                     command.input.c_str(), in.polygons_triangulated);
    }
    for (const std::string& note : in.notes)
        std::fprintf(stderr, "loopsub: note: %s: %s\n", command.input.c_str(), note.c_str());
}

// The options: each rule the command line's, else the file's tag, else the default.
loopsub::Options options_of(const Command& command, const loopsub::obj::ObjMesh& in) {
    loopsub::Options options = command.options;
    // One evaluation follows: derived tables make the plan quicker and smaller, and cost that evaluation less than
    // they save (docs/benchmark.md, "Stored or derived tables").
    options.level_tables = loopsub::LevelTables::Derived;
    options.boundary = command.boundary.value_or(in.boundary.value_or(loopsub::Boundary::EdgesOnly));
    options.crease_method = command.crease_method.value_or(in.crease_method.value_or(loopsub::CreaseMethod::Uniform));
    options.face_varying =
        command.face_varying.value_or(in.face_varying.value_or(loopsub::FaceVaryingInterpolation::CornersOnly));
    return options;
}

// The limit positions and the compact normals as the vn, each corner naming its own: one vn per normal some corner
// uses (a vertex whose corners all take their sides' normals has an unused one of its own), in the plan's order.
void evaluate_with_normals(loopsub::Plan& plan, const loopsub::obj::ObjMesh& in, loopsub::obj::ObjMesh& out) {
    std::vector<float> normals(std::size_t(plan.num_limit_normals()) * 3);
    plan.evaluate(loopsub::interleaved(in.positions.data(), 3), loopsub::interleaved(out.positions.data(), 3),
                  loopsub::Plan::LimitNormals{normals.data()});
    const std::int32_t* index = plan.corner_normal_indices();
    std::vector<std::int32_t> number(std::size_t(plan.num_limit_normals()), -1);
    for (std::size_t c = 0; c < out.triangles.size(); ++c) number[std::size_t(index[c])] = 0;
    for (std::size_t k = 0; k < number.size(); ++k) {
        if (number[k] < 0) continue;
        number[k] = std::int32_t(out.normals.size() / 3);
        out.normals.insert(out.normals.end(), &normals[3 * k], &normals[3 * k] + 3);
    }
    out.triangle_normals.resize(out.triangles.size());
    for (std::size_t c = 0; c < out.triangles.size(); ++c) out.triangle_normals[c] = number[std::size_t(index[c])];
}

// The output's tags, and the rules that shaped it, so that refining it again continues the same surface.
void carry_tags(const Command& command, const loopsub::Plan& plan, const loopsub::obj::ObjMesh& in,
                loopsub::obj::ObjMesh& out) {
    out.crease_edges = plan.output_crease_edges();
    out.crease_sharpness = plan.output_crease_sharpness();
    out.corner_vertices = plan.output_corner_vertices();
    out.corner_sharpness = plan.output_corner_sharpness();
    // Old vertices keep their indices at every level, so the cone tags carry over unchanged.
    out.cone_vertices = in.cone_vertices;
    out.boundary = command.boundary ? command.boundary : in.boundary;
    out.crease_method = command.crease_method ? command.crease_method : in.crease_method;
    out.face_varying = command.face_varying ? command.face_varying : in.face_varying;
}

// --levels: the plan's positions (with --limit, and its normals), UVs and tags written out.
void subdivide(const Command& command, const loopsub::obj::ObjMesh& in, const loopsub::Options& options) {
    loopsub::FaceVaryingLayer uv_layer;
    loopsub::Plan plan(with_uv_layer(in, uv_layer), options);
    print_notes(command, plan.notes());

    loopsub::obj::ObjMesh out;
    out.positions.resize(std::size_t(plan.num_output_vertices()) * 3);
    const std::int32_t* triangles = plan.output_triangles();
    out.triangles.assign(triangles, triangles + std::size_t(plan.num_output_triangles()) * 3);
    if (options.limit_surface) evaluate_with_normals(plan, in, out);
    else plan.evaluate(loopsub::interleaved(in.positions.data(), 3), loopsub::interleaved(out.positions.data(), 3));
    const double evaluate_ms = plan.last_evaluate_ms();

    if (!in.triangle_uvs.empty()) {
        out.uvs.resize(std::size_t(plan.num_output_face_varying_values(0)) * 2);
        plan.evaluate_face_varying(0, loopsub::interleaved(in.uvs.data(), 2), loopsub::interleaved(out.uvs.data(), 2));
        const std::int32_t* uv_indices = plan.output_face_varying_indices(0);
        out.triangle_uvs.assign(uv_indices, uv_indices + out.triangles.size());
    }
    carry_tags(command, plan, in, out);
    loopsub::obj::write_obj(command.output, out, options.threads);

    if (command.stats) {
        std::fprintf(stats_stream(command),
                     "topology_ms=%.3f evaluate_ms=%.3f levels=%d vertices_in=%d triangles_in=%d vertices_out=%d "
                     "triangles_out=%d kernel=%s threads=%d\n",
                     plan.topology_ms(), evaluate_ms, plan.levels(), in.num_vertices(), in.num_triangles(),
                     plan.num_output_vertices(), plan.num_output_triangles(), loopsub::kernel_name(plan.kernel()),
                     plan.options().threads);
    }
}

// The file's notes, then the refinement (or the tessellation) written out.
int refine(const Command& command, const loopsub::obj::ObjMesh& in) {
    print_file_notes(command, in);
    const loopsub::Options options = options_of(command, in);
    if (command.tessellate > 0 || command.camera) tessellate(command, in, options);
    else subdivide(command, in, options);
    return 0;
}

// Reads the file, then refines it, the core's problems with the input said at their line of the file.
int run(const Command& command) {
    const loopsub::obj::ObjMesh in = loopsub::obj::read_obj(command.input);
    try {
        return refine(command, in);
    } catch (const loopsub::InputError& e) {
        if (!e.problem()) throw;
        throw loopsub::InputError(loopsub::obj::locate(in, command.input, *e.problem()));
    }
}

}  // namespace

int main(int argc, char** argv) {
    Command command;
    try {
        command = parse_command_line(argc, argv);
    } catch (const UsageError& e) {
        std::fprintf(stderr, "loopsub: error: %s\n%s", e.what(), kUsage);
        return 2;
    }
    if (command.help) {
        std::fputs(kUsage, stdout);
        return 0;
    }
    try {
        return run(command);
    } catch (const loopsub::MemoryLimitError& e) {
        // The core's message gives the bytes; when the limit is what refused it, restate both in the flag's unit.
        // (A refinement can also be refused for passing 32-bit indices, which no limit would allow.)
        const std::uint64_t limit = command.options.memory_limit_bytes;
        if (e.required_bytes > limit) {
            std::fprintf(
                stderr, "loopsub: error: %s (%llu MiB needed, --memory-limit-mb is %llu)\n", e.what(),
                static_cast<unsigned long long>(e.required_bytes / (1u << 20) + (e.required_bytes % (1u << 20) != 0)),
                static_cast<unsigned long long>(limit >> 20));
        } else {
            std::fprintf(stderr, "loopsub: error: %s\n", e.what());
        }
    } catch (const loopsub::InputError& e) {
        std::fprintf(stderr, "loopsub: error: %s\n", e.what());
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "loopsub: error: out of memory (try fewer --levels)\n");
    } catch (const std::exception& e) { std::fprintf(stderr, "loopsub: error: %s\n", e.what()); }
    return 1;
}
