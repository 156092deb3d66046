// A parameter change at run time (dynamic_reconfigure, the page's panel): the model and its
// generated equations anew at the same state, and the jump of the total energy it causes booked
// as parameter_energy, so that the ledger E + D - W - parameter_energy stays constant across it.
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

}  // namespace kane_sim
