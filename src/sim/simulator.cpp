#include "kane_sim/sim/simulator.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <boost/numeric/odeint.hpp>

#include "kane_sim/analysis/stability.h"
#include "kane_sim/format_number.h"

namespace kane_sim {
namespace odeint = boost::numeric::odeint;

namespace {

// Odeint's view of the first-order system x' = f(x) at a held torque, f from either the
// generated equations (GeneratedMechanism) or the generic assembly (MechanismModel).
template <class Equations>
struct EquationsOfMotion {
  const Equations* equations;
  double torque;

  void operator()(const OdeState& x, OdeState& dxdt, double /*t*/) const {
    dxdt = equations->stateDerivative(fromOdeState(x), torque);
  }
};

// Resting contact: the same equations with the sliders held together at the gap, the
// constraint force from Kane's equations (MechanismModel::restingContact). q2 and u2 follow from
// q1 and u1 on the contact, so the motion is integrated on the contact and never drifts off it.
template <class Equations>
struct RestingContactMotion {
  const MechanismModel* model;
  const Equations* equations;
  double torque;

  void operator()(const OdeState& x, OdeState& dxdt, double /*t*/) const {
    const State held = model->onContact(fromOdeState(x));
    dxdt = equations->stateDerivative(held, torque);  // free u', and W', D' on the contact
    const RestingContact contact =
        model->restingContact(held, SpeedVector(dxdt[2], dxdt[3]), torque);
    dxdt[1] = held.u2;
    dxdt[2] = contact.u_dot[0];
    dxdt[3] = contact.u_dot[1];
  }
};

bool isFinite(const OdeState& x) {
  return std::all_of(x.begin(), x.end(), [](double v) { return std::isfinite(v); });
}

// Within these magnitudes every derived quantity (energies, forces, F*_r) of a state stays
// finite for any accepted parameters; beyond them a state is a runaway, not a mechanism.
constexpr double kMaxMagnitude = 1e100;

bool withinScale(const OdeState& x) {
  return std::all_of(x.begin(), x.end(), [](double v) { return std::abs(v) <= kMaxMagnitude; });
}

// dopri5 gives up on a physics step after this many rejected or accepted sub-steps; reaching
// it means the tolerances ask for more than double precision can give at this state.
constexpr int kMaxSubstepsPerTick = 100000;

}  // namespace

class Simulator::Integrator {
 public:
  using Dopri5 = odeint::controlled_runge_kutta<odeint::runge_kutta_dopri5<OdeState>>;

  explicit Integrator(const SimulationSettings& s)
      : type_(s.integrator),
        dopri5_(odeint::make_controlled(s.absolute_tolerance, s.relative_tolerance,
                                        odeint::runge_kutta_dopri5<OdeState>())) {}

  // Advances x from t to exactly t + dt. `reuse_last_derivative`: x is where the last
  // successful call left it and the right-hand side (the torque) is unchanged. Returns nullptr,
  // or why it failed (a literal: no string is built on the good path).
  template <class System>
  const char* advance(const System& system, OdeState& x, double t, double dt,
                      bool reuse_last_derivative) {
    if (type_ == IntegratorType::kRk4) {
      rk4_.do_step(system, x, t, dt);
      return nullptr;
    }
    // dopri5 reuses the derivative at the end of its last step (first same as last); that is
    // only valid for the same state and the same torque.
    if (!reuse_last_derivative) dopri5_.reset();
    const double t_end = t + dt;
    double substep = std::min(dopri5_substep_, dt);
    for (int n = 0; n < kMaxSubstepsPerTick; ++n) {
      const double remaining = t_end - t;
      if (remaining <= 1e-12 * dt) return nullptr;
      const bool last = substep >= remaining;
      double h = last ? remaining : substep;
      if (dopri5_.try_step(system, x, t, h) == odeint::success) {
        if (!isFinite(x)) return "dopri5 produced a non-finite state";
        // Keep the controller's suggestion for the next tick, unless this step was shortened
        // only to land on the tick boundary.
        if (!last) dopri5_substep_ = h;
        if (last) return nullptr;
      }
      substep = h;
    }
    static_assert(kMaxSubstepsPerTick == 100000, "the message below names the limit");
    return "dopri5 needed more than 100000 sub-steps for one physics step";
  }

 private:
  IntegratorType type_;
  odeint::runge_kutta4<OdeState> rk4_;
  Dopri5 dopri5_;
  double dopri5_substep_ = 1e-3;
};

Simulator::Simulator(const Config& config)
    : model_(mechanismModel(config)),
      generated_(model_),
      equations_(config.simulation.equations),
      integrator_type_(config.simulation.integrator),
      initial_state_(config.initial_state),
      state_(config.initial_state),
      step_size_(1.0 / config.simulation.physics_rate),
      integrator_(std::make_unique<Integrator>(config.simulation)),
      slider4_below_(separationAtLeast(toOdeState(state_), 0.0)) {}

Simulator::~Simulator() = default;

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
  // x_C - x_B = q2 - 4L cos q1 lies within q2 -+ 4L: those bounds settle most calls (slider 4
  // hangs below the crank's reach) without the cosine, which costs as much as an rk4 stage's.
  const double L = model_.parameters().rod_half_length;
  const double reach = slider3Position(L, 1.0);  // |x_B| <= 4L
  if (x[1] - reach >= threshold) return true;
  if (x[1] + reach < threshold) return false;
  return sliderSeparation(L, x[0], x[1]) >= threshold;
}

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

Status Simulator::step() {
  if (equations_ == EquationsSource::kGenerated) return stepWith(generated_);
  return stepWith(model_);
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

template <class Equations>
Status Simulator::stepWith(const Equations& equations) {
  OdeState x = toOdeState(state_, motor_work_, dissipated_energy_);
  const EquationsOfMotion<Equations> free{&equations, torque_};
  const RestingContactMotion<Equations> held{&model_, &equations, torque_};
  const SliderContact& contact = model_.parameters().contact;
  double t = time();
  double remaining = step_size_;
  bool reuse_derivative = last_derivative_valid_;
  const bool rk4 = integrator_type_ == IntegratorType::kRk4;
  const char* error = nullptr;
  const auto pushes = [&](const OdeState& at) {  // the held contact still pushes (N >= 0)
    return restingContactAt(equations, fromOdeState(at)).force >= 0.0;
  };
  const auto apart = [&](const OdeState& at) { return separationAtLeast(at, contact.gap); };
  static_assert(kMaxContactEventsPerStep == 16 && kMaxCrankTurnPerStep == 1.0,
                "the messages below name the limits");
  for (int events = 0;; ++events) {
    if (events > kMaxContactEventsPerStep) {
      error = "the sliders' contact changed more than 16 times within one physics step";
      break;
    }
    if (resting_contact_ && !pushes(x)) {  // the contact would pull: it lets go
      resting_contact_ = false;
      reuse_derivative = false;
    }
    OdeState trial = x;
    error = resting_contact_ ? integrator_->advance(held, trial, t, remaining, reuse_derivative)
                             : integrator_->advance(free, trial, t, remaining, reuse_derivative);
    if (!error && !withinScale(trial))  // NaN fails it too
      error = "the step produced a non-finite or runaway state (beyond 1e100)";
    if (!error && rk4 && !(std::abs(trial[2]) * step_size_ <= kMaxCrankTurnPerStep))
      error =
          "the crank would turn more than 1 rad in one rk4 step, which rk4 cannot resolve "
          "(use simulation.integrator dopri5 or a higher simulation.physics_rate)";
    if (error) break;
    double span = 0.0;  // how far into the remaining step the event lies
    if (resting_contact_) {
      // Integrated on the contact: q2, u2 follow from q1, u1 exactly (no drift off it).
      putOnContact(&trial);
      if (pushes(trial)) {
        x = trial;
        break;
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
        break;
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
    ++contact_impacts_;
  }
  if (rests) {
    putOnContact(x);
    resting_contact_ = true;
  }
}

void Simulator::reset() {
  torque_ = 0.0;
  static_cast<void>(setState(initial_state_));  // the initial state was checked at start-up
}

Status Simulator::setState(const State& x) {
  const Status usable = checkState(x);
  if (!usable.ok) return usable;
  state_ = x;
  motor_work_ = 0.0;
  dissipated_energy_ = 0.0;
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
  const auto refuse = [&x](const std::string& why) {
    std::ostringstream msg;
    msg << "q1 = " << formatNumber(x.q1) << ", q2 = " << formatNumber(x.q2)
        << ", u1 = " << formatNumber(x.u1) << ", u2 = " << formatNumber(x.u2) << " " << why
        << "; state kept";
    return Status{false, msg.str()};
  };
  const double values[] = {x.q1, x.q2, x.u1, x.u2};
  const char* names[] = {"q1", "q2", "u1", "u2"};
  for (int i = 0; i < 4; ++i) {
    if (!std::isfinite(values[i])) {
      std::ostringstream msg;
      msg << names[i] << " = " << formatNumber(values[i]) << " is not finite; state kept";
      return {false, msg.str()};
    }
  }
  // q1 beyond a million turns: its cosine has lost every digit of the angle's fraction.
  if (std::abs(x.q1) > kMaxCrankAngle) {
    std::ostringstream msg;
    msg << "q1 = " << formatNumber(x.q1) << " rad is beyond +-" << kMaxCrankAngle
        << " rad, where a double no longer resolves the crank's angle; state kept";
    return {false, msg.str()};
  }
  if (!std::isfinite(model_.energy(x).total()))
    return refuse("gives a non-finite energy; use values of the mechanism's size");
  const OdeState rates = generated_.stateDerivative(x, torque_);
  if (!isFinite(rates)) return refuse("gives non-finite accelerations u'");
  const SliderContact& contact = model_.parameters().contact;
  if (contact.enabled && !separationAtLeast(toOdeState(x), contact.gap)) {
    std::ostringstream msg;
    msg << "q1 = " << x.q1 << ", q2 = " << x.q2 << " puts slider 4 "
        << model_.geometry(x.q1, x.q2).sliderSeparation()
        << " m below slider 3 (x_C - x_B), closer than contact.gap " << contact.gap
        << " m: with contact enabled the sliders must be apart; state kept";
    return {false, msg.str()};
  }
  if (!withinScale(toOdeState(x)))
    return refuse("is beyond the mechanism's scale (a magnitude over 1e100)");
  if (integrator_type_ == IntegratorType::kRk4) {
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
  }
  return {};
}

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
  const MechanismLoads loads = model_.loads(k, state_, torque_);
  const MechanismModel::Equations equations = MechanismModel::equations(k, loads, state_);
  const PowerTerms power = MechanismModel::power(loads, state_);
  Snapshot snap;
  snap.time = time();
  snap.state = state_;
  snap.torque = loads.motor.torque.z();  // what the drive delivers (motor line) at u1
  snap.command.commanded = torque_;
  // u' as the integrators step it: from the generated equations on that path (so a check of
  // the published u' checks the equations in use), else from the assembly; equal to rounding.
  if (equations_ == EquationsSource::kGenerated) {
    const OdeState dx = generated_.stateDerivative(state_, torque_);
    snap.u_dot = SpeedVector(dx[2], dx[3]);
  } else {
    snap.u_dot = equations.solveAccelerations();
  }
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
  snap.geometry = k.geometry;
  snap.joints = MechanismModel::jointValues(k, state_, snap.torque);
  return snap;
}

}  // namespace kane_sim
