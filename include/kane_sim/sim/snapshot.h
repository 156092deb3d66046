// Everything one publish (or one CSV row) needs about one instant, computed once in the core:
// the ROS layer, the CSV writer and the bag writer only translate it.
#ifndef KANE_SIM_SIM_SNAPSHOT_H
#define KANE_SIM_SIM_SNAPSHOT_H

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "kane_sim/control/crank_servo.h"
#include "kane_sim/description/joint_values.h"
#include "kane_sim/model/constraint_forces.h"
#include "kane_sim/model/mechanism_model.h"
#include "kane_sim/model/power_flow.h"
#include "kane_sim/model/state.h"

namespace kane_sim {

// What the command handling holds at this instant.
struct CommandStatus {
  double commanded = 0.0;  // [N m] last accepted torque_command, before clamping
  double torque_limit = std::numeric_limits<double>::infinity();  // [N m] command.torque_limit
  bool timed_out = false;  // no command for command.timeout: 0 N m applied
};

struct Snapshot {
  double time = 0.0;  // [s] sim time
  State state;
  // u1' [rad/s^2], u2' [m/s^2] from the equations the integrators step (simulation.equations)
  SpeedVector u_dot = SpeedVector::Zero();
  double torque = 0.0;  // M_m [N m] the drive applies at this instant (after the motor line)
  CommandStatus command;
  SpeedVector active_forces = SpeedVector::Zero();   // F_r: F_1 [N m], F_2 [N]
  SpeedVector inertia_forces = SpeedVector::Zero();  // F*_r at u': F*_1 [N m], F*_2 [N]
  EnergyTerms energy;
  double motor_work = 0.0;         // W = ∫ M_m u1 dt since start or reset [J]
  double motor_power = 0.0;        // M_m u1 [W]
  double dissipated_energy = 0.0;  // D [J]: dampers and contact since start or reset
  double dissipated_power = 0.0;   // D' [W]
  // Σ ΔE of runtime parameter changes (dynamic_reconfigure) since start, reset or set_state [J].
  double parameter_energy = 0.0;
  std::uint64_t parameter_changes = 0;  // runtime parameter changes since start
  double spring_elongation = 0.0;       // e [m], eq (15); positive = compressed
  // x_C - x_B [m]: slider 4 below slider 3 when > 0. The textbook example models no contact
  // between the sliders, so a hard-driven crank can pull one through the other.
  double slider_separation = 0.0;
  std::uint64_t slider_crossings = 0;  // sign changes of slider_separation since start or reset
  std::uint64_t contact_impacts = 0;   // slider impacts since start or reset (contact on)
  bool resting_contact = false;        // the sliders rest on each other, held at contact.gap
  double contact_force = 0.0;          // N [N] then on slider 4 along +i (0 when apart)
  // What Kane's method shows beyond the motion: the pins' and rails' reaction forces (auxiliary
  // speeds), each load's power (Σ = dT/dt) and each body's kinetic energy (Σ = T).
  ConstraintForces constraint_forces;
  LoadPowers load_powers;
  std::array<double, kNumBodies> body_kinetic_energy{};
  double impact_energy = 0.0;  // [J] lost in slider impacts since start or reset (part of D)
  MechanismGeometry geometry;  // positions of O, A, B, C, C1, C2; rod angles
  JointValues joints;          // crank, coupler, slider3, slider4
  ServoStatus servo;           // command.mode velocity | position: the servo's update

  // Every number finite: what the node and the tools check before anything is published or
  // written (a snapshot that fails it is withheld and reported, never sent).
  bool allFinite() const {
    const double values[] = {time,
                             torque,
                             command.commanded,
                             energy.kinetic,
                             energy.potentialTotal(),
                             motor_work,
                             motor_power,
                             dissipated_energy,
                             dissipated_power,
                             parameter_energy,
                             spring_elongation,
                             slider_separation,
                             contact_force,
                             servo.output,
                             servo.integral,
                             load_powers.total(),
                             impact_energy};
    for (double v : values)
      if (!std::isfinite(v)) return false;
    for (int i = 0; i < kNumJoints; ++i)
      if (!std::isfinite(joints.position[i]) || !std::isfinite(joints.velocity[i]) ||
          !std::isfinite(joints.effort[i]))
        return false;
    for (double t : body_kinetic_energy)
      if (!std::isfinite(t)) return false;
    return state.isFinite() && u_dot.allFinite() && active_forces.allFinite() &&
           constraint_forces.allFinite() && inertia_forces.allFinite() &&
           std::isfinite(energyBalance());
  }

  // The energy ledger: E + D - W - parameter_energy, constant to the integrator's order [J].
  double energyBalance() const {
    return energy.total() + dissipated_energy - motor_work - parameter_energy;
  }
};

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_SNAPSHOT_H
