#include "kane_sim/analysis/stability.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include "kane_sim/model/generated_mechanism.h"

namespace kane_sim {
namespace {

// Every 10 degrees: M11(q1) varies smoothly, as cos 2 q1, and the extremes of the crank's inertia
// (q1 = 0, pi) and of the spring's lever 4 L sin q1 (q1 = pi/2, 3 pi/2) are among the samples.
constexpr int kCrankSamples = 36;

// The model with the motor line's slope as a crank damper (see fastestRate).
MechanismModel withMotorLineAsDamper(const MechanismModel& model) {
  MechanismParameters p = model.parameters();
  if (p.motor.no_load_speed > 0.0 && std::isfinite(p.motor.torque_limit))
    p.damping.crank += p.motor.torque_limit / p.motor.no_load_speed;
  return MechanismModel(p, model.springRestLength());
}

// A = d x'/d x by central differences of the generated equations (the fast path, the same
// physics): a stability bound needs a few digits, not analyze's 1e-10, and the loader asks for
// 36 of these per config, twice (a sweep of 1000 cases builds 1000 configs).
double rateOf(const GeneratedMechanism& equations, const State& x, double torque) {
  const double values[] = {x.q1, x.q2, x.u1, x.u2};
  Eigen::Matrix4d A;
  // Friction's tanh bends within v_s of a zero rate: a speed's step must stay inside that bend,
  // or the difference sees a step of 2 F_c over 2 h and misses the slope F_c / v_s (1 N over v_s
  // 1e-9 once passed as a rate 1000 times too small).
  const bool friction = equations.variant() == generated::RatesVariant::kCoulomb;
  const double speed_cap = 1e-2 * equations.constants().friction_velocity_scale;
  for (int j = 0; j < 4; ++j) {
    double h = 1e-6 * (1.0 + std::abs(values[j]));
    if (friction && j >= 2) h = std::min(h, speed_cap);
    double plus[] = {x.q1, x.q2, x.u1, x.u2}, minus[] = {x.q1, x.q2, x.u1, x.u2};
    plus[j] += h;
    minus[j] -= h;
    const OdeState up =
        equations.stateDerivative(State{plus[0], plus[1], plus[2], plus[3]}, torque);
    const OdeState down =
        equations.stateDerivative(State{minus[0], minus[1], minus[2], minus[3]}, torque);
    for (int i = 0; i < 4; ++i) A(i, j) = (up[i] - down[i]) / (2 * h);
  }
  if (!A.allFinite()) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::EigenSolver<Eigen::Matrix4d> solver(A, false);
  if (solver.info() != Eigen::Success) return std::numeric_limits<double>::quiet_NaN();
  const double rate = solver.eigenvalues().cwiseAbs().maxCoeff();
  return std::isfinite(rate) ? rate : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

double fastestRate(const MechanismModel& model, const State& x, double torque) {
  return rateOf(GeneratedMechanism(withMotorLineAsDamper(model)), x, torque);
}

StiffestConfiguration stiffestConfiguration(const MechanismModel& model, const State& start) {
  const GeneratedMechanism equations(withMotorLineAsDamper(model));
  StiffestConfiguration stiffest;
  const double energy = model.energy(start).total();  // E0, what the motion has to spend
  for (int i = 0; i < kCrankSamples; ++i) {
    const double q1 = 2 * M_PI * i / kCrankSamples;
    State x;
    x.q1 = q1;
    x.q2 = model.geometry(q1, 0.0).pin_b.x() + model.springRestLength();
    // The crank's speed there if all of E0 - V went into it: a light crank (small M11) swings
    // fast, and its centripetal terms are rates of their own.
    const double kinetic = energy - model.energy(x).total();
    const double m11 = model.equations(x, 0.0).mass_matrix(0, 0);
    State moving = x;
    moving.u1 = kinetic > 0.0 ? std::sqrt(2.0 * kinetic / m11) : 0.0;
    for (const State& at : {x, moving}) {
      const double rate = rateOf(equations, at, 0.0);
      if (!std::isfinite(rate)) return {std::numeric_limits<double>::quiet_NaN(), q1, at.u1};
      if (rate > stiffest.rate) stiffest = {rate, q1, at.u1};
    }
  }
  return stiffest;
}

}  // namespace kane_sim
