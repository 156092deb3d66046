// Everything config/mechanism.yaml holds, as plain structs. The node (through rosparam), the
// offline tools and the tests all read it through load_config.h, so the defaults below are the
// single source of the optional values.
#ifndef KANE_SIM_CONFIG_H
#define KANE_SIM_CONFIG_H

#include <string>

#include "kane_sim/state.h"

namespace kane_sim {

struct MechanismParameters {
  double rod_mass = 1.0;          // m  [kg], each of rods 1 and 2
  double rod_half_length = 0.25;  // L  [m], the rods are 2L long
  double slider3_mass = 0.5;      // M1 [kg]
  double slider4_mass = 0.8;      // M2 [kg]
  double spring_stiffness = 200;  // k  [N/m]
  double gravity = 9.81;          // g  [m/s^2], along +i (down)
  // I1z = I2z [kg m^2], central moment of inertia of each rod about k. A uniform slender rod 2L
  // long has m (2L)^2 / 12; the seed's script uses m L^2 / 12 (config/textbook.yaml).
  double rod_inertia = 1.0 * 0.5 * 0.5 / 12.0;

  static double slenderRodInertia(double mass, double half_length) {
    return mass * (2.0 * half_length) * (2.0 * half_length) / 12.0;
  }
};

enum class IntegratorType { kRk4, kDopri5 };

struct SimulationSettings {
  double physics_rate = 1000.0;  // [Hz], one physics step is 1/physics_rate of sim time
  IntegratorType integrator = IntegratorType::kRk4;
  double absolute_tolerance = 1e-9;  // dopri5 only
  double relative_tolerance = 1e-9;  // dopri5 only
  double publish_rate = 100.0;       // [Hz] joint_states, tf, mechanism_state
  double real_time_factor = 1.0;     // sim time per wall time; 0 = as fast as possible
  bool publish_clock = false;        // true: the node owns /clock
  bool start_paused = false;         // true: the node waits for `unpause` or `step`
};

struct CommandSettings {
  double torque_limit = 50.0;  // [N m] |M_m| is clamped to this
  double timeout = 0.5;        // [s] no command for this long -> torque 0; 0 disables
};

struct FrameSettings {
  std::string prefix;           // prepended to every frame name
  std::string world = "world";  // REP-105 world frame, z up
  double pivot_height = 2.0;    // [m] height of O above the world origin
};

struct Config {
  MechanismParameters mechanism;
  State initial_state;  // q10, q20, u10, u20; the spring is unstretched at (q10, q20)
  SimulationSettings simulation;
  CommandSettings command;
  FrameSettings frames;
};

const char* integratorName(IntegratorType type);

}  // namespace kane_sim

#endif  // KANE_SIM_CONFIG_H
