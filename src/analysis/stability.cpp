#include "kane_sim/analysis/stability.h"

#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include "kane_sim/analysis/linear_analysis.h"

namespace kane_sim {
namespace {

constexpr int kCrankSamples = 72;  // every 5 degrees: M11(q1) varies smoothly, as cos 2 q1

// The model with the motor line's slope as a crank damper (see fastestRate).
MechanismModel withMotorLineAsDamper(const MechanismModel& model) {
  MechanismParameters p = model.parameters();
  if (p.motor.no_load_speed > 0.0 && std::isfinite(p.motor.torque_limit))
    p.damping.crank += p.motor.torque_limit / p.motor.no_load_speed;
  return MechanismModel(p, model.springRestLength());
}

}  // namespace

double fastestRate(const MechanismModel& model, const State& x, double torque) {
  const LinearModel linear = linearize(withMotorLineAsDamper(model), x, torque);
  if (!linear.A.allFinite()) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::EigenSolver<Eigen::Matrix4d> solver(linear.A, false);
  if (solver.info() != Eigen::Success) return std::numeric_limits<double>::quiet_NaN();
  const double rate = solver.eigenvalues().cwiseAbs().maxCoeff();
  return std::isfinite(rate) ? rate : std::numeric_limits<double>::quiet_NaN();
}

StiffestConfiguration stiffestConfiguration(const MechanismModel& model, const State& start) {
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
      const double rate = fastestRate(model, at, 0.0);
      if (!std::isfinite(rate)) return {std::numeric_limits<double>::quiet_NaN(), q1, at.u1};
      if (rate > stiffest.rate) stiffest = {rate, q1, at.u1};
    }
  }
  return stiffest;
}

}  // namespace kane_sim
