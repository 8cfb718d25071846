#include "rules/rules.h"

#include <cmath>

namespace loopsub {

namespace {
constexpr double kPi = 3.14159265358979323846;  // M_PI is POSIX, not standard C++
}  // namespace

double loop_b(int valence) { return (3.0 + 2.0 * std::cos(2.0 * kPi / valence)) / 8.0; }
double loop_a(int valence) { return 5.0 / 8.0 - loop_b(valence) * loop_b(valence); }

}  // namespace loopsub

namespace loopsub::detail {

VertexMask smooth_vertex_mask(int valence) {
    if (valence == 0) return corner_vertex_mask();
    if (valence == 6) return {0.625, 0.0625, 0.0};
    // The seed's c0 = n / a(n) - n with ci = 1, divided by their sum n / a(n).
    const double a = loop_a(valence);
    return {1.0 - a, a / valence, 0.0};
}

VertexMask crease_vertex_mask() { return {0.75, 0.0, 0.125}; }

VertexMask corner_vertex_mask() { return {1.0, 0.0, 0.0}; }

VertexMask cone_vertex_mask(int valence) {
    if (valence == 0) return corner_vertex_mask();  // a loose vertex tagged as a cone has nothing to average
    // c0 = n / (5/8 - b(n)) - n with ci = 1: normalised, the centre keeps 3/8 + b(n).
    const double spread = 5.0 / 8.0 - loop_b(valence);
    return {1.0 - spread, spread / valence, 0.0};
}

VertexMask blend(const VertexMask& a, double weight_a, const VertexMask& b) {
    const double weight_b = 1.0 - weight_a;
    return {weight_a * a.self + weight_b * b.self, weight_a * a.ring + weight_b * b.ring,
            weight_a * a.crease + weight_b * b.crease};
}

EdgeMask crease_edge_mask() { return {0.5, 0.5, 0.0}; }

EdgeMask blend(const EdgeMask& a, double weight_a, const EdgeMask& b) {
    const double weight_b = 1.0 - weight_a;
    return {weight_a * a.a + weight_b * b.a, weight_a * a.b + weight_b * b.b, weight_a * a.wings + weight_b * b.wings};
}

EdgeMask five_three_edge_mask(bool five_on_a) {
    return five_on_a ? EdgeMask{0.625, 0.375, 0.0} : EdgeMask{0.375, 0.625, 0.0};
}

LimitMask ring_limit_mask(const VertexMask& refinement, int valence) {
    if (valence == 0) return corner_limit_mask();
    // The vertex row of the ring's subdivision matrix fixes the eigenvector: l_ring = 8 beta / 3 * l_self.
    const double scaled = 8.0 * refinement.ring / 3.0;
    const double each = scaled / (1.0 + valence * scaled);
    return {1.0 - valence * each, each, 0.0, 0.0};
}

LimitMask smooth_limit_mask(int valence) {
    if (valence == 6) return {0.5, 1.0 / 12.0, 0.0, 0.0};
    return ring_limit_mask(smooth_vertex_mask(valence), valence);
}

LimitMask crease_limit_mask() { return {4.0 / 6.0, 0.0, 1.0 / 6.0, 1.0 / 6.0}; }

LimitMask corner_limit_mask() { return {1.0, 0.0, 0.0, 0.0}; }

LimitMask hoppe94_crease_limit_mask(bool regular, double vertex_weight_a, double vertex_weight_b) {
    // Child v' = 3/4 v + 1/8 (a + b); edge points e_a = w_a v + (1 - w_a) a, e_b likewise; then the child's
    // stationary mask s_self v' + s_end (e_a + e_b).
    const double s_self = regular ? 4.0 / 6.0 : 3.0 / 5.0, s_end = regular ? 1.0 / 6.0 : 1.0 / 5.0;
    const VertexMask step = crease_vertex_mask();
    return {s_self * step.self + s_end * (vertex_weight_a + vertex_weight_b), 0.0,
            s_self * step.crease + s_end * (1.0 - vertex_weight_a),
            s_self * step.crease + s_end * (1.0 - vertex_weight_b)};
}

void smooth_tangent_weights(int valence, std::vector<float>& t1, std::vector<float>& t2) {
    t1.assign(valence, 0.0f);
    t2.assign(valence, 0.0f);
    for (int i = 0; i < valence; ++i) {
        // Valence 6 exactly as OpenSubdiv writes it (1, 1/2, sqrt(3)/2): cos(pi / 3) is not 1/2 in floating point.
        if (valence == 6) {
            static constexpr float kCos[6] = {1.0f, 0.5f, -0.5f, -1.0f, -0.5f, 0.5f};
            static constexpr float kHalfRoot3 = float(0.5 * 1.73205080756887729352);
            static constexpr float kSin[6] = {0.0f, kHalfRoot3, kHalfRoot3, 0.0f, -kHalfRoot3, -kHalfRoot3};
            t1[i] = kCos[i], t2[i] = kSin[i];
        } else {
            const double angle = 2.0 * kPi * i / valence;
            t1[i] = float(std::cos(angle)), t2[i] = float(std::sin(angle));
        }
    }
}

void side_tangent_weights(int faces, std::vector<float>& t1, std::vector<float>& t2) {
    const int points = faces + 1;  // p_0 .. p_faces, after the vertex at index 0
    t1.assign(points + 1, 0.0f);
    t2.assign(points + 1, 0.0f);
    auto p = [](int i) { return i + 1; };
    // Along the crease, from the trailing towards the leading edge.
    t1[p(0)] = 1.5f, t1[p(faces)] = -1.5f;
    // Across, into the side: by the number of interior edges (OpenSubdiv's scale factors keep the magnitudes
    // of regular and irregular cases alike; only the direction matters for a normal).
    const int interior = faces - 1;
    if (interior == 0) {
        t2[0] = -6.0f, t2[p(0)] = 3.0f, t2[p(1)] = 3.0f;
    } else if (interior == 1) {
        t2[0] = -3.0f, t2[p(1)] = 3.0f;
    } else if (interior == 2) {
        const float root3 = 1.73205080756887729352f;
        t2[0] = -root3, t2[p(0)] = t2[p(3)] = -0.5f * root3, t2[p(1)] = t2[p(2)] = root3;
    } else {
        const double theta = kPi / (interior + 1);
        t2[p(0)] = t2[p(faces)] = float(-3.0 * std::sin(theta));
        const double scale = -6.0 * (std::cos(theta) - 1.0);
        for (int i = 1; i <= interior; ++i) t2[p(i)] = float(scale * std::sin(i * theta));
    }
}

void dart_limit_masks(int valence, std::vector<double>& position, std::vector<double>& t1, std::vector<double>& t2) {
    const int n = valence, size = n + 1;
    // The subdivision matrix of the 1-ring, a row per refined point: the vertex, then the midpoint of each edge.
    std::vector<double> matrix(std::size_t(size) * size, 0.0);
    const VertexMask vertex = smooth_vertex_mask(n);
    matrix[0] = vertex.self;
    for (int i = 0; i < n; ++i) matrix[std::size_t(1 + i)] = vertex.ring;
    for (int i = 0; i < n; ++i) {
        const EdgeMask edge = i == 0 ? crease_edge_mask() : smooth_edge_mask();
        double* row = &matrix[std::size_t(1 + i) * size];
        row[0] += edge.a, row[1 + i] += edge.b;
        row[1 + (i + n - 1) % n] += edge.wings, row[1 + (i + 1) % n] += edge.wings;
    }
    auto times_matrix = [&](std::vector<double>& x) {  // x <- x S
        std::vector<double> y(std::size_t(size), 0.0);
        for (int i = 0; i < size; ++i)
            for (int j = 0; j < size; ++j) y[std::size_t(j)] += x[std::size_t(i)] * matrix[std::size_t(i) * size + j];
        x.swap(y);
    };
    // The limit: the vertex's row of S^k converges to the left eigenvector of eigenvalue 1 (its weights sum to 1).
    position.assign(std::size_t(size), 0.0);
    position[0] = 1.0;
    for (int k = 0; k < 400; ++k) times_matrix(position);
    // The tangent plane: the left invariant plane of the next two eigenvalues, by iterating a plane of weights that
    // sum to zero (no part of the limit point) from the smooth tangent masks, kept orthonormal.
    std::vector<float> c, s;
    smooth_tangent_weights(n, c, s);
    t1.assign(std::size_t(size), 0.0), t2.assign(std::size_t(size), 0.0);
    for (int i = 0; i < n; ++i) t1[std::size_t(1 + i)] = c[std::size_t(i)], t2[std::size_t(1 + i)] = s[std::size_t(i)];
    auto normalise = [&](std::vector<double>& x, const std::vector<double>* against) {
        double sum = 0.0;
        for (double w : x) sum += w;
        for (int i = 0; i < size; ++i) x[std::size_t(i)] -= sum * position[std::size_t(i)];
        if (against) {
            double dot = 0.0;
            for (int i = 0; i < size; ++i) dot += x[std::size_t(i)] * (*against)[std::size_t(i)];
            for (int i = 0; i < size; ++i) x[std::size_t(i)] -= dot * (*against)[std::size_t(i)];
        }
        double length = 0.0;
        for (double w : x) length += w * w;
        for (double& w : x) w /= std::sqrt(length);
    };
    for (int k = 0; k < 400; ++k) {
        times_matrix(t1), times_matrix(t2);
        normalise(t1, nullptr), normalise(t2, &t1);
    }
    // Oriented as the smooth masks: on a flat regular ring, counter-clockwise about +z, t1 x t2 points up.
    double a[2] = {0.0, 0.0}, b[2] = {0.0, 0.0};
    for (int i = 0; i < n; ++i) {
        const double angle = 2.0 * kPi * i / n;
        a[0] += t1[std::size_t(1 + i)] * std::cos(angle), a[1] += t1[std::size_t(1 + i)] * std::sin(angle);
        b[0] += t2[std::size_t(1 + i)] * std::cos(angle), b[1] += t2[std::size_t(1 + i)] * std::sin(angle);
    }
    if (a[0] * b[1] - a[1] * b[0] < 0.0) t1.swap(t2);
}

SdcRule sdc_vertex_rule(float vertex_sharpness, int sharp_edge_count) {
    if (is_sharp(vertex_sharpness) || sharp_edge_count > 2) return SdcRule::Corner;
    if (sharp_edge_count == 2) return SdcRule::Crease;
    return sharp_edge_count == 1 ? SdcRule::Dart : SdcRule::Smooth;
}

float decrement_sharpness(float sharpness) {
    if (is_infinite(sharpness)) return kInfiniteSharpness;
    return sharpness > 1.0f ? sharpness - 1.0f : 0.0f;
}

float chaikin_sharpness_at_vertex(float edge_sharpness, const float* incident_sharpness, int incident_count) {
    if (!is_semi_sharp(edge_sharpness)) return is_infinite(edge_sharpness) ? kInfiniteSharpness : 0.0f;
    float sharp_sum = 0.0f;
    int sharp_count = 0;
    for (int i = 0; i < incident_count; ++i) {
        if (is_semi_sharp(incident_sharpness[i])) {
            sharp_sum += incident_sharpness[i];
            ++sharp_count;
        }
    }
    if (sharp_count > 1) {
        // 3/4 of its own sharpness and 1/4 of the average of the other semi-sharp edges at the vertex.
        const float others_average = (sharp_sum - edge_sharpness) / float(sharp_count - 1);
        edge_sharpness = 0.75f * edge_sharpness + 0.25f * others_average;
    }
    edge_sharpness -= 1.0f;
    return is_sharp(edge_sharpness) ? edge_sharpness : 0.0f;
}

float transition_weight(CreaseMethod method, float parent_vertex_sharpness, float child_vertex_sharpness,
                        const float* parent_edge_sharpness, const float* child_edge_sharpness, int edge_count) {
    int count = 0;
    float sum = 0.0f;
    if (is_sharp(parent_vertex_sharpness) && !is_sharp(child_vertex_sharpness)) {
        count = 1;
        sum = parent_vertex_sharpness;
    }
    for (int i = 0; i < edge_count; ++i) {
        // Uniform decay reaches zero exactly for sharpness in (0, 1]; Chaikin has to be asked.
        const bool decays =
            method == CreaseMethod::Uniform ? parent_edge_sharpness[i] <= 1.0f : !is_sharp(child_edge_sharpness[i]);
        if (is_sharp(parent_edge_sharpness[i]) && decays) {
            sum += parent_edge_sharpness[i];
            ++count;
        }
    }
    if (count == 0) return 0.0f;
    const float weight = sum / float(count);
    return weight > 1.0f ? 1.0f : weight;
}

}  // namespace loopsub::detail
