// Simulator's contact resolver: a touch of the sliders as an impact (Kane's impulsive form,
// restitution e) or, when the rebound would come back within a step, the start of resting
// contact; the contact force from Kane's equations while held. Only the contact path calls it.
#include "kane_sim/sim/simulator.h"

#include <algorithm>
#include <optional>

namespace kane_sim {

void Simulator::putOnContact(OdeState* x) const {
  const State held = model_.onContact(fromOdeState(*x));
  (*x)[1] = held.q2;
  (*x)[3] = held.u2;
}

template <class Equations>
RestingContact Simulator::restingContactAt(const Equations& equations, const State& held) const {
  const OdeState free = equations.stateDerivative(held, torque_);
  return model_.restingContact(held, SpeedVector(free[2], free[3]), torque_);
}

template <class Equations>
void Simulator::touch(const Equations& equations, OdeState* x) {
  // At the gap. A rebound that the free motion would bring back within a physics step (a bounce
  // at speed v under a closing acceleration a returns after 2 v / a) is the endless chatter of a
  // body coming to rest: the touch ends plastically in resting contact, held by the constraint
  // force while that force pushes. A faster approach is an impact with restitution e.
  const State at = fromOdeState(*x);
  const RestingContact held = restingContactAt(equations, model_.onContact(at));
  const double approach =
      -MechanismModel::separationJacobian(model_.kinematics(at)).dot(at.speeds());
  const double rebound = model_.parameters().contact.restitution * std::max(approach, 0.0);
  const bool rests =
      held.closing_acceleration > 0.0 && rebound <= held.closing_acceleration * step_size_;
  const std::optional<SliderImpact> impact =
      model_.sliderImpact(at, rests ? 0.0 : model_.parameters().contact.restitution);
  if (impact) {
    (*x)[2] = impact->after.u1;
    (*x)[3] = impact->after.u2;
    (*x)[5] += impact->energy_loss;  // D: the ledger books the impact's loss
    step_impact_energy_ += impact->energy_loss;
    ++contact_impacts_;
  }
  if (rests) {
    putOnContact(x);
    resting_contact_ = true;
  }
}

// The two equations the simulator steps (simulation.equations).
template RestingContact Simulator::restingContactAt(const GeneratedMechanism&, const State&) const;
template RestingContact Simulator::restingContactAt(const MechanismModel&, const State&) const;
template void Simulator::touch(const GeneratedMechanism&, OdeState*);
template void Simulator::touch(const MechanismModel&, OdeState*);

}  // namespace kane_sim
