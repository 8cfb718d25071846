#include "support/meshes.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <utility>

namespace loopsub::testing {

namespace {

constexpr double kPi = 3.14159265358979323846;

void add_vertex(TestMesh& mesh, double x, double y, double z) {
    mesh.positions.push_back(float(x));
    mesh.positions.push_back(float(y));
    mesh.positions.push_back(float(z));
}

void add_triangle(TestMesh& mesh, int a, int b, int c) {
    mesh.triangles.push_back(a);
    mesh.triangles.push_back(b);
    mesh.triangles.push_back(c);
}

// The quad a-b-c-d as two triangles, split along its diagonal a-c.
void add_quad(TestMesh& mesh, int a, int b, int c, int d) {
    add_triangle(mesh, a, b, c);
    add_triangle(mesh, a, c, d);
}

// For convex meshes around the origin: flips every triangle whose normal points inwards, so that all are
// counter-clockwise seen from outside.
void orient_outward(TestMesh& mesh) {
    const auto& p = mesh.positions;
    for (int t = 0; t < mesh.num_triangles(); ++t) {
        std::int32_t* tri = &mesh.triangles[3 * t];
        double a[3], b[3], c[3];
        for (int k = 0; k < 3; ++k) {
            a[k] = p[3 * tri[0] + k];
            b[k] = p[3 * tri[1] + k];
            c[k] = p[3 * tri[2] + k];
        }
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        double centroid_dot = 0;
        for (int k = 0; k < 3; ++k) centroid_dot += n[k] * (a[k] + b[k] + c[k]);
        if (centroid_dot < 0) std::swap(tri[1], tri[2]);
    }
}

// Sharpness values that exercise every branch of OpenSubdiv's semi-sharp rules: below 1 (blend at the first
// level), exactly 1 and 2 (sharp, then the transition), fractional above 1, and infinite.
float random_sharpness(std::mt19937& rng) {
    static const float kChoices[] = {0.25f, 0.5f, 0.9f, 1.0f, 1.3f, 2.0f, 2.5f, 3.7f, kInfiniteSharpness};
    std::uniform_int_distribution<int> pick(0, 2 * int(std::size(kChoices)) - 1);
    int k = pick(rng);
    if (k < int(std::size(kChoices))) return kChoices[k];
    std::uniform_real_distribution<float> any(0.05f, 4.0f);
    return any(rng);
}

}  // namespace

MeshView TestMesh::view_with_uvs() const {
    uv_layer_ = {triangle_uvs.data(), int(uvs.size() / 2)};
    MeshView with_uvs = view();
    with_uvs.face_varying = &uv_layer_;
    with_uvs.num_face_varying = 1;
    return with_uvs;
}

std::vector<std::array<std::int32_t, 2>> unique_edges(const std::vector<std::int32_t>& triangles) {
    std::vector<std::array<std::int32_t, 2>> edges;
    edges.reserve(triangles.size());
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
        for (int k = 0; k < 3; ++k) {
            std::int32_t a = triangles[t + k], b = triangles[t + (k + 1) % 3];
            edges.push_back({std::min(a, b), std::max(a, b)});
        }
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    return edges;
}

double bounding_box_diagonal(const std::vector<float>& positions) {
    if (positions.empty()) return 0;
    double lo[3] = {positions[0], positions[1], positions[2]};
    double hi[3] = {lo[0], lo[1], lo[2]};
    for (std::size_t i = 0; i + 2 < positions.size(); i += 3) {
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min<double>(lo[k], positions[i + k]);
            hi[k] = std::max<double>(hi[k], positions[i + k]);
        }
    }
    return std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                     (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

TestMesh icosahedron() {
    TestMesh mesh;
    mesh.name = "icosahedron";
    const double g = (1.0 + std::sqrt(5.0)) / 2.0;
    const double s = 1.0 / std::sqrt(1.0 + g * g);  // unit sphere
    const double base[12][3] = {{-1, g, 0},  {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g},  {0, 1, g},
                                {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
    for (const auto& v : base) add_vertex(mesh, v[0] * s, v[1] * s, v[2] * s);
    const int faces[20][3] = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                              {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                              {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (const auto& f : faces) add_triangle(mesh, f[0], f[1], f[2]);
    orient_outward(mesh);
    return mesh;
}

TestMesh icosphere(int splits) {
    TestMesh mesh = icosahedron();
    for (int s = 0; s < splits; ++s) {
        std::map<std::pair<int, int>, int> midpoint;
        std::vector<std::int32_t> next;
        auto mid = [&](int a, int b) {
            auto key = std::make_pair(std::min(a, b), std::max(a, b));
            auto it = midpoint.find(key);
            if (it != midpoint.end()) return it->second;
            double m[3], len = 0;
            for (int k = 0; k < 3; ++k) {
                m[k] = 0.5 * (double(mesh.positions[3 * a + k]) + mesh.positions[3 * b + k]);
                len += m[k] * m[k];
            }
            len = std::sqrt(len);
            int index = mesh.num_vertices();
            add_vertex(mesh, m[0] / len, m[1] / len, m[2] / len);
            midpoint.emplace(key, index);
            return index;
        };
        for (int t = 0; t < mesh.num_triangles(); ++t) {
            int a = mesh.triangles[3 * t], b = mesh.triangles[3 * t + 1], c = mesh.triangles[3 * t + 2];
            int ab = mid(a, b), bc = mid(b, c), ca = mid(c, a);
            next.insert(next.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
        }
        mesh.triangles = std::move(next);
    }
    mesh.name = "icosphere" + std::to_string(mesh.num_triangles());
    return mesh;
}

TestMesh cube() {
    TestMesh mesh;
    mesh.name = "cube";
    for (int v = 0; v < 8; ++v) add_vertex(mesh, (v & 1) ? 1 : -1, (v & 2) ? 1 : -1, (v & 4) ? 1 : -1);
    // Each face as a quad (in either winding: orient_outward fixes it), split along its first diagonal.
    const int quads[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
    for (const auto& q : quads) add_quad(mesh, q[0], q[1], q[2], q[3]);
    orient_outward(mesh);
    return mesh;
}

TestMesh bipyramid(int n) {
    TestMesh mesh;
    mesh.name = "bipyramid" + std::to_string(n);
    add_vertex(mesh, 0, 0, 1.2);
    add_vertex(mesh, 0, 0, -0.8);
    for (int k = 0; k < n; ++k) {
        double u = 2 * kPi * k / n;
        add_vertex(mesh, std::cos(u), std::sin(u), 0.1 * std::sin(3 * u));
    }
    for (int k = 0; k < n; ++k) {
        int a = 2 + k, b = 2 + (k + 1) % n;
        add_triangle(mesh, 0, a, b);
        add_triangle(mesh, 1, b, a);
    }
    orient_outward(mesh);
    return mesh;
}

TestMesh torus(int nu, int nv) {
    TestMesh mesh;
    mesh.name = "torus" + std::to_string(nu) + "x" + std::to_string(nv);
    const double big = 1.0, small = 0.4;
    for (int i = 0; i < nu; ++i) {
        for (int j = 0; j < nv; ++j) {
            double u = 2 * kPi * i / nu, v = 2 * kPi * j / nv;
            add_vertex(mesh, (big + small * std::cos(v)) * std::cos(u), (big + small * std::cos(v)) * std::sin(u),
                       small * std::sin(v));
        }
    }
    for (int i = 0; i < nu; ++i) {
        for (int j = 0; j < nv; ++j) {
            add_quad(mesh, torus_vertex(nv, i, j), torus_vertex(nv, (i + 1) % nu, j),
                     torus_vertex(nv, (i + 1) % nu, (j + 1) % nv), torus_vertex(nv, i, (j + 1) % nv));
        }
    }
    return mesh;
}

TestMesh grid(int nx, int ny) {
    TestMesh mesh;
    mesh.name = "grid" + std::to_string(nx) + "x" + std::to_string(ny);
    const double h = 1.0 / std::max(nx, ny);
    for (int j = 0; j <= ny; ++j) {
        for (int i = 0; i <= nx; ++i) {
            double x = i * h, y = j * h;
            add_vertex(mesh, x, y, 0.1 * std::sin(3 * x) * std::cos(2 * y));
        }
    }
    for (int j = 0; j < ny; ++j) {
        for (int i = 0; i < nx; ++i) {
            add_quad(mesh, grid_vertex(nx, i, j), grid_vertex(nx, i + 1, j), grid_vertex(nx, i + 1, j + 1),
                     grid_vertex(nx, i, j + 1));
        }
    }
    return mesh;
}

TestMesh open_cylinder(int n, int rows) {
    TestMesh mesh;
    mesh.name = "open_cylinder" + std::to_string(n) + "x" + std::to_string(rows);
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j <= rows; ++j) {
            double u = 2 * kPi * i / n;
            add_vertex(mesh, std::cos(u), std::sin(u), 2.0 * j / rows);
        }
    }
    auto vertex = [&](int i, int j) { return (i % n) * (rows + 1) + j; };
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < rows; ++j) {
            add_quad(mesh, vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1));
        }
    }
    return mesh;
}

TestMesh open_fan(int n) {
    TestMesh mesh;
    mesh.name = "open_fan" + std::to_string(n);
    add_vertex(mesh, 0, 0, 0.5);
    for (int k = 0; k < n; ++k) {
        double u = 2 * kPi * k / n;
        add_vertex(mesh, std::cos(u), std::sin(u), 0.15 * std::cos(2 * u));
    }
    for (int k = 0; k < n; ++k) add_triangle(mesh, 0, 1 + k, 1 + (k + 1) % n);
    return mesh;
}

TestMesh hemisphere(int splits) {
    TestMesh sphere = icosphere(splits);
    TestMesh mesh;
    mesh.name = "hemisphere" + std::to_string(splits);
    std::vector<int> new_index(sphere.num_vertices(), -1);
    for (int t = 0; t < sphere.num_triangles(); ++t) {
        const std::int32_t* tri = &sphere.triangles[3 * t];
        double z =
            (sphere.positions[3 * tri[0] + 2] + sphere.positions[3 * tri[1] + 2] + sphere.positions[3 * tri[2] + 2]) /
            3.0;
        if (z <= -0.05) continue;
        for (int k = 0; k < 3; ++k) {
            int v = tri[k];
            if (new_index[v] < 0) {
                new_index[v] = mesh.num_vertices();
                add_vertex(mesh, sphere.positions[3 * v], sphere.positions[3 * v + 1], sphere.positions[3 * v + 2]);
            }
            mesh.triangles.push_back(new_index[v]);
        }
    }
    return mesh;
}

TestMesh fin_on_grid() {
    TestMesh mesh = grid(3, 3);
    mesh.name = "fin_on_grid";
    // The fin's tip stands above the edge's midpoint.
    const int a = grid_vertex(3, 1, 1), b = grid_vertex(3, 2, 2);
    add_vertex(mesh, 0.5 * (mesh.positions[3 * a] + mesh.positions[3 * b]),
               0.5 * (mesh.positions[3 * a + 1] + mesh.positions[3 * b + 1]), 0.4);
    add_triangle(mesh, a, b, mesh.num_vertices() - 1);
    return mesh;
}

TestMesh bowtie(int n) {
    TestMesh mesh;
    mesh.name = "bowtie" + std::to_string(n);
    add_vertex(mesh, 0, 0, 0);
    for (int side = 0; side < 2; ++side) {
        const double sign = side == 0 ? 1.0 : -1.0;
        const int first = mesh.num_vertices();
        for (int k = 0; k <= n; ++k) {
            double u = 0.5 * kPi * k / n - 0.25 * kPi;  // a quarter turn of fan on each side
            add_vertex(mesh, sign * std::cos(u), std::sin(u), 0.2 * sign * std::sin(2 * u));
        }
        for (int k = 0; k < n; ++k) add_triangle(mesh, 0, first + k, first + k + 1);
    }
    return mesh;
}

PillowOnIcosahedron pillow_on_icosahedron() {
    PillowOnIcosahedron p{icosahedron(), 0, 0};
    p.mesh.name = "pillow on an icosahedron";
    p.v = p.mesh.num_vertices(), p.apex = p.mesh.triangles[0];
    const float* at = &p.mesh.positions[3 * std::size_t(p.apex)];
    p.mesh.positions.insert(p.mesh.positions.end(),
                            {at[0] + 0.6f, at[1] + 0.2f, at[2] + 0.3f, at[0] + 0.1f, at[1] + 0.7f, at[2] - 0.2f});
    p.mesh.triangles.insert(p.mesh.triangles.end(), {p.v, p.apex, p.v + 1, p.v, p.v + 1, p.apex});
    return p;
}

void jitter(TestMesh& mesh, unsigned seed, float amount) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> offset(-amount, amount);
    for (float& p : mesh.positions) p += offset(rng);
}

void add_random_creases(TestMesh& mesh, unsigned seed, double fraction, bool semi_sharp) {
    std::mt19937 rng(seed);
    std::bernoulli_distribution take(fraction);
    for (const auto& e : unique_edges(mesh.triangles)) {
        if (!take(rng)) continue;
        mesh.add_crease(e[0], e[1], semi_sharp ? random_sharpness(rng) : kInfiniteSharpness);
    }
}

void add_random_corners(TestMesh& mesh, unsigned seed, int count, bool semi_sharp) {
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> vertex(0, mesh.num_vertices() - 1);
    std::set<int> taken(mesh.corner_vertices.begin(), mesh.corner_vertices.end());
    count = std::min(count, mesh.num_vertices() - int(taken.size()));
    while (count > 0) {
        int v = vertex(rng);
        if (!taken.insert(v).second) continue;
        mesh.add_corner(v, semi_sharp ? random_sharpness(rng) : kInfiniteSharpness);
        --count;
    }
}

void add_uvs_with_seam(TestMesh& mesh) {
    const int n = mesh.num_vertices();
    mesh.uvs.assign(4 * std::size_t(n), 0.0f);
    for (int v = 0; v < n; ++v) {
        float x = mesh.positions[3 * v], y = mesh.positions[3 * v + 1], z = mesh.positions[3 * v + 2];
        mesh.uvs[2 * v] = x + 0.3f * z;
        mesh.uvs[2 * v + 1] = y - 0.2f * z;
        // The copy used on the other side of the seam: a different value, so that a seam that is smoothed over
        // (or a corner that picks the wrong copy) shows.
        mesh.uvs[2 * (n + v)] = 2.0f + 0.5f * x;
        mesh.uvs[2 * (n + v) + 1] = 0.5f * y + 0.25f * z;
    }
    mesh.triangle_uvs.resize(mesh.triangles.size());
    for (int t = 0; t < mesh.num_triangles(); ++t) {
        double cx = 0;
        for (int k = 0; k < 3; ++k) cx += mesh.positions[3 * mesh.triangles[3 * t + k]];
        int offset = cx > 0 ? n : 0;
        for (int k = 0; k < 3; ++k) mesh.triangle_uvs[3 * t + k] = mesh.triangles[3 * t + k] + offset;
    }
}

}  // namespace loopsub::testing
