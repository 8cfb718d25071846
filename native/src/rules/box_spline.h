// The Loop surface over a regular triangle: the quartic three-direction box spline of its 12 control points (Stam,
// "Evaluation of Loop Subdivision Surfaces", 1998), what Loop subdivision converges to where every vertex around the
// triangle is smooth with six neighbours. No mesh here: the caller gathers the 12 points in this order,
//
//          P0    P1
//       P2    P3    P4
//    P5    P6    P7    P8
//       P9    P10   P11
//
// the triangle being (P3, P6, P7), counter-clockwise. A point of it is P3 + v (P6 - P3) + w (P7 - P3).
#pragma once

namespace loopsub::detail {

inline constexpr int kBoxSplinePoints = 12;

// The weights of the 12 points at (v, w), v, w >= 0, v + w <= 1, and of the derivatives along v and w.
void box_spline_weights(double v, double w, double weights[kBoxSplinePoints], double dv[kBoxSplinePoints],
                        double dw[kBoxSplinePoints]);

}  // namespace loopsub::detail
