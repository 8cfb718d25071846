// The limit at OpenSubdiv's darts and infinitely sharp corners, where neither Far::PrimvarRefiner::Limit (the smooth
// masks at a dart) nor Bfr (its tangent plane 10 levels down, not yet converged) gives the true limit to 1e-3 rad: the
// limit's own definitions. At a dart, the limit point and tangent plane are the dominant left eigenvector and the next
// left invariant plane of the 1-ring's subdivision matrix; at a corner each sharp edge's limit curve leaves the vertex
// along the edge, so a side's tangent plane holds both its sharp edges.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <vector>

#include "loopsub/loopsub.h"
#include "mesh_gen.h"
#include "rules/rules.h"

namespace loopsub::testing {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Loop's subdivision of a dart's 1-ring, written from the rules (docs/rules.md): the vertex by Loop's smooth mask
// (beta = (5/8 - (3/8 + cos(2 pi / n) / 4)^2) / n, 1/16 at valence 6), the sharp edge to p_0 by its midpoint, every
// other edge by {3, 3, 1, 1} / 8.
std::vector<double> dart_subdivision(int n) {
    const double beta = n == 6 ? 1.0 / 16.0 : (0.625 - std::pow(0.375 + 0.25 * std::cos(2.0 * kPi / n), 2)) / n;
    const int size = n + 1;
    std::vector<double> s(std::size_t(size * size), 0.0);
    s[0] = 1.0 - n * beta;
    for (int i = 0; i < n; ++i) s[std::size_t(1 + i)] = beta;
    for (int i = 0; i < n; ++i) {
        double* row = &s[std::size_t((1 + i) * size)];
        if (i == 0) {
            row[0] = row[1] = 0.5;
            continue;
        }
        row[0] += 0.375, row[1 + i] += 0.375, row[1 + (i + n - 1) % n] += 0.125, row[1 + (i + 1) % n] += 0.125;
    }
    return s;
}

std::vector<double> times(const std::vector<double>& x, const std::vector<double>& s) {
    const std::size_t size = x.size();
    std::vector<double> y(size, 0.0);
    for (std::size_t i = 0; i < size; ++i)
        for (std::size_t j = 0; j < size; ++j) y[j] += x[i] * s[i * size + j];
    return y;
}

TEST(DartLimitMasks, AreTheLeftEigenvectorsOfTheDartsSubdivision) {
    for (int n = 3; n <= 12; ++n) {
        std::vector<double> position, t1, t2;
        detail::dart_limit_masks(n, position, t1, t2);
        const std::vector<double> s = dart_subdivision(n);
        // The limit point: fixed by the subdivision, weights summing to one.
        const std::vector<double> moved = times(position, s);
        double sum = 0.0;
        for (int i = 0; i <= n; ++i) EXPECT_NEAR(moved[std::size_t(i)], position[std::size_t(i)], 1e-12) << n;
        for (double w : position) sum += w;
        EXPECT_NEAR(sum, 1.0, 1e-12) << n;
        // The tangents: a plane of weights that the subdivision maps into itself, away from the limit point (each
        // sums to zero), and not the smooth masks' (the dart turns it).
        for (const std::vector<double>* t : {&t1, &t2}) {
            std::vector<double> image = times(*t, s);
            double a = 0.0, b = 0.0, aa = 0.0, bb = 0.0, ab = 0.0, total = 0.0;
            for (int i = 0; i <= n; ++i) {
                a += image[std::size_t(i)] * t1[std::size_t(i)], b += image[std::size_t(i)] * t2[std::size_t(i)];
                aa += t1[std::size_t(i)] * t1[std::size_t(i)], bb += t2[std::size_t(i)] * t2[std::size_t(i)];
                ab += t1[std::size_t(i)] * t2[std::size_t(i)], total += (*t)[std::size_t(i)];
            }
            // Least squares in the plane of t1 and t2: what is left over must vanish.
            const double det = aa * bb - ab * ab, x = (a * bb - b * ab) / det, y = (b * aa - a * ab) / det;
            double residual = 0.0;
            for (int i = 0; i <= n; ++i)
                residual += std::pow(image[std::size_t(i)] - x * t1[std::size_t(i)] - y * t2[std::size_t(i)], 2);
            EXPECT_LT(std::sqrt(residual), 1e-10) << n;
            EXPECT_NEAR(total, 0.0, 1e-12) << n;
        }
        // Outward: on a flat ring counter-clockwise about +z, t1 x t2 points up.
        double u[2] = {0.0, 0.0}, v[2] = {0.0, 0.0};
        for (int i = 0; i < n; ++i) {
            const double angle = 2.0 * kPi * i / n;
            u[0] += t1[std::size_t(1 + i)] * std::cos(angle), u[1] += t1[std::size_t(1 + i)] * std::sin(angle);
            v[0] += t2[std::size_t(1 + i)] * std::cos(angle), v[1] += t2[std::size_t(1 + i)] * std::sin(angle);
        }
        EXPECT_GT(u[0] * v[1] - u[1] * v[0], 0.0) << n;
    }
}

TEST(CornerLimitNormals, HoldBothSharpEdgesOfTheirSide) {
    // A bent grid with a crease across it from boundary to boundary: its ends are corners (two boundary edges and the
    // crease), each with sides of one and two faces; and a tagged corner inside the crease.
    TestMesh mesh = grid(6, 5);
    jitter(mesh, 254, 0.05f);
    for (int i = 0; i < 6; ++i) mesh.add_crease(grid_vertex(6, i, 2), grid_vertex(6, i + 1, 2));
    mesh.add_corner(grid_vertex(6, 3, 2));
    for (int levels = 0; levels <= 2; ++levels) {
        Options options;
        options.rules = Rules::OpenSubdiv;
        options.levels = levels;
        options.limit_surface = true;
        Plan plan(mesh.view(), options);
        std::vector<float> points(3 * std::size_t(plan.num_output_vertices()));
        std::vector<float> normals(9 * std::size_t(plan.num_output_triangles()));
        std::vector<float> limit_points(points.size());
        plan.evaluate(interleaved(mesh.positions.data(), 3), interleaved(limit_points.data(), 3), normals.data());
        // The control points of the level (the limit curve leaves a corner along the edge between them).
        options.limit_surface = false;
        Plan control(mesh.view(), options);
        control.evaluate(interleaved(mesh.positions.data(), 3), interleaved(points.data(), 3));
        // Each corner of a triangle at a corner vertex: its side's sharp edges are the mesh's sharp edges there; the
        // triangle's own edges at the vertex that are sharp must be perpendicular to its normal, and the normal must
        // face the way the triangle does.
        const std::vector<VertexType>& types = plan.level_vertex_types(levels);
        std::set<std::pair<int, int>> sharp;
        const auto& pairs = plan.output_sharp_edges();
        for (std::size_t k = 0; k + 1 < pairs.size(); k += 2) sharp.insert(std::minmax(pairs[k], pairs[k + 1]));
        const std::int32_t* t = plan.output_triangles();
        int checked = 0;
        for (int c = 0; c < 3 * plan.num_output_triangles(); ++c) {
            const int v = t[c];
            if (types[std::size_t(v)] != VertexType::Corner) continue;
            const int face = c / 3, k = c % 3;
            const float* n = &normals[3 * std::size_t(c)];
            const float* p = &points[3 * std::size_t(v)];
            double facing[3];
            {
                const float *a = &points[3 * std::size_t(t[3 * face + (k + 1) % 3])],
                            *b = &points[3 * std::size_t(t[3 * face + (k + 2) % 3])];
                const double e[3] = {a[0] - p[0], a[1] - p[1], a[2] - p[2]},
                             f[3] = {b[0] - p[0], b[1] - p[1], b[2] - p[2]};
                facing[0] = e[1] * f[2] - e[2] * f[1], facing[1] = e[2] * f[0] - e[0] * f[2],
                facing[2] = e[0] * f[1] - e[1] * f[0];
            }
            EXPECT_GT(n[0] * facing[0] + n[1] * facing[1] + n[2] * facing[2], 0.0) << "corner " << c;
            for (int j : {1, 2}) {
                const int w = t[3 * face + (k + j) % 3];
                if (!sharp.count(std::minmax(v, w))) continue;
                // The limit curve of a sharp edge at a corner leaves along the edge of the control points.
                const float* q = &points[3 * std::size_t(w)];
                double d[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]}, length = 0.0, dot = 0.0;
                for (int x = 0; x < 3; ++x) length += d[x] * d[x];
                for (int x = 0; x < 3; ++x) dot += n[x] * d[x] / std::sqrt(length);
                EXPECT_NEAR(dot, 0.0, 1e-5) << "level " << levels << ", corner " << c << " (vertex " << v << ")";
                ++checked;
            }
        }
        EXPECT_GT(checked, 0);
    }
}

}  // namespace
}  // namespace loopsub::testing
