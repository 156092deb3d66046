// The integrator adapter of Simulator (private to src/sim): odeint's view of the equations of
// motion (free, and held on a resting contact) and Simulator::Integrator, which advances a state
// by exactly one physics step with rk4 or dopri5. Included by simulator.cpp only, so the
// equations inline into the integrator's stages.
#ifndef KANE_SIM_SIM_INTEGRATOR_H
#define KANE_SIM_SIM_INTEGRATOR_H

#include <algorithm>
#include <cmath>
#include <type_traits>

#include <boost/numeric/odeint.hpp>

#include "kane_sim/model/rk4_step.h"
#include "kane_sim/sim/simulator.h"

namespace kane_sim {
namespace odeint = boost::numeric::odeint;

namespace {

// Odeint's view of the first-order system x' = f(x) at a held torque, f from either the
// generated equations (GeneratedMechanism) or the generic assembly (MechanismModel).
template <class Equations>
struct EquationsOfMotion {
  const Equations* equations;
  double torque;

  void operator()(const OdeState& x, OdeState& dxdt) const {
    dxdt = equations->stateDerivative(fromOdeState(x), torque);
  }
  void operator()(const OdeState& x, OdeState& dxdt, double /*t*/) const { (*this)(x, dxdt); }
};

// Resting contact: the same equations with the sliders held together at the gap, the
// constraint force from Kane's equations (MechanismModel::restingContact). q2 and u2 follow from
// q1 and u1 on the contact, so the motion is integrated on the contact and never drifts off it.
template <class Equations>
struct RestingContactMotion {
  const MechanismModel* model;
  const Equations* equations;
  double torque;

  void operator()(const OdeState& x, OdeState& dxdt, double /*t*/) const { (*this)(x, dxdt); }
  void operator()(const OdeState& x, OdeState& dxdt) const {
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

inline bool withinScale(const OdeState& x) {
  // Every component at once (no early exit: a plain loop GCC unrolls, std::all_of it called).
  bool within = true;
  for (double v : x) within &= std::abs(v) <= kMaxMagnitude;
  return within;
}

constexpr int kMaxSubstepsPerTick = Simulator::kMaxSubstepsPerTick;

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
  double dopri5Substep() const { return dopri5_substep_; }
  void setDopri5Substep(double substep) { dopri5_substep_ = substep; }

  template <class System>
  const char* advance(const System& system, OdeState& x, double t, double dt,
                      bool reuse_last_derivative) {
    if (type_ == IntegratorType::kRk4) {
      rk4Step(system, x, dt);
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
  // The four stages (model/rk4_step.h) with the equations flattened into one body, on a local
  // copy of the state: the caller's state is then read once and written once instead of at
  // every stage (GCC keeps the stepper out of the large stepWith).
  template <class System>
  __attribute__((flatten)) void rk4Step(const System& system, OdeState& x, double dt) {
    OdeState local = x;
    kane_sim::rk4Step(system, local, dt);
    x = local;
  }
  // The generated equations: the stages of the variant the constants need, fixed at compile time
  // (GeneratedMechanism::withBound) and flattened into one body. With sin and cos inline
  // (model/math_functions.h) nothing between the stages is opaque to the compiler (without
  // friction, whose tanh stays a library call), so it forms the equations' coefficients (the
  // constants' functions) once per step.
  void rk4Step(const EquationsOfMotion<GeneratedMechanism>& system, OdeState& x, double dt) {
    system.equations->withBound([&](const auto& bound) {
      rk4Step(EquationsOfMotion<std::decay_t<decltype(bound)>>{&bound, system.torque}, x, dt);
    });
  }

  IntegratorType type_;
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

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_INTEGRATOR_H
