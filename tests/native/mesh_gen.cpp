#include "mesh_gen.h"

#include "obj_io.h"

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace loopsub::testing {

namespace {

// True for an `f` line that names the same vertex twice (the vertex index is what precedes the first '/').
bool is_degenerate_face_line(const std::string& line) {
    std::istringstream tokens(line);
    std::string token;
    tokens >> token;
    if (token != "f") return false;
    std::set<std::string> seen;
    while (tokens >> token)
        if (!seen.insert(token.substr(0, token.find('/'))).second) return true;
    return false;
}

}  // namespace

const char* peer_shapes_missing() {
    return std::filesystem::is_directory(LOOPSUB_PEER_SHAPES)
               ? nullptr
               : "OpenSubdiv's Loop shapes are not in " LOOPSUB_PEER_SHAPES
                 " (clone beside the team's shared folder to run this test)";
}

void require_peer_shapes() {
    if (const char* missing = peer_shapes_missing()) throw PeerShapesMissing(missing);
}

TestMesh peer_shape(const std::string& file_name, bool drop_degenerate_faces) {
    require_peer_shapes();
    const std::string path = std::string(LOOPSUB_PEER_SHAPES) + "/" + file_name;
    obj::ObjMesh obj;
    if (drop_degenerate_faces) {
        std::ifstream in(path);
        if (!in) throw std::runtime_error("cannot open " + path);
        std::string text, line;
        while (std::getline(in, line))
            if (!is_degenerate_face_line(line)) text += line + "\n";
        obj = obj::parse_obj(text, path);
    } else {
        obj = obj::read_obj(path);
    }
    TestMesh mesh;
    mesh.name = file_name.substr(0, file_name.rfind('.'));
    static_cast<MeshData&>(mesh) = obj;
    if (!obj.triangle_uvs.empty()) {
        mesh.uvs = obj.uvs;
        mesh.triangle_uvs = obj.triangle_uvs;
    }
    mesh.boundary = obj.boundary.value_or(Boundary::EdgesOnly);
    mesh.crease_method = obj.crease_method.value_or(CreaseMethod::Uniform);
    return mesh;
}

std::vector<float> evaluate_positions(Plan& plan, const TestMesh& mesh) {
    std::vector<float> out(3 * std::size_t(plan.num_output_vertices()));
    plan.evaluate(interleaved(mesh.positions.data(), 3), interleaved(out.data(), 3));
    return out;
}

LimitEvaluation evaluate_limit(Plan& plan, const TestMesh& mesh) {
    LimitEvaluation result{std::vector<float>(3 * std::size_t(plan.num_output_vertices())),
                           std::vector<float>(9 * std::size_t(plan.num_output_triangles()))};
    plan.evaluate(interleaved(mesh.positions.data(), 3), interleaved(result.positions.data(), 3),
                  result.normals.data());
    return result;
}

}  // namespace loopsub::testing
