// The mechanism seen as four joints (sensor_msgs/JointState order), from the model's own
// kinematics so that no formula is written twice.
#ifndef KANE_SIM_JOINT_VALUES_H
#define KANE_SIM_JOINT_VALUES_H

#include <array>

#include "kane_sim/mechanism_model.h"

namespace kane_sim {

enum Joint {
  kCrankJoint = 0,
  kCouplerJoint = 1,
  kSlider3Joint = 2,
  kSlider4Joint = 3,
  kNumJoints = 4
};

constexpr std::array<const char*, kNumJoints> kJointNames = {"crank_joint", "coupler_joint",
                                                             "slider3_joint", "slider4_joint"};

struct JointValues {
  std::array<double, kNumJoints> position{};  // rad, rad, m, m
  std::array<double, kNumJoints> velocity{};  // rad/s, rad/s, m/s, m/s
  std::array<double, kNumJoints> effort{};    // N m, N m, N, N: actuator effort (only the crank)
};

// crank_joint: rod 1 about O (q1, u1; effort M_m). coupler_joint: rod 2 relative to rod 1
// about A (-2 q1). slider3_joint: x of B. slider4_joint: x of C (q2, u2). The passive joints
// report effort 0.
inline JointValues jointValues(const MechanismModel& model, const State& x, double motor_torque) {
  const MechanismGeometry g = model.geometry(x.q1, x.q2);
  const MechanismModel::Bodies b = model.bodies(x, motor_torque);
  const SpeedVector u = x.speeds();
  JointValues j;
  j.position = {g.rod1_angle, g.rod2_angle - g.rod1_angle, g.pin_b.x(), g.point_c.x()};
  j.velocity = {b[kRod1].angularVelocity(u).z(),
                b[kRod2].angularVelocity(u).z() - b[kRod1].angularVelocity(u).z(),
                b[kSlider3].velocity(u).x(), b[kSlider4].velocity(u).x()};
  j.effort = {motor_torque, 0.0, 0.0, 0.0};
  return j;
}

}  // namespace kane_sim

#endif  // KANE_SIM_JOINT_VALUES_H
