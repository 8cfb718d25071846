// The rows' two meshes (loopsub_bench.cpp describes them), made with the tests' generators (support/meshes.h), both
// with a UV layer with a seam (add_uvs_with_seam).
#include <map>
#include <utility>
#include <vector>

#include "bench.h"

namespace bench {

namespace {

// Tags the edges between the triangles whose centroid lies above z = height and the others: a closed loop.
void tag_loop(Mesh& m, float height, float sharpness) {
    std::map<std::pair<int, int>, int> above;  // per edge: triangles above minus triangles below
    for (int f = 0; f < m.num_triangles(); ++f) {
        const int* v = &m.triangles[3 * f];
        const float z = (m.positions[3 * v[0] + 2] + m.positions[3 * v[1] + 2] + m.positions[3 * v[2] + 2]) / 3.0f;
        for (int k = 0; k < 3; ++k) above[std::minmax(v[k], v[(k + 1) % 3])] += z > height ? 1 : -1;
    }
    for (const auto& [edge, balance] : above) {
        if (balance == 0) m.add_crease(edge.first, edge.second, sharpness);
    }
}

Mesh creased_icosphere() {
    Mesh m = loopsub::testing::icosphere(4);
    m.name = "creased";
    tag_loop(m, 0.3f, 10.0f);
    tag_loop(m, -0.4f, 2.5f);
    m.corner_vertices = {0, 3, 6, 9};  // icosahedron vertices (valence 5), away from and on both sides of the loops
    m.corner_sharpness = {10.0f, 10.0f, 1.5f, 1.5f};
    return m;
}

}  // namespace

const std::vector<Mesh>& meshes() {
    static const std::vector<Mesh> all = [] {
        Mesh smooth = loopsub::testing::icosphere(4);
        smooth.name = "icosphere";
        std::vector<Mesh> both{smooth, creased_icosphere()};
        for (Mesh& m : both) loopsub::testing::add_uvs_with_seam(m);
        return both;
    }();
    return all;
}

}  // namespace bench
