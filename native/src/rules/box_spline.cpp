#include "rules/box_spline.h"

namespace loopsub::detail {

namespace {

// The basis functions as quartic forms in the barycentric coordinates (u, v, w), u = 1 - v - w: twelve times the
// coefficient of each monomial u^a v^b w^c, the monomials in kExponents' order.
constexpr int kMonomials = 15;
constexpr int kExponents[kMonomials][3] = {{4, 0, 0}, {3, 1, 0}, {3, 0, 1}, {2, 2, 0}, {2, 1, 1},
                                           {2, 0, 2}, {1, 3, 0}, {1, 2, 1}, {1, 1, 2}, {1, 0, 3},
                                           {0, 4, 0}, {0, 3, 1}, {0, 2, 2}, {0, 1, 3}, {0, 0, 4}};
constexpr int kCoefficients[kBoxSplinePoints][kMonomials] = {
    {1, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0},         {1, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0},
    {1, 6, 2, 12, 6, 0, 6, 6, 0, 0, 1, 2, 0, 0, 0},        {6, 24, 24, 24, 60, 24, 8, 36, 36, 8, 1, 6, 12, 6, 1},
    {1, 2, 6, 0, 6, 12, 0, 0, 6, 6, 0, 0, 0, 2, 1},        {0, 0, 0, 0, 0, 0, 2, 0, 0, 0, 1, 0, 0, 0, 0},
    {1, 8, 6, 24, 36, 12, 24, 60, 36, 6, 6, 24, 24, 8, 1}, {1, 6, 8, 12, 36, 24, 6, 36, 60, 24, 1, 8, 24, 24, 6},
    {0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1},         {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 2, 0, 0, 0},
    {0, 0, 0, 0, 0, 0, 2, 6, 6, 2, 1, 6, 12, 6, 1},        {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 1},
};

double power(double x, int n) {
    double p = 1.0;
    for (int i = 0; i < n; ++i) p *= x;
    return p;
}

}  // namespace

void box_spline_weights(double v, double w, double weights[kBoxSplinePoints], double dv[kBoxSplinePoints],
                        double dw[kBoxSplinePoints]) {
    const double coordinates[3] = {1.0 - v - w, v, w};
    double value[kMonomials], partial[kMonomials][3];  // each monomial and its partials in u, v, w
    for (int m = 0; m < kMonomials; ++m) {
        value[m] = 1.0;
        for (int c = 0; c < 3; ++c) value[m] *= power(coordinates[c], kExponents[m][c]);
        for (int d = 0; d < 3; ++d) {
            const int n = kExponents[m][d];
            double p = n;
            for (int c = 0; c < 3; ++c) p *= power(coordinates[c], kExponents[m][c] - (c == d && n > 0));
            partial[m][d] = n > 0 ? p : 0.0;
        }
    }
    for (int i = 0; i < kBoxSplinePoints; ++i) {
        double sum = 0.0, sum_v = 0.0, sum_w = 0.0;
        for (int m = 0; m < kMonomials; ++m) {
            const double c = kCoefficients[i][m];
            sum += c * value[m];
            sum_v += c * (partial[m][1] - partial[m][0]);  // moving along v takes from u
            sum_w += c * (partial[m][2] - partial[m][0]);
        }
        weights[i] = sum / 12.0, dv[i] = sum_v / 12.0, dw[i] = sum_w / 12.0;
    }
}

}  // namespace loopsub::detail
