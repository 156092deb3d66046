// The mechanism seen as four joints, in sensor_msgs/JointState order.
#ifndef KANE_SIM_MODEL_JOINT_VALUES_H
#define KANE_SIM_MODEL_JOINT_VALUES_H

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

struct JointValues {
  std::array<double, kNumJoints> position{};  // rad, rad, m, m
  std::array<double, kNumJoints> velocity{};  // rad/s, rad/s, m/s, m/s
  std::array<double, kNumJoints> effort{};    // N m, N m, N, N: actuator effort (only the crank)
};

}  // namespace kane_sim

#endif  // KANE_SIM_MODEL_JOINT_VALUES_H
