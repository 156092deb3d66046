// What Simulator books and reports: the energy ledger (E + D - W - parameter_energy, with a
// parameter change's jump booked as parameter_energy) and the snapshot of the state, its
// equations, energies and contact, computed once per publish.
#include "kane_sim/sim/simulator.h"

namespace kane_sim {

void Simulator::setParameters(const MechanismParameters& parameters) {
  const double before = model_.energy(state_).total();
  model_ = MechanismModel(parameters, model_.springRestLength());
  generated_ = GeneratedMechanism(model_);
  if (!parameters.contact.enabled) resting_contact_ = resting_contact_at_start_of_step_ = false;
  parameter_energy_ += model_.energy(state_).total() - before;
  ++parameter_changes_;
  last_derivative_valid_ = false;
}

Snapshot Simulator::snapshot() const {
  const MechanismKinematics k = model_.kinematics(state_);
  MechanismLoads loads = model_.loads(k, state_, torque_);
  const MechanismModel::Equations equations = MechanismModel::equations(k, loads, state_);
  const PowerTerms power = MechanismModel::power(loads, state_);
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
  snap.active_forces = equations.active_forces;
  if (resting_contact_) {
    // Held together: the contact force is one more load, J^T N in F_r, and u' is constrained.
    const RestingContact contact = model_.restingContact(state_, snap.u_dot, torque_);
    snap.u_dot = contact.u_dot;
    snap.active_forces += contact.generalized_force;
    snap.contact_force = contact.force;
    snap.resting_contact = true;
  }
  snap.inertia_forces = equations.inertiaForces(snap.u_dot);
  snap.energy = model_.energy(k, state_);
  snap.motor_work = motor_work_;
  snap.dissipated_energy = dissipated_energy_;
  snap.parameter_energy = parameter_energy_;
  snap.parameter_changes = parameter_changes_;
  snap.motor_power = power.motor;
  snap.dissipated_power = power.dissipated;
  snap.contact_impacts = contact_impacts_;
  snap.spring_elongation = model_.springElongation(k.geometry);
  snap.slider_separation = k.geometry.sliderSeparation();
  snap.slider_crossings = slider_crossings_;
  // The contact's force joins the list (zero when apart) for the reactions and the powers.
  MechanismModel::addContactLoads(k, snap.contact_force, &loads);
  snap.constraint_forces = constraintForces(k, loads, state_, snap.u_dot);
  snap.load_powers = loadPowers(loads, state_);
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
