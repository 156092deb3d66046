// The mechanism's four joints and their names: joint_states', the robot description's and the
// damping section's keys (config/parameter_schema.cpp) are these. The values the robot
// description gives them are description/joint_values.h.
#ifndef KANE_SIM_MODEL_JOINT_NAMES_H
#define KANE_SIM_MODEL_JOINT_NAMES_H

#include <array>

namespace kane_sim {

enum Joint {
  kCrankJoint = 0,    // rod 1 about O: q1
  kCouplerJoint = 1,  // rod 2 relative to rod 1 about A: -2 q1
  kSlider3Joint = 2,  // x of B: 4 L cos q1
  kSlider4Joint = 3,  // x of C: q2
  kNumJoints = 4
};

constexpr std::array<const char*, kNumJoints> kJointNames = {"crank_joint", "coupler_joint",
                                                             "slider3_joint", "slider4_joint"};

}  // namespace kane_sim

#endif  // KANE_SIM_MODEL_JOINT_NAMES_H
