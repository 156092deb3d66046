// The tf frame ids the mechanism publishes, with the configured prefix.
#ifndef KANE_SIM_ROS_FRAME_NAMES_H
#define KANE_SIM_ROS_FRAME_NAMES_H

#include <array>
#include <string>

#include "kane_sim/config/config.h"
#include "kane_sim/model/mechanism_model.h"

namespace kane_sim {

struct FrameNames {
  std::string world;      // REP-105 world frame, z up; shared by instances, never prefixed
  std::string mechanism;  // the textbook's frame (0): x down, origin at O
  std::array<std::string, kNumBodies> bodies;  // rod1, rod2, slider3, slider4 (mass centers)

  // "robot1" and "robot1/" both give "robot1/rod1"; "" gives "rod1".
  explicit FrameNames(const FrameSettings& settings) {
    std::string prefix = settings.prefix;
    if (!prefix.empty() && prefix.back() != '/') prefix += '/';
    world = settings.world;
    mechanism = prefix + "mechanism";
    bodies = {prefix + "rod1", prefix + "rod2", prefix + "slider3", prefix + "slider4"};
  }
};

}  // namespace kane_sim

#endif  // KANE_SIM_ROS_FRAME_NAMES_H
