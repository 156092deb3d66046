// rviz markers of the mechanism: rods, pins, sliders, rail, spring zigzag and torque arrow,
// all in the `mechanism` frame with stable namespaces and ids (rviz updates, never piles up).
#ifndef KANE_SIM_ROS_MARKERS_H
#define KANE_SIM_ROS_MARKERS_H

#include <ros/time.h>
#include <visualization_msgs/MarkerArray.h>

#include "kane_sim/ros/frame_names.h"
#include "kane_sim/sim/snapshot.h"

namespace kane_sim {

struct MarkerColors {  // RGB, used by the rviz smoke test to find the mechanism on screen
  static constexpr float kRod[3] = {0.15f, 0.35f, 0.95f};   // blue
  static constexpr float kSlider[3] = {1.0f, 0.55f, 0.0f};  // orange
  static constexpr float kSpring[3] = {0.1f, 0.85f, 0.2f};  // green
  static constexpr float kTorque[3] = {0.95f, 0.1f, 0.1f};  // red
  static constexpr float kPin[3] = {0.8f, 0.8f, 0.8f};      // light grey
  static constexpr float kRail[3] = {0.45f, 0.45f, 0.45f};  // grey
};

// The torque arrow is full length (0.3 m) at snapshot.command.torque_limit.
visualization_msgs::MarkerArray mechanismMarkers(const Snapshot& snapshot, const FrameNames& frames,
                                                 const ros::Time& stamp);

}  // namespace kane_sim

#endif  // KANE_SIM_ROS_MARKERS_H
