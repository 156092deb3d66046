// What Simulator reports: the snapshot of the state, its equations, energies, powers, reactions
// and contact, computed once per publish, and the joints as joint_states names them.
#include "kane_sim/sim/simulator.h"

namespace kane_sim {

Snapshot Simulator::snapshot() const {
  const MechanismKinematics k = model_.kinematics(state_);
  Snapshot snap;
  snap.time = time();
  snap.state = state_;
  snap.torque = model_.appliedMotorTorque(torque_, state_.u1);  // what the drive delivers at u1
  snap.command.commanded = torque_;
  // u' as the integrators step it: from the generated equations on that path (so a check of
  // the published u' checks the equations in use), else from the assembly; equal to rounding.
  const OdeState dx = withEquations(
      [this](const auto& equations) { return equations.stateDerivative(state_, torque_); });
  snap.u_dot = SpeedVector(dx[2], dx[3]);
  if (resting_contact_) {
    // Held together: u' is constrained, and the contact's force N is one more load.
    const RestingContact contact = model_.restingContact(state_, snap.u_dot, torque_);
    snap.u_dot = contact.u_dot;
    snap.contact_force = contact.force;
    snap.resting_contact = true;
  }
  // The loads with the contact's entries (zero when apart): F_r, the reactions and the powers
  // all come from this one list.
  MechanismLoads loads = model_.loads(k, state_, torque_);
  MechanismModel::addContactLoads(k, snap.contact_force, &loads);
  const MechanismModel::Equations equations = MechanismModel::equations(k, loads, state_);
  snap.active_forces = equations.active_forces;
  snap.inertia_forces = equations.inertiaForces(snap.u_dot);
  snap.energy = model_.energy(k, state_);
  snap.motor_work = motor_work_;
  snap.dissipated_energy = dissipated_energy_;
  snap.parameter_energy = parameter_energy_;
  snap.parameter_changes = parameter_changes_;
  snap.load_powers = loadPowers(loads, state_);
  snap.motor_power = snap.load_powers[LoadName::kMotor];
  snap.dissipated_power = -snap.load_powers.dissipative();
  snap.contact_impacts = contact_impacts_;
  snap.spring_elongation = model_.springElongation(k.geometry);
  snap.slider_separation = k.geometry.sliderSeparation();
  snap.slider_crossings = slider_crossings_;
  snap.constraint_forces = constraintForces(k, loads, state_, snap.u_dot);
  snap.body_kinetic_energy = bodyKineticEnergies(k, state_);
  snap.impact_energy = impact_energy_;
  snap.geometry = k.geometry;
  snap.joints = jointValues(k, state_, snap.torque);
  return snap;
}

JointValues Simulator::joints() const {
  const MechanismKinematics k = model_.kinematics(state_);
  return jointValues(k, state_, model_.appliedMotorTorque(torque_, state_.u1));
}

}  // namespace kane_sim
