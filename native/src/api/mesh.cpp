#include "loopsub/loopsub.h"

namespace loopsub {

void MeshData::add_crease(int a, int b, float sharpness) {
    crease_edges.push_back(a);
    crease_edges.push_back(b);
    crease_sharpness.push_back(sharpness);
}

void MeshData::add_corner(int v, float sharpness) {
    corner_vertices.push_back(v);
    corner_sharpness.push_back(sharpness);
}

MeshView MeshData::view() const {
    MeshView mesh;
    mesh.num_vertices = num_vertices();
    mesh.triangles = triangles.data();
    mesh.num_triangles = num_triangles();
    mesh.crease_edges = crease_edges.data();
    mesh.crease_sharpness = crease_sharpness.data();
    mesh.num_crease_edges = int(crease_sharpness.size());
    mesh.corner_vertices = corner_vertices.data();
    mesh.corner_sharpness = corner_sharpness.data();
    mesh.num_corners = int(corner_sharpness.size());
    mesh.cone_vertices = cone_vertices.data();
    mesh.num_cones = int(cone_vertices.size());
    mesh.hole_triangles = hole_triangles.data();
    mesh.num_holes = int(hole_triangles.size());
    return mesh;
}

}  // namespace loopsub
