// libFuzzer target: raw bytes as a mesh with tags and options, straight into Plan, evaluate, evaluate_face_varying
// and output_edges, with no reader in between: indices out of range, NaN and huge values, negative counts
// of nothing, every option. Layout (each field taken from the bytes in turn, zero when they run out):
//   options byte (rules, boundary, crease method, kernel, 2 threads, limit surface, closed), second options byte
//   (boundary none, face-varying mode, a face-varying layer), levels 0-3, crease threshold (float),
//   vertex count 0-63, triangle count 0-63, crease count 0-15, corner count 0-7, cone count 0-7, hole count 0-3,
//   layer value count 0-63, then the triangles' indices, crease edges and sharpness, corners and sharpness, cones,
//   holes, the layer's value indices (indices are bytes, so some fall outside the mesh), then the positions, two
//   face-varying channels per corner and the layer's values (raw float bits). "Closed" takes an octahedron's 6
//   vertices and 8 triangles instead of the counts and the triangles' indices (the bytes are read all the same): a
//   closed surface, which random triangles hardly ever are, and whose limit comes from the last level's grandparent.
//   Last, the triangles' own edges (MeshView::triangle_edges): a byte that gives them (bit 0), numbered by their ends
//   (bit 1, so that they pass) or else from the bytes; then a byte per corner, from which a numbered corner's edge may
//   take a number of its own (a second edge on the same ends, as a refined level has next to a valence-2 vertex).
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <map>
#include <stdexcept>
#include <utility>
#include <vector>

#include "fuzz_common.h"

namespace {

// The output's edges, as Blender's mesh takes them (Plan::output_edges): each triangle's edge k joins its corners k and
// k + 1, every edge is some triangle's, and the triangles copied in the same pass are the output's.
void require_output_edges(const loopsub::Plan& plan) {
    const int num_edges = plan.num_output_edges(), num_triangles = plan.num_output_triangles();
    std::vector<std::int32_t> ends(2 * std::size_t(num_edges)), triangle_edges(3 * std::size_t(num_triangles));
    std::vector<std::int32_t> copied(3 * std::size_t(num_triangles));
    plan.output_edges(ends.data(), triangle_edges.data(), copied.data());
    const std::int32_t* corners = plan.output_triangles();
    if (!std::equal(copied.begin(), copied.end(), corners)) std::abort();
    std::vector<std::uint8_t> used(std::size_t(num_edges), 0);
    for (int c = 0; c < 3 * num_triangles; ++c) {
        const std::int32_t e = triangle_edges[std::size_t(c)];
        if (e < 0 || e >= num_edges) std::abort();
        const std::int32_t a = corners[c], b = corners[c % 3 == 2 ? c - 2 : c + 1];
        const std::int32_t x = ends[2 * std::size_t(e)], y = ends[2 * std::size_t(e) + 1];
        if (!((x == a && y == b) || (x == b && y == a))) std::abort();
        used[std::size_t(e)] = 1;
    }
    for (const std::uint8_t edge_used : used)
        if (!edge_used) std::abort();
}

// The input edges' numbers on the output's edges (Plan::output_edge_parents), each input triangle's side numbered by
// its corner: every number is a side's, and an input edge's (its greatest side's) reaches 2^levels edges, its halves.
void require_output_edge_parents(const loopsub::Plan& plan, int num_input_triangles, int levels) {
    std::vector<std::int32_t> side_edges(3 * std::size_t(num_input_triangles));
    for (std::size_t c = 0; c < side_edges.size(); ++c) side_edges[c] = std::int32_t(c);
    std::vector<std::int32_t> parents(std::size_t(plan.num_output_edges()));
    plan.output_edge_parents(side_edges.data(), parents.data());
    std::vector<int> edges_on(side_edges.size(), 0);
    for (const std::int32_t parent : parents) {
        if (parent < -1 || parent >= std::int32_t(side_edges.size())) std::abort();
        if (parent >= 0) ++edges_on[std::size_t(parent)];
    }
    for (const int count : edges_on)
        if (count != 0 && count != 1 << levels) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace loopsub;
    fuzz::Bytes in(data, size);
    const std::uint8_t flags = in.byte();
    Options options = fuzz::options_from(flags);
    options.limit_surface = (flags & 64) != 0;
    const std::uint8_t more = in.byte();
    if (more & 1) options.boundary = Boundary::None;
    options.face_varying = FaceVaryingInterpolation((more >> 1) % 6);
    const bool with_layer = (more & 16) != 0;
    options.level_tables = LevelTables((more >> 5) % 3);
    options.levels = in.byte() % 4;
    options.crease_threshold = in.number();
    const bool closed = (flags & 128) != 0;
    int vertices = in.byte() % 64, triangles = in.byte() % 64;
    const int creases = in.byte() % 16, corners = in.byte() % 8, cones = in.byte() % 8, holes = in.byte() % 4,
              layer_values = in.byte() % 64;
    if (closed) vertices = 6, triangles = 8;

    MeshData mesh;
    mesh.positions.resize(3 * std::size_t(vertices));
    fuzz::read_mesh(in, mesh, vertices, triangles, creases, corners, cones);
    if (closed)  // the octahedron: vertices +x -x +y -y +z -z, each face counter-clockwise seen from outside
        mesh.triangles = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    for (int i = 0; i < holes; ++i) mesh.hole_triangles.push_back(in.index(triangles));
    std::vector<std::int32_t> corner_values(3 * std::size_t(triangles));
    for (std::int32_t& value : corner_values) value = in.index(layer_values);
    for (float& value : mesh.positions) value = in.number();
    std::vector<float> face_varying(6 * std::size_t(triangles));
    for (float& value : face_varying) value = in.number();
    std::vector<std::vector<float>> values(1, std::vector<float>(2 * std::size_t(layer_values)));
    for (float& value : values[0]) value = in.number();
    const std::uint8_t edges_byte = in.byte();
    std::vector<std::int32_t> triangle_edges(3 * std::size_t(triangles));
    std::map<std::pair<std::int32_t, std::int32_t>, std::int32_t> number_of_ends;
    for (int c = 0; c < 3 * triangles; ++c) {
        const std::int32_t a = mesh.triangles[std::size_t(c)], b = mesh.triangles[std::size_t(c - c % 3 + (c + 1) % 3)];
        const std::uint8_t split = in.byte();
        std::int32_t& edge = triangle_edges[std::size_t(c)];
        if (edges_byte & 2)  // a number is the first corner on its ends, or a corner's own (no other corner takes it)
            edge = split % 8 == 0 ? c : number_of_ends.try_emplace(std::minmax(a, b), c).first->second;
        else edge = in.index(3 * triangles);
    }

    try {
        const FaceVaryingLayer layer{corner_values.data(), layer_values};
        MeshView view = mesh.view();
        if (with_layer) view.face_varying = &layer, view.num_face_varying = 1;
        if (edges_byte & 1) view.triangle_edges = triangle_edges.data();
        Plan plan(view, options);
        fuzz::exercise(plan, mesh.positions, face_varying, 2, values);
        try {
            require_output_edges(plan);
            require_output_edge_parents(plan, triangles, options.levels);
        } catch (const std::logic_error&) {  // refused: a plan of no levels, or with holes (tagged or Boundary::None)
        }
    } catch (const InputError&) {
    } catch (const MemoryLimitError&) {}
    return 0;
}
