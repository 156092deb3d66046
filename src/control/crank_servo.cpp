#include "kane_sim/control/crank_servo.h"

#include <algorithm>
#include <cmath>

namespace kane_sim {

const ServoStatus& CrankServo::update(double setpoint, double q1, double u1, double holding,
                                      double dt) {
  const bool position = settings_.mode == CommandMode::kPosition;
  const double limit = settings_.torque_limit;
  ServoStatus& s = status_;
  s.setpoint = setpoint;
  s.measured = position ? q1 : u1;
  s.error = setpoint - s.measured;
  const double kp = position ? settings_.position_kp : settings_.velocity_kp;
  const double ki = position ? settings_.position_ki : settings_.velocity_ki;
  s.proportional = kp * s.error;
  s.derivative = position ? -settings_.position_kd * u1 : 0.0;
  s.feedforward = settings_.feedforward == Feedforward::kHolding ? holding : 0.0;
  if (dt > 0.0) {
    // Anti-windup: no integration that would push an output already at the limit further.
    const bool pushing_saturated =
        s.saturated && ((s.output > 0) == (s.error > 0)) && s.error != 0.0;
    if (!pushing_saturated) integral_ += ki * s.error * dt;
    integral_ = std::clamp(integral_, -limit, limit);
  }
  s.integral = integral_;
  s.output = s.proportional + s.integral + s.derivative + s.feedforward;
  s.saturated = std::abs(s.output) > limit;
  s.command = std::clamp(s.output, -limit, limit);
  return s;
}

}  // namespace kane_sim
