// The servo in the crank's drive (command.mode velocity | position), as ros_control's
// velocity/position controllers would run it, without ros_control: at every physics step it
// turns the setpoint and the measured crank angle q1 and speed u1 into a motor command M_m,
// clamped to command.torque_limit. The drive's motor line then limits it at speed, as for any
// torque command. ROS-free; SimDriver owns one.
//
//   position: M_m = kp (r - q1) + I - kd u1 + f      I' = ki (r - q1)
//   velocity: M_m = kp (w - u1) + I + f              I' = ki (w - u1)
//
// f is the holding moment (command.feedforward: holding), -F_1 of gravity and the spring at the
// present configuration. The integral stops while the output is saturated in the error's
// direction (anti-windup) and never exceeds the torque limit.
#ifndef KANE_SIM_CONTROL_CRANK_SERVO_H
#define KANE_SIM_CONTROL_CRANK_SERVO_H

#include "kane_sim/config/config.h"

namespace kane_sim {

// One servo update: what it saw and what it commanded (published on servo_state).
struct ServoStatus {
  double setpoint = 0.0;      // r [rad] or w [rad/s]
  double measured = 0.0;      // q1 [rad] or u1 [rad/s]
  double error = 0.0;         // setpoint - measured
  double proportional = 0.0;  // [N m]
  double integral = 0.0;      // [N m]
  double derivative = 0.0;    // [N m] (position: -kd u1)
  double feedforward = 0.0;   // [N m]
  double output = 0.0;        // [N m] their sum, before the limit
  double command = 0.0;       // [N m] the output within ±torque_limit: the drive's M_m command
  bool saturated = false;     // |output| > torque_limit
};

class CrankServo {
 public:
  explicit CrankServo(const CommandSettings& settings) : settings_(settings) {}

  // New gains and limit (runtime reconfiguration); the integral is kept.
  void setSettings(const CommandSettings& settings) { settings_ = settings; }
  // The command at (q1, u1) for `setpoint`, with `holding` the feedforward moment when it is on.
  // dt [s] > 0 advances the integral over the step just taken; 0 only re-evaluates.
  const ServoStatus& update(double setpoint, double q1, double u1, double holding, double dt);
  void clearIntegral() { integral_ = 0.0; }
  const ServoStatus& status() const { return status_; }

  // What it remembers (the integral, the last update's status), for checkpoints.
  double integral() const { return integral_; }
  void restore(double integral, const ServoStatus& status) {
    integral_ = integral;
    status_ = status;
  }

 private:
  CommandSettings settings_;
  double integral_ = 0.0;  // [N m]
  ServoStatus status_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_CONTROL_CRANK_SERVO_H
