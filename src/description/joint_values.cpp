#include "kane_sim/description/joint_values.h"

namespace kane_sim {

JointValues jointValues(const MechanismKinematics& k, const State& x, double actuator_effort) {
  const MechanismGeometry& g = k.geometry;
  const SpeedVector u = x.speeds();
  const double w1 = k.rod1.angularVelocity(u).z();
  const double w2 = k.rod2.angularVelocity(u).z();
  JointValues j;
  j.position = {g.rod1_angle, g.rod2_angle - g.rod1_angle, g.pin_b.x(), g.point_c.x()};
  j.velocity = {w1, w2 - w1, k.slider3.velocity(u).x(), k.slider4.velocity(u).x()};
  j.effort = {actuator_effort, 0.0, 0.0, 0.0};
  return j;
}

}  // namespace kane_sim
