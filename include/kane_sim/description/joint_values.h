// The mechanism seen as the robot description's four joints, in joint_states' order
// (model/joint_names.h): what joint_states carries and what the tf poses are computed from.
#ifndef KANE_SIM_DESCRIPTION_JOINT_VALUES_H
#define KANE_SIM_DESCRIPTION_JOINT_VALUES_H

#include <array>

#include "kane_sim/model/joint_names.h"
#include "kane_sim/model/mechanism_model.h"
#include "kane_sim/model/state.h"

namespace kane_sim {

struct JointValues {
  std::array<double, kNumJoints> position{};  // rad, rad, m, m
  std::array<double, kNumJoints> velocity{};  // rad/s, rad/s, m/s, m/s
  std::array<double, kNumJoints> effort{};    // N m, N m, N, N: actuator effort (only the crank)
};

// The joints at state `x` (kinematics `k` of it) with `actuator_effort` on the crank: crank q1,
// coupler -2 q1 (rod 2 relative to rod 1), slider 3 at x_B = 4 L cos q1, slider 4 at q2.
JointValues jointValues(const MechanismKinematics& k, const State& x, double actuator_effort);

// The state a reading of the joints gives: q1, u1 from the crank, q2, u2 from slider 4 (what a
// state-feedback controller reads of joint_states).
inline State stateFromJoints(const JointValues& j) {
  return {j.position[kCrankJoint], j.position[kSlider4Joint], j.velocity[kCrankJoint],
          j.velocity[kSlider4Joint]};
}

}  // namespace kane_sim

#endif  // KANE_SIM_DESCRIPTION_JOINT_VALUES_H
