#include "kane_sim/sim/simulator.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <boost/numeric/odeint.hpp>

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

bool isFinite(const OdeState& x) {
  return std::all_of(x.begin(), x.end(), [](double v) { return std::isfinite(v); });
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
    msg << "torque " << torque << " N m is not finite; keeping " << torque_ << " N m";
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

Status Simulator::step() {
  if (equations_ == EquationsSource::kGenerated) return stepWith(generated_);
  return stepWith(model_);
}

template <class Equations>
Status Simulator::stepWith(const Equations& equations) {
  OdeState x = toOdeState(state_, motor_work_, dissipated_energy_);
  const EquationsOfMotion<Equations> system{&equations, torque_};
  const SliderContact& contact = model_.parameters().contact;
  double t = time();
  double remaining = step_size_;
  const char* error = nullptr;
  for (int impacts = 0;; ++impacts) {
    OdeState trial = x;
    error = integrator_->advance(system, trial, t, remaining, last_derivative_valid_);
    if (!error && !isFinite(trial)) error = "the step produced a non-finite state";
    if (error) break;
    if (!contact.enabled || separationAtLeast(trial, contact.gap) ||
        impacts == kMaxImpactsPerStep) {
      x = trial;
      break;
    }
    // The sliders closed to the gap within this step: find when (bisection on the integrated
    // motion to 2^-50 of the step), apply the impact there, integrate the rest of the step.
    double before = 0.0, after = remaining;
    OdeState at_touch = x;
    for (int i = 0; i < 50; ++i) {
      const double mid = 0.5 * (before + after);
      OdeState probe = x;
      if (integrator_->advance(system, probe, t, mid, false)) break;
      if (separationAtLeast(probe, contact.gap)) {
        before = mid;
        at_touch = probe;
      } else {
        after = mid;
      }
    }
    const std::optional<SliderImpact> impact = model_.sliderImpact(fromOdeState(at_touch));
    x = at_touch;
    if (impact) {
      x[2] = impact->after.u1;
      x[3] = impact->after.u2;
      x[5] += impact->energy_loss;  // D: the ledger books the impact's loss
      ++contact_impacts_;
    }
    t += before;
    remaining -= before;
    last_derivative_valid_ = false;
  }
  last_derivative_valid_ = !error;
  if (error) {
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
  ++ticks_;
  return {};
}

void Simulator::reset() {
  torque_ = 0.0;
  static_cast<void>(setState(initial_state_));  // the initial state was checked at start-up
}

Status Simulator::setState(const State& x) {
  const double values[] = {x.q1, x.q2, x.u1, x.u2};
  const char* names[] = {"q1", "q2", "u1", "u2"};
  for (int i = 0; i < 4; ++i) {
    if (!std::isfinite(values[i])) {
      std::ostringstream msg;
      msg << names[i] << " = " << values[i] << " is not finite; state kept";
      return {false, msg.str()};
    }
  }
  if (!std::isfinite(model_.energy(x).total())) {
    std::ostringstream msg;
    msg << "q1 = " << x.q1 << ", q2 = " << x.q2 << ", u1 = " << x.u1 << ", u2 = " << x.u2
        << " gives a non-finite energy; use values of the mechanism's size; state kept";
    return {false, msg.str()};
  }
  state_ = x;
  motor_work_ = 0.0;
  dissipated_energy_ = 0.0;
  parameter_energy_ = 0.0;
  slider_crossings_ = 0;
  contact_impacts_ = 0;
  step_too_coarse_ = false;
  last_derivative_valid_ = false;
  slider4_below_ = separationAtLeast(toOdeState(state_), 0.0);
  return {};
}

void Simulator::setParameters(const MechanismParameters& parameters) {
  const double before = model_.energy(state_).total();
  model_ = MechanismModel(parameters, model_.springRestLength());
  generated_ = GeneratedMechanism(model_);
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
