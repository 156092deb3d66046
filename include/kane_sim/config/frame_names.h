// The tf frame ids (= URDF link names) of the mechanism, with the configured prefix: the names
// the frames section gives (the loader refuses a world frame named like one of them).
#ifndef KANE_SIM_CONFIG_FRAME_NAMES_H
#define KANE_SIM_CONFIG_FRAME_NAMES_H

#include <array>
#include <string>

#include "kane_sim/config/config.h"
#include "kane_sim/model/mechanism_model.h"

namespace kane_sim {

struct FrameNames {
  std::string world;      // REP-105 world frame, z up; shared by instances, never prefixed
  std::string mechanism;  // the textbook's frame (0): x down, origin at O (the robot's base)
  // Link frames in Body order: rod1 and rod2 at their inboard pins O and A with x along the
  // rod; slider3 at B and slider4 at C with the mechanism's axes.
  std::array<std::string, kNumBodies> bodies;

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

#endif  // KANE_SIM_CONFIG_FRAME_NAMES_H
