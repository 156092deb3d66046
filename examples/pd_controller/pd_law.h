// The example controller's law, ROS-free: M_m = kp e - kd u1 + ki ∫e dt, clamped, with
// e = q1_setpoint - q1. The integral term (ki 0 by default: a PD) is the state a controller must
// clear when the simulator moves the mechanism (kane_sim_node's ~reset_event).
#ifndef KANE_SIM_EXAMPLES_PD_LAW_H
#define KANE_SIM_EXAMPLES_PD_LAW_H

#include <algorithm>

namespace kane_sim {

struct PdGains {
  double kp = 500.0;           // [N m / rad]
  double kd = 30.0;            // [N m s / rad]
  double torque_limit = 50.0;  // [N m]
  double ki = 0.0;             // [N m / (rad s)] integral gain; 0 = a PD
};

// ∫e dt over the controller's samples, held so that ki ∫e stays within the torque limit (no
// wind-up while the drive saturates or the crank is held).
class IntegralTerm {
 public:
  // Adds e over dt [s] (a sample interval; non-positive or over 1 s is a gap: nothing added).
  void add(const PdGains& gains, double error, double dt) {
    if (!(dt > 0.0 && dt <= 1.0) || gains.ki <= 0.0) return;
    const double bound = gains.torque_limit / gains.ki;
    integral_ = std::clamp(integral_ + error * dt, -bound, bound);
  }
  void clear() { integral_ = 0.0; }
  double value() const { return integral_; }  // [rad s]

 private:
  double integral_ = 0.0;
};

inline double pdTorque(const PdGains& gains, double setpoint, double q1, double u1,
                       double integral = 0.0) {
  const double torque = gains.kp * (setpoint - q1) - gains.kd * u1 + gains.ki * integral;
  return std::clamp(torque, -gains.torque_limit, gains.torque_limit);
}

}  // namespace kane_sim

#endif  // KANE_SIM_EXAMPLES_PD_LAW_H
