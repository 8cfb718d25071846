#include "topology/tessellation_pattern.h"

#include <vector>

namespace loopsub::detail {

namespace {

// Each lattice point (b1, b2) of rate n, b1 + b2 <= n, to its index among the face's points.
class Lattice {
public:
    Lattice(const int rates[3], int n, int first_inner) : n_(n), index_(std::size_t(n + 1) * (n + 1), -1) {
        at(0, 0) = 0, at(n, 0) = 1, at(0, n) = 2;
        if (rates[0] == n && rates[1] == n && rates[2] == n)
            for (int i = 1; i < n; ++i) {
                at(i, 0) = first_edge_point(rates, 0) + i - 1;      // edge 0, point i: (i, 0)
                at(n - i, i) = first_edge_point(rates, 1) + i - 1;  // edge 1: (n - i, i)
                at(0, n - i) = first_edge_point(rates, 2) + i - 1;  // edge 2: (0, n - i)
            }
        int next = first_inner;
        for (int b2 = 1; b2 < n; ++b2)
            for (int b1 = 1; b1 + b2 < n; ++b1) at(b1, b2) = next++;
    }
    std::int32_t& at(int b1, int b2) { return index_[std::size_t(b2) * (n_ + 1) + b1]; }

private:
    int n_;
    std::vector<std::int32_t> index_;
};

void add_triangle(FacePattern& out, int a, int b, int c) {
    out.triangles.push_back(a), out.triangles.push_back(b), out.triangles.push_back(c);
}

}  // namespace

void tessellate_triangle(const int rates[3], int inner_rate, FacePattern& out) {
    const int n = inner_rate;
    out.points.clear(), out.triangles.clear();
    out.points.push_back({0, 0, 1}), out.points.push_back({1, 0, 1}), out.points.push_back({0, 1, 1});
    for (int k = 0; k < 3; ++k) {
        const int r = rates[k];
        for (int i = 1; i < r; ++i) {
            if (k == 0) out.points.push_back({i, 0, r});
            if (k == 1) out.points.push_back({r - i, i, r});
            if (k == 2) out.points.push_back({0, r - i, r});
        }
    }
    const int first_inner = int(out.points.size());
    for (int b2 = 1; b2 < n; ++b2)
        for (int b1 = 1; b1 + b2 < n; ++b1) out.points.push_back({b1, b2, n});
    const bool uniform = rates[0] == n && rates[1] == n && rates[2] == n;
    Lattice lattice(rates, n, first_inner);
    if (uniform) {
        for (int b2 = 0; b2 < n; ++b2)
            for (int b1 = 0; b1 + b2 < n; ++b1) {
                add_triangle(out, lattice.at(b1, b2), lattice.at(b1 + 1, b2), lattice.at(b1, b2 + 1));
                if (b1 + b2 + 1 < n)
                    add_triangle(out, lattice.at(b1 + 1, b2), lattice.at(b1 + 1, b2 + 1), lattice.at(b1, b2 + 1));
            }
        return;
    }
    // The inner lattice, then a strip per edge between the edge's points and the inner ring's side along it.
    std::vector<std::int32_t> ring[3];
    double ring_place[3][2];  // where along its edge the first and last point of each side lie
    if (n >= 3) {
        for (int b2 = 1; b2 + 2 < n; ++b2)
            for (int b1 = 1; b1 + b2 + 2 <= n; ++b1) {
                add_triangle(out, lattice.at(b1, b2), lattice.at(b1 + 1, b2), lattice.at(b1, b2 + 1));
                if (b1 + b2 + 3 <= n)
                    add_triangle(out, lattice.at(b1 + 1, b2), lattice.at(b1 + 1, b2 + 1), lattice.at(b1, b2 + 1));
            }
        for (int j = 1; j <= n - 2; ++j) {
            ring[0].push_back(lattice.at(j, 1));          // b2 = 1, from corner 0's side to corner 1's
            ring[1].push_back(lattice.at(n - 1 - j, j));  // b0 = 1, from corner 1's side to corner 2's
            ring[2].push_back(lattice.at(1, n - 1 - j));  // b1 = 1, from corner 2's side to corner 0's
        }
        for (auto& place : ring_place) place[0] = 1.5 / n, place[1] = 1.0 - 1.5 / n;
    } else {
        const int centre = int(out.points.size());
        out.points.push_back({1, 1, 3});
        for (int k = 0; k < 3; ++k) ring[k] = {centre}, ring_place[k][0] = ring_place[k][1] = 0.5;
    }
    for (int k = 0; k < 3; ++k) {
        const int r = rates[k];
        std::vector<std::int32_t> edge;  // the edge's points, corner k to corner k + 1
        edge.push_back(k);
        for (int i = 1; i < r; ++i) edge.push_back(first_edge_point(rates, k) + i - 1);
        edge.push_back((k + 1) % 3);
        const std::vector<std::int32_t>& side = ring[k];
        const int m = int(side.size()) - 1;
        auto inner_place = [&](int j) {
            return m == 0 ? ring_place[k][0] : ring_place[k][0] + (ring_place[k][1] - ring_place[k][0]) * j / m;
        };
        int i = 0, j = 0;
        while (i < r || j < m) {
            const bool outer = j == m || (i < r && double(i + 1) / r <= inner_place(j + 1));
            if (outer) {
                add_triangle(out, edge[i], edge[i + 1], side[j]);
                ++i;
            } else {
                add_triangle(out, edge[i], side[j + 1], side[j]);
                ++j;
            }
        }
    }
}

}  // namespace loopsub::detail
