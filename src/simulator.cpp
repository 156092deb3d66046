#include "kane_sim/simulator.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <boost/numeric/odeint.hpp>

namespace kane_sim {
namespace odeint = boost::numeric::odeint;

namespace {

// The first-order system x' = f(x): q' = u (kinematical equations, eq 1) and u' from eq (18).
struct EquationsOfMotion {
  const MechanismModel* model;
  double torque;

  void operator()(const OdeState& x, OdeState& dxdt, double /*t*/) const {
    const SpeedVector u_dot = model->accelerations(fromOdeState(x), torque);
    dxdt[0] = x[2];
    dxdt[1] = x[3];
    dxdt[2] = u_dot[0];
    dxdt[3] = u_dot[1];
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

  // Advances x from t to exactly t + dt. `continues` says that x is where the last successful
  // call left it and the right-hand side (the torque) is unchanged.
  StepResult advance(const EquationsOfMotion& system, OdeState& x, double t, double dt,
                     bool continues) {
    if (type_ == IntegratorType::kRk4) {
      rk4_.do_step(system, x, t, dt);
      return {};
    }
    // dopri5 reuses the derivative at the end of its last step (first same as last); that is
    // only valid for the same state and the same torque.
    if (!continues) dopri5_.reset();
    const double t_end = t + dt;
    double substep = std::min(dopri5_substep_, dt);
    for (int n = 0; n < kMaxSubstepsPerTick; ++n) {
      const double remaining = t_end - t;
      if (remaining <= 1e-12 * dt) return {};
      const bool last = substep >= remaining;
      double h = last ? remaining : substep;
      if (dopri5_.try_step(system, x, t, h) == odeint::success) {
        if (!isFinite(x)) return {false, "dopri5 produced a non-finite state"};
        // Keep the controller's suggestion for the next tick, unless this step was shortened
        // only to land on the tick boundary.
        if (!last) dopri5_substep_ = h;
        if (last) return {};
      }
      substep = h;
    }
    std::ostringstream msg;
    msg << "dopri5 needed more than " << kMaxSubstepsPerTick << " sub-steps for one physics step";
    return {false, msg.str()};
  }

 private:
  IntegratorType type_;
  odeint::runge_kutta4<OdeState> rk4_;
  Dopri5 dopri5_;
  double dopri5_substep_ = 1e-3;
};

Simulator::Simulator(const Config& config)
    : model_(config.mechanism, config.initial_state),
      settings_(config.simulation),
      initial_state_(config.initial_state),
      state_(config.initial_state),
      step_size_(1.0 / config.simulation.physics_rate),
      integrator_(std::make_unique<Integrator>(config.simulation)),
      slider_separation_(sliderSeparation(state_)) {}

Simulator::~Simulator() = default;

StepResult Simulator::setTorque(double torque) {
  if (!std::isfinite(torque)) {
    std::ostringstream msg;
    msg << "torque " << torque << " N m is not finite; keeping " << torque_ << " N m";
    return {false, msg.str()};
  }
  if (torque != torque_) continues_ = false;
  torque_ = torque;
  return {};
}

StepResult Simulator::step() {
  OdeState x = toOdeState(state_);
  const EquationsOfMotion system{&model_, torque_};
  StepResult result = integrator_->advance(system, x, time(), step_size_, continues_);
  if (result.ok && !isFinite(x)) result = {false, "the step produced a non-finite state"};
  continues_ = result.ok;
  if (!result.ok) {
    std::ostringstream msg;
    msg << result.error << " at t = " << time() << " s (q1 = " << state_.q1
        << ", q2 = " << state_.q2 << ", u1 = " << state_.u1 << ", u2 = " << state_.u2
        << ", M_m = " << torque_ << "); step refused, state kept";
    return {false, msg.str()};
  }
  const State next = fromOdeState(x);
  motor_work_ += torque_ * (next.q1 - state_.q1);  // exact for a torque held over the step
  const double separation = sliderSeparation(next);
  if ((separation > 0) != (slider_separation_ > 0)) ++slider_crossings_;
  slider_separation_ = separation;
  if (settings_.integrator == IntegratorType::kRk4 &&
      std::abs(next.u1) * step_size_ > kMaxCrankAnglePerStep)
    step_too_coarse_ = true;
  state_ = next;
  ++ticks_;
  return result;
}

void Simulator::reset() {
  state_ = initial_state_;
  torque_ = 0.0;
  motor_work_ = 0.0;
  slider_crossings_ = 0;
  step_too_coarse_ = false;
  continues_ = false;
  slider_separation_ = sliderSeparation(state_);
}

double Simulator::sliderSeparation(const State& x) const {
  const MechanismGeometry g = model_.geometry(x.q1, x.q2);
  return g.point_c.x() - g.pin_b.x();
}

MechanismSnapshot Simulator::snapshot() const {
  MechanismSnapshot snap;
  snap.time = time();
  snap.state = state_;
  snap.torque = torque_;
  const MechanismModel::Forces forces = model_.generalizedForces(state_, torque_);
  snap.u_dot = forces.solveAccelerations();
  snap.active_forces = forces.active;
  snap.inertia_forces = forces.inertia(snap.u_dot);
  snap.energy = model_.energy(state_);
  snap.motor_work = motor_work_;
  snap.motor_power = torque_ * state_.u1;
  snap.spring_elongation = model_.springElongation(state_.q1, state_.q2);
  snap.slider_separation = slider_separation_;
  snap.slider_crossings = slider_crossings_;
  return snap;
}

}  // namespace kane_sim
