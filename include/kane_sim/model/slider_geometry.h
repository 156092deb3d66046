// Where the sliders are along the rail, from (q1, q2) alone: plain functions of doubles, no
// Eigen, so the SIMD lanes (batch/) can use them from code built for another instruction set.
#ifndef KANE_SIM_MODEL_SLIDER_GEOMETRY_H
#define KANE_SIM_MODEL_SLIDER_GEOMETRY_H

#include <cmath>

#include "kane_sim/model/math_functions.h"

namespace kane_sim {

// x_B = 4 L cos q1 [m]: slider 3 on the rail, where rod 2's end B is (the loop's closure).
inline double slider3Position(double rod_half_length, double cos_q1) {
  return 4 * rod_half_length * cos_q1;
}
// x_C - x_B [m] without the rest of the geometry (one cosine): the simulator's per-step checks.
inline double sliderSeparation(double rod_half_length, double q1, double q2) {
  return q2 - slider3Position(rod_half_length, math::cos(q1));
}

// x_C - x_B >= threshold. x_C - x_B = q2 - 4L cos q1 lies within q2 -+ 4L: those bounds settle
// most calls (slider 4 hangs below the crank's reach) without the cosine, which costs as much as
// an rk4 stage's. One test for the single simulator and the lanes (the crossing counter).
inline bool sliderSeparationAtLeast(double rod_half_length, double q1, double q2,
                                    double threshold) {
  const double reach = slider3Position(rod_half_length, 1.0);  // |x_B| <= 4L
  if (q2 - reach >= threshold) return true;
  if (q2 + reach < threshold) return false;
  return sliderSeparation(rod_half_length, q1, q2) >= threshold;
}

}  // namespace kane_sim

#endif  // KANE_SIM_MODEL_SLIDER_GEOMETRY_H
