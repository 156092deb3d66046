// The example controller's law, ROS-free: M_m = kp (q1_setpoint - q1) - kd u1, clamped.
#ifndef KANE_SIM_EXAMPLES_PD_LAW_H
#define KANE_SIM_EXAMPLES_PD_LAW_H

#include <algorithm>

namespace kane_sim {

struct PdGains {
  double kp = 500.0;           // [N m / rad]
  double kd = 30.0;            // [N m s / rad]
  double torque_limit = 50.0;  // [N m]
};

inline double pdTorque(const PdGains& gains, double setpoint, double q1, double u1) {
  const double torque = gains.kp * (setpoint - q1) - gains.kd * u1;
  return std::clamp(torque, -gains.torque_limit, gains.torque_limit);
}

}  // namespace kane_sim

#endif  // KANE_SIM_EXAMPLES_PD_LAW_H
