#include "kane_sim/sim/simulator.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <type_traits>

#include "integrator.h"
#include "kane_sim/analysis/stability.h"
#include "kane_sim/format_number.h"

namespace kane_sim {

Status Simulator::setTorque(double torque) {
  if (!std::isfinite(torque)) {
    std::ostringstream msg;
    msg << "torque " << formatNumber(torque) << " N m is not finite; keeping " << torque_ << " N m";
    return {false, msg.str()};
  }
  if (torque != torque_) last_derivative_valid_ = false;
  torque_ = torque;
  return {};
}

bool Simulator::separationAtLeast(const OdeState& x, double threshold) const {
  return sliderSeparationAtLeast(model_.parameters().rod_half_length, x[0], x[1], threshold);
}

Status Simulator::step() {
  return withEquations([this](const auto& equations) { return stepWith(equations); });
}

// Advances from x over at most `span`, and finds by bisection (to 2^-50 of the span) the last
// instant at which `holds` is still true; `holds` is true at x and false at x + span. Returns
// that instant's offset and leaves the state there in *at.
template <class System, class Holds>
double Simulator::lastInstantWhere(const System& system, const OdeState x, double t, double span,
                                   const Holds& holds, OdeState* at) {
  // x by value: `at` may be the caller's x.
  double before = 0.0, after = span;
  *at = x;
  for (int i = 0; i < 50; ++i) {
    const double mid = 0.5 * (before + after);
    OdeState probe = x;
    if (integrator_->advance(system, probe, t, mid, false)) break;
    if (holds(probe)) {
      before = mid;
      *at = probe;
    } else {
      after = mid;
    }
  }
  return before;
}

// One advance of x over `span` from t and the checks every trial state passes: nullptr, or why
// the step is refused (a literal).
template <class System>
const char* Simulator::advanceChecked(const System& system, OdeState* x, double t, double span,
                                      bool reuse_derivative) {
  const char* error = integrator_->advance(system, *x, t, span, reuse_derivative);
  static_assert(kMaxCrankTurnPerStep == 1.0, "the message below names the limit");
  if (!error && !withinScale(*x))  // NaN fails it too
    error = "the step produced a non-finite or runaway state (beyond 1e100)";
  if (!error && integrator_type_ == IntegratorType::kRk4 &&
      !(std::abs((*x)[2]) * step_size_ <= kMaxCrankTurnPerStep))
    error = kCrankTurnRefusal;
  return error;
}

template <class Equations>
Status Simulator::stepWith(const Equations& equations) {
  OdeState x = toOdeState(state_, motor_work_, dissipated_energy_);
  step_impact_energy_ = 0.0;
  // Without contact the step is one advance (most runs); with it, the events it may hold.
  const char* error = resting_contact_ || model_.parameters().contact.enabled
                          ? advanceThroughContact(equations, &x)
                          : advanceChecked(EquationsOfMotion<Equations>{&equations, torque_}, &x,
                                           time(), step_size_, last_derivative_valid_);
  last_derivative_valid_ = !error;
  if (error) {
    resting_contact_ = resting_contact_at_start_of_step_;
    std::ostringstream msg;
    msg << error << " at t = " << time() << " s (q1 = " << state_.q1 << ", q2 = " << state_.q2
        << ", u1 = " << state_.u1 << ", u2 = " << state_.u2 << ", M_m = " << torque_
        << "); step refused, state kept";
    return {false, msg.str()};
  }
  const State next = fromOdeState(x);
  // Integrated with the motion: for a held torque without the motor line W' = M_m u1 gets the
  // same weights as q1' = u1, so W = M_m Δq1 to rounding, as exact as before.
  motor_work_ = x[4];
  dissipated_energy_ = x[5];
  impact_energy_ += step_impact_energy_;
  const bool slider4_below = separationAtLeast(x, 0.0);
  if (slider4_below != slider4_below_) ++slider_crossings_;
  slider4_below_ = slider4_below;
  if (integrator_type_ == IntegratorType::kRk4 &&
      std::abs(next.u1) * step_size_ > kMaxCrankAnglePerStep)
    step_too_coarse_ = true;
  state_ = next;
  resting_contact_at_start_of_step_ = resting_contact_;
  ++ticks_;
  return {};
}

// The step with contact enabled or held: advance, and where the sliders touch or a held contact
// lets go within the step, find the instant, resolve it there and advance the rest.
template <class Equations>
const char* Simulator::advanceThroughContact(const Equations& equations, OdeState* state) {
  OdeState& x = *state;
  const EquationsOfMotion<Equations> free{&equations, torque_};
  const RestingContactMotion<Equations> held{&model_, &equations, torque_};
  const SliderContact& contact = model_.parameters().contact;
  double t = time();
  double remaining = step_size_;
  bool reuse_derivative = last_derivative_valid_;
  const auto pushes = [&](const OdeState& at) {  // the held contact still pushes (N >= 0)
    return restingContactAt(equations, fromOdeState(at)).force >= 0.0;
  };
  const auto apart = [&](const OdeState& at) { return separationAtLeast(at, contact.gap); };
  static_assert(kMaxContactEventsPerStep == 16, "the message below names the limit");
  for (int events = 0;; ++events) {
    if (events > kMaxContactEventsPerStep)
      return "the sliders' contact changed more than 16 times within one physics step";
    if (resting_contact_ && !pushes(x)) {  // the contact would pull: it lets go
      resting_contact_ = false;
      reuse_derivative = false;
    }
    OdeState trial = x;
    const char* error = resting_contact_
                            ? advanceChecked(held, &trial, t, remaining, reuse_derivative)
                            : advanceChecked(free, &trial, t, remaining, reuse_derivative);
    if (error) return error;
    double span = 0.0;  // how far into the remaining step the event lies
    if (resting_contact_) {
      // Integrated on the contact: q2, u2 follow from q1, u1 exactly (no drift off it).
      putOnContact(&trial);
      if (pushes(trial)) {
        x = trial;
        return nullptr;
      }
      // The contact force turns to a pull within the step: let go where it does.
      span = lastInstantWhere(
          held, x, t, remaining,
          [&](OdeState at) {
            putOnContact(&at);
            return pushes(at);
          },
          &x);
      putOnContact(&x);
      resting_contact_ = false;
    } else {
      if (!contact.enabled || apart(trial)) {
        x = trial;
        return nullptr;
      }
      // The sliders closed to the gap within this step: find when, resolve the touch there,
      // integrate the rest of the step.
      span = lastInstantWhere(free, x, t, remaining, apart, &x);
      touch(equations, &x);
    }
    t += span;
    remaining -= span;
    reuse_derivative = false;
  }
}

Simulator::Dynamics Simulator::dynamics() const {
  Dynamics d;
  d.state = state_;
  d.ticks = ticks_;
  d.torque = torque_;
  d.motor_work = motor_work_;
  d.dissipated_energy = dissipated_energy_;
  d.impact_energy = impact_energy_;
  d.parameter_energy = parameter_energy_;
  d.slider_crossings = slider_crossings_;
  d.contact_impacts = contact_impacts_;
  d.parameter_changes = parameter_changes_;
  d.step_too_coarse = step_too_coarse_;
  d.slider4_below = slider4_below_;
  d.resting_contact = resting_contact_;
  d.dopri5_substep = integrator_->dopri5Substep();
  return d;
}

void Simulator::restore(const Dynamics& d) {
  state_ = d.state;
  ticks_ = d.ticks;
  torque_ = d.torque;
  motor_work_ = d.motor_work;
  dissipated_energy_ = d.dissipated_energy;
  impact_energy_ = d.impact_energy;
  parameter_energy_ = d.parameter_energy;
  slider_crossings_ = d.slider_crossings;
  contact_impacts_ = d.contact_impacts;
  parameter_changes_ = d.parameter_changes;
  step_too_coarse_ = d.step_too_coarse;
  slider4_below_ = d.slider4_below;
  resting_contact_ = resting_contact_at_start_of_step_ = d.resting_contact;
  integrator_->setDopri5Substep(d.dopri5_substep);
  // dopri5 evaluates the derivative afresh instead of reusing its last one: the same function
  // of the same state, so the same bits.
  last_derivative_valid_ = false;
  step_impact_energy_ = 0.0;
}

void Simulator::reset() {
  torque_ = 0.0;
  static_cast<void>(setState(initial_state_));  // the initial state was checked at start-up
}

Status Simulator::setState(const State& x) {
  const Status usable = checkState(x);
  if (!usable.ok) return {false, usable.error + "; state kept"};
  state_ = x;
  motor_work_ = 0.0;
  dissipated_energy_ = 0.0;
  impact_energy_ = 0.0;
  parameter_energy_ = 0.0;
  slider_crossings_ = 0;
  contact_impacts_ = 0;
  step_too_coarse_ = false;
  last_derivative_valid_ = false;
  resting_contact_ = resting_contact_at_start_of_step_ = false;
  slider4_below_ = separationAtLeast(toOdeState(state_), 0.0);
  return {};
}

Status Simulator::checkState(const State& x) const {
  const Status usable = checkUsable(x);
  if (!usable.ok || integrator_type_ != IntegratorType::kRk4) return usable;
  const auto refuse = [&x](const std::string& why) {
    return Status{false, stateText(x) + " " + why};
  };
  if (!(std::abs(x.u1) * step_size_ <= kMaxCrankTurnPerStep))
    return refuse("turns the crank more than 1 rad per rk4 step, which rk4 cannot resolve");
  const double rate = fastestRate(model_, x, torque_);
  if (!(rate * step_size_ <= kRk4StabilityLimit)) {
    std::ostringstream msg;
    msg << "is too stiff for rk4 at " << 1.0 / step_size_
        << " Hz: the linearised motion's fastest rate there is " << rate
        << " 1/s (rate h = " << rate * step_size_ << ", at most " << kRk4StabilityLimit << ")";
    return refuse(msg.str());
  }
  // One rule with step(): a state whose first step step() would refuse (the crank past 1 rad
  // within it, a runaway) is refused here too (u1 h = 1 exactly was once accepted, and the
  // next step refused).
  OdeState trial = toOdeState(x);
  withEquations([&](const auto& equations) {
    rk4Step(EquationsOfMotion<std::decay_t<decltype(equations)>>{&equations, torque_}, trial,
            step_size_);
    return 0;
  });
  if (!withinScale(trial) || !(std::abs(trial[2]) * step_size_ <= kMaxCrankTurnPerStep))
    return refuse("would turn the crank more than 1 rad within its first rk4 step (u1 reaches " +
                  formatNumber(trial[2]) + " rad/s), which rk4 cannot resolve");
  return {};
}

std::string Simulator::stateText(const State& x) {
  return "q1 = " + formatNumber(x.q1) + ", q2 = " + formatNumber(x.q2) +
         ", u1 = " + formatNumber(x.u1) + ", u2 = " + formatNumber(x.u2);
}

Status Simulator::checkUsable(const State& x) const {
  const auto refuse = [&x](const std::string& why) {
    return Status{false, stateText(x) + " " + why};
  };
  const double values[] = {x.q1, x.q2, x.u1, x.u2};
  const char* names[] = {"q1", "q2", "u1", "u2"};
  for (int i = 0; i < 4; ++i)
    if (!std::isfinite(values[i]))
      return {false, std::string(names[i]) + " = " + formatNumber(values[i]) + " is not finite"};
  // q1 beyond a million turns: its cosine has lost every digit of the angle's fraction.
  if (std::abs(x.q1) > kMaxCrankAngle) {
    std::ostringstream msg;
    msg << "q1 = " << formatNumber(x.q1) << " rad is beyond +-" << kMaxCrankAngle
        << " rad, where a double no longer resolves the crank's angle";
    return {false, msg.str()};
  }
  if (!std::isfinite(model_.energy(x).total()))
    return refuse("gives a non-finite energy; use values of the mechanism's size");
  const OdeState rates = generated_.stateDerivative(x, torque_);
  if (!isFinite(rates)) return refuse("gives non-finite accelerations u'");
  const SliderContact& contact = model_.parameters().contact;
  if (contact.enabled && !separationAtLeast(toOdeState(x), contact.gap)) {
    // x points down the rail: a negative separation puts slider 4 above slider 3.
    const double separation = model_.geometry(x.q1, x.q2).sliderSeparation();
    return {false, "q1 = " + formatNumber(x.q1) + ", q2 = " + formatNumber(x.q2) +
                       " puts slider 4 " + formatNumber(std::abs(separation)) +
                       (separation < 0.0 ? " m above" : " m below") +
                       " slider 3 (x_C - x_B = " + formatNumber(separation) +
                       " m), closer than contact.gap " + formatNumber(contact.gap) +
                       " m: with contact enabled the sliders must be apart"};
  }
  if (!withinScale(toOdeState(x)))
    return refuse("is beyond the mechanism's scale (a magnitude over 1e100)");
  return {};
}

}  // namespace kane_sim
