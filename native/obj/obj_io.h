// Reading (obj_read.cpp) and writing (obj_write.cpp) Wavefront OBJ with OpenSubdiv's tags (the format of its
// regression shapes):
//   t crease 2/1/0 A B S          edge A-B (0-based) has sharpness S
//   t corner 1/1/0 V S            vertex V has corner sharpness S
//   t interpolateboundary 1/0/0 M RenderMan numbering: 0 none, 1 edges and corners, 2 edges only
//   t creasemethod 0/0/1 chaikin  Chaikin decay of semi-sharp creases (or "uniform")
//   t cone 1/0/0 V                vertex V is a cone (Hoppe94 rules)
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "base/large_allocator.h"
#include "loopsub/loopsub.h"

namespace loopsub::obj {

// The mesh (vertices, triangles, tags) plus what an OBJ file carries besides.
struct ObjMesh : MeshData {
    std::vector<float> uvs;                     // 2 per `vt`
    std::vector<std::int32_t> triangle_uvs;     // 3 per triangle, 0-based `vt` indices; empty when the faces have none
    std::optional<Boundary> boundary;           // from `t interpolateboundary`
    std::optional<CreaseMethod> crease_method;  // from `t creasemethod`
    std::optional<FaceVaryingInterpolation> face_varying;  // from `t facevaryinginterpolateboundary`
    // Written only: normals (3 per `vn`) and their index at each corner (3 per triangle; empty: none).
    std::vector<float> normals;
    std::vector<std::int32_t> triangle_normals;
    int polygons_triangulated = 0;   // faces with more than three corners, split by ear clipping
    std::vector<std::string> notes;  // what the reader skipped or filled in, one line per kind
    // Where the elements the core reads came from, for locate(): per face of the file its line and its first triangle
    // (face_first_triangle has one more: the number of triangles); per crease, corner and cone tag the line it is on.
    std::vector<int> face_lines;
    std::vector<std::int32_t> face_first_triangle;
    std::vector<int> crease_lines, corner_lines, cone_lines;
};

// Throws InputError naming the file and line for anything it cannot read.
ObjMesh read_obj(const std::string& path);
ObjMesh parse_obj(const std::string& text, const std::string& name = "<string>");

// The core's problem with a mesh read from the file `name` (InputError::problem), said at its line in the file's
// words: "name:12: the face repeats vertex 3 ..." (OBJ's vertex numbers, a polygon rather than its triangles), "name:7:
// crease 0-3 is not an edge of the mesh". Where the file has no line for it (a vertex's value), the core's message.
std::string locate(const ObjMesh& mesh, const std::string& name, const InputProblem& problem);

// Arrays of a one-shot job's output (the CLI's points and normals), filled by the core before they are written: in
// huge pages where the system gives them, and not zeroed first (the core's allocator for large arrays).
using OutputFloats = loopsub::detail::LargeVector<float>;

// The arrays the v, vt, vn and f lines are written from: an ObjMesh's own (of), or a caller's that need no copy into
// one (a tessellation's triangles and the face points at their corners). Null triangle_uvs / triangle_normals: none.
struct ObjLines {
    const float *positions = nullptr, *uvs = nullptr, *normals = nullptr;  // 3, 2 and 3 per line
    std::size_t num_positions = 0, num_uvs = 0, num_normals = 0;
    const std::int32_t *triangles = nullptr, *triangle_uvs = nullptr, *triangle_normals = nullptr;  // 3 per triangle
    std::size_t num_triangles = 0;
    static ObjLines of(const ObjMesh& mesh);
};

// Writes v, vt (if any), vn (if any), f and the tags. With threads > 1, the v, vt, vn and f lines are formatted in
// chunks of 8,192 lines on that many threads (the caller among them) and written in order: the file's
// bytes are the same for any number. Up to 16 chunks a thread are held (about 0.25 MB of text each).
void write_obj(const std::string& path, const ObjMesh& mesh, int threads = 1);
// The same with the v, vt, vn and f lines from `lines`, the tags from `mesh`.
void write_obj(const std::string& path, const ObjMesh& mesh, const ObjLines& lines, int threads = 1);

}  // namespace loopsub::obj
