// The physical parameters of the textbook example's mechanism (symbols as in the textbook).
// Required values have no default here: the config loader (config/load_config.h) reads them
// from the config file, which is their one source.
#ifndef KANE_SIM_MODEL_MECHANISM_PARAMETERS_H
#define KANE_SIM_MODEL_MECHANISM_PARAMETERS_H

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace kane_sim {

// Viscous damping at the four joints (joint_states' names) and in parallel with the spring; all
// zero in the textbook example.
struct JointDamping {
  double crank = 0.0;    // c_O [N m s/rad] pin O: torque -c_O w1 k on rod 1
  double coupler = 0.0;  // c_A [N m s/rad] pin A: -c_A (w2 - w1) k on rod 2, the opposite on rod 1
  double slider3 = 0.0;  // c_B [N s/m] slider 3 on the rail: -c_B v_B i at B
  double slider4 = 0.0;  // c_C [N s/m] slider 4 on the rail: -c_C v_C i at C
  double spring = 0.0;  // c_S [N s/m] beside the spring: -c_S (v_C - v_B) i at C, the opposite at B

  // Every field, once: equality and any() derive from it (a damper added above and not here
  // fails test_generated_equations' every-parameter test).
  auto fields() const { return std::tie(crank, coupler, slider3, slider4, spring); }
  bool any() const {
    return std::apply([](auto... c) { return ((c != 0.0) || ...); }, fields());
  }
};

// Coulomb friction at the four joints, smoothed: F = -F_c tanh(v / v_s) against the joint's
// rate v (the same sites and rates as the dampers above). No stiction: a load below F_c does
// not hold a joint still, it lets it creep at v ~ v_s F / F_c. All zero by default.
struct JointFriction {
  double crank = 0.0;    // F_O [N m] pin O, on w1
  double coupler = 0.0;  // F_A [N m] pin A, on w2 - w1
  double slider3 = 0.0;  // F_B [N] slider 3 on the rail, on v_B
  double slider4 = 0.0;  // F_C [N] slider 4 on the rail, on v_C
  // v_s [rad/s or m/s]: below it the force grows linearly, as a damper of F_c / v_s; rk4 needs
  // that damper's rate within its stability bound (the loader's check names this key).
  double velocity_scale = 0.01;

  // Every field, once: equality derives from it (test_generated_equations' every-parameter test
  // walks the schema's physical rows and fails for a field left out here).
  auto fields() const { return std::tie(crank, coupler, slider3, slider4, velocity_scale); }
  bool any() const { return crank != 0.0 || coupler != 0.0 || slider3 != 0.0 || slider4 != 0.0; }
};

// The drive's torque-speed line (a DC motor): in the direction the crank already turns it
// delivers at most torque_limit (1 - |u1| / no_load_speed), 0 beyond the no-load speed; braking
// is limited by torque_limit only. no_load_speed 0 turns the line off (the textbook's ideal
// driver moment).
struct MotorLine {
  double torque_limit = std::numeric_limits<double>::infinity();  // [N m] stall torque
  double no_load_speed = 0.0;                                     // w0 [rad/s], 0 = off
};

// The torque M_m the drive delivers at crank speed u1 for a command (already within the torque
// limit): the command itself when the line is off or the command brakes.
inline double motorLineTorque(const MotorLine& line, double command, double u1) {
  if (line.no_load_speed <= 0.0 || command * u1 <= 0.0) return command;  // off, or braking
  const double available =
      line.torque_limit * std::max(0.0, 1.0 - std::abs(u1) / line.no_load_speed);
  return std::copysign(std::min(std::abs(command), available), command);
}

// Contact between the sliders, as impacts: when x_C - x_B closes to `gap` with the sliders
// approaching, an impulse along the rail (Kane's generalized impulses through the partial
// velocities of B and C) reverses their relative speed times `restitution` (Newton's law).
// restitution 1 is lossless; what an impact takes is dissipated energy.
struct SliderContact {
  bool enabled = false;
  // [m] x_C - x_B at touch. The robot description draws the slider blocks this tall
  // (description/body_shapes.h), so by default they touch when contact does.
  double gap = 0.07;
  double restitution = 0.5;  // e in [0, 1]: separating speed / approaching speed

  auto fields() const { return std::tie(enabled, gap, restitution); }
};

struct MechanismParameters {
  static constexpr double kUnset = std::numeric_limits<double>::quiet_NaN();

  double rod_mass = kUnset;          // m  [kg], each of rods 1 (OA) and 2 (AB)
  double rod_half_length = kUnset;   // L  [m], the rods are 2L long
  double slider3_mass = kUnset;      // M1 [kg]
  double slider4_mass = kUnset;      // M2 [kg]
  double spring_stiffness = kUnset;  // k  [N/m]
  double gravity = kUnset;           // g  [m/s^2], along +i (down)
  // I1z = I2z [kg m^2], central moment of inertia of each rod about k. A uniform slender rod 2L
  // long has m (2L)^2 / 12 (the loader's default); the textbook's script uses m L^2 / 12.
  double rod_inertia = kUnset;

  // Options beyond the textbook example, all off by default.
  // A torsional spring at pin O: -k_t (q1 - q1_0) k on rod 1 (the load list's crank_spring).
  double crank_spring_stiffness = 0.0;   // k_t [N m/rad]
  double crank_spring_rest_angle = 0.0;  // q1_0 [rad]
  JointDamping damping;
  JointFriction friction;
  MotorLine motor;
  SliderContact contact;

  static double slenderRodInertia(double mass, double half_length) {
    return mass * (2.0 * half_length) * (2.0 * half_length) / 12.0;
  }

  // Every field, once (equality derives from it: a field left out here would let a
  // reconfiguration of it go unnoticed, as a damper once ran the undamped kernel).
  auto fields() const {
    return std::tie(rod_mass, rod_half_length, slider3_mass, slider4_mass, spring_stiffness,
                    gravity, rod_inertia, crank_spring_stiffness, crank_spring_rest_angle, damping,
                    friction, motor, contact);
  }
};

inline bool operator==(const JointDamping& a, const JointDamping& b) {
  return a.fields() == b.fields();
}
inline bool operator==(const JointFriction& a, const JointFriction& b) {
  return a.fields() == b.fields();
}
// With the line off the stall torque plays no part in the physics (the command's clamp does
// that job), so two lines that are off are the same whatever their torque_limit.
inline bool operator==(const MotorLine& a, const MotorLine& b) {
  return a.no_load_speed == b.no_load_speed &&
         (a.no_load_speed == 0.0 || a.torque_limit == b.torque_limit);
}
inline bool operator==(const SliderContact& a, const SliderContact& b) {
  return a.fields() == b.fields();
}
inline bool operator==(const MechanismParameters& a, const MechanismParameters& b) {
  return a.fields() == b.fields();
}
inline bool operator!=(const MechanismParameters& a, const MechanismParameters& b) {
  return !(a == b);
}

}  // namespace kane_sim

#endif  // KANE_SIM_MODEL_MECHANISM_PARAMETERS_H
