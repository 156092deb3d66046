// The drawn and collision shapes of the bodies: one set of sizes for the URDF (RobotModel in
// rviz, collision geometry) and the rviz markers. The physics treats the rods as slender
// (only I1z = I2z matters) and the sliders as particles; these sizes are for looking at them.
#ifndef KANE_SIM_DESCRIPTION_BODY_SHAPES_H
#define KANE_SIM_DESCRIPTION_BODY_SHAPES_H

#include "kane_sim/model/mechanism_parameters.h"

namespace kane_sim {
namespace shapes {

constexpr double kRodDiameter = 0.03;   // [m] the rods are cylinders 2L long
constexpr double kPinDiameter = 0.045;  // [m] spheres at O, A, B (markers only)
// The sliders are boxes centred on B and C: along the rail (the mechanism's x), across it in
// the plane (y) and out of the plane (z).
// [m] along the rail: as tall as contact's default gap, so drawn blocks touch when the sliders do.
constexpr double kSliderLength = SliderContact{}.gap;
constexpr double kSliderWidth = 0.12;  // [m]
constexpr double kSliderDepth = 0.06;  // [m]

}  // namespace shapes

// RGB of the bodies (URDF materials) and the markers; the rviz smoke test looks for them.
struct MarkerColors {
  static constexpr float kRod[3] = {0.15f, 0.35f, 0.95f};     // blue
  static constexpr float kSlider[3] = {1.0f, 0.55f, 0.0f};    // orange
  static constexpr float kSpring[3] = {0.1f, 0.85f, 0.2f};    // green
  static constexpr float kTorque[3] = {0.95f, 0.1f, 0.1f};    // red
  static constexpr float kPin[3] = {0.8f, 0.8f, 0.8f};        // light grey
  static constexpr float kRail[3] = {0.45f, 0.45f, 0.45f};    // grey
  static constexpr float kSetpoint[3] = {1.0f, 0.85f, 0.1f};  // yellow: the crank_marker arrow
};

}  // namespace kane_sim

#endif  // KANE_SIM_DESCRIPTION_BODY_SHAPES_H
