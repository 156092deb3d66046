// Functions of the mechanism's parameters that are not the equations of motion: the rods'
// default inertia and the drive's torque-speed line (MechanismParameters itself is generated
// from codegen/parameters.yaml into model/mechanism_parameters.h).
#ifndef KANE_SIM_MODEL_MECHANISM_LAWS_H
#define KANE_SIM_MODEL_MECHANISM_LAWS_H

#include <algorithm>
#include <cmath>

#include "kane_sim/model/mechanism_parameters.h"

namespace kane_sim {

// I1z = I2z of a uniform slender rod 2L long: m (2L)^2 / 12 (the loader's default; the
// textbook's script uses m L^2 / 12).
inline double slenderRodInertia(double mass, double half_length) {
  return mass * (2.0 * half_length) * (2.0 * half_length) / 12.0;
}

// The torque M_m the drive delivers at crank speed u1 for a command (already within the torque
// limit): the command itself when the line is off or the command brakes.
inline double motorLineTorque(const MotorLine& line, double command, double u1) {
  if (line.no_load_speed <= 0.0 || command * u1 <= 0.0) return command;  // off, or braking
  const double available =
      line.torque_limit * std::max(0.0, 1.0 - std::abs(u1) / line.no_load_speed);
  return std::copysign(std::min(std::abs(command), available), command);
}

// d(motorLineTorque)/d(command) and d/d(u1) at (command, u1): (1, 0) where the line passes the
// command (off, braking, or below what is available), (0, the line's slope) where it limits it.
// Each side decided as motorLineTorque decides it (the corner |command| = available passes).
struct MotorLineSlopes {
  double per_command = 1.0;
  double per_speed = 0.0;  // [N m s/rad]
};
inline MotorLineSlopes motorLineSlopes(const MotorLine& line, double command, double u1) {
  if (line.no_load_speed <= 0.0 || command * u1 <= 0.0) return {};
  const double fraction = 1.0 - std::abs(u1) / line.no_load_speed;
  if (!(line.torque_limit * std::max(0.0, fraction) < std::abs(command))) return {};
  const double slope = fraction > 0.0 ? -line.torque_limit / line.no_load_speed : 0.0;
  return {0.0, std::copysign(1.0, command) * std::copysign(1.0, u1) * slope};
}

}  // namespace kane_sim

#endif  // KANE_SIM_MODEL_MECHANISM_LAWS_H
