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
    p.damping.crank_joint += p.motor.torque_limit / p.motor.no_load_speed;
  return MechanismModel(p, model.springRestLength());
}

// A = d x'/d x: the generated equations' exact derivatives (the fast path's physics).
Eigen::Matrix4d jacobianOf(const GeneratedMechanism& equations, const State& x, double torque) {
  return equations.linearization(x, torque).A;
}

// The largest |eigenvalue| of A; NaN when A or its eigenvalues are not finite.
double spectralRadius(const Eigen::Matrix4d& A) {
  if (!A.allFinite()) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::EigenSolver<Eigen::Matrix4d> solver(A, false);
  if (solver.info() != Eigen::Success) return std::numeric_limits<double>::quiet_NaN();
  const double rate = solver.eigenvalues().cwiseAbs().maxCoeff();
  return std::isfinite(rate) ? rate : std::numeric_limits<double>::quiet_NaN();
}

// An upper bound of spectralRadius(A) at the cost of a few sums (+inf when A is not finite):
// the row-sum norm of D^-1 A D, D = diag(1, 1, s, s), which has A's eigenvalues. With
// A = [0 I; K C] (q' = u) and s = sqrt(|K|), it is about sqrt(|K|) + |C|: an undamped mode's
// w exactly, a damper's or friction's rate within a small factor. The eigenvalue problem it
// spares costs ~0.8 us, 73 of them in a config's check.
double spectralRadiusBound(const Eigen::Matrix4d& A) {
  if (!A.allFinite()) return std::numeric_limits<double>::infinity();
  const Eigen::Matrix4d size = A.cwiseAbs();
  const double stiffness = std::max(size.block<2, 2>(2, 0).rowwise().sum().maxCoeff(), 1e-300);
  const double s = std::sqrt(stiffness);
  double bound = 0.0;
  for (int i = 0; i < 4; ++i) {
    const double scale_in = i < 2 ? 1.0 : 1.0 / s;  // d_i^-1
    double row = 0.0;
    for (int j = 0; j < 4; ++j) row += size(i, j) * (j < 2 ? 1.0 : s) * scale_in;
    bound = std::max(bound, row);
  }
  return bound * (1.0 + 1e-12);  // the sums' own rounding, on the safe side
}

// The states stiffestConfiguration samples, each passed to visit(state, q1) until it returns
// false.
template <class Visit>
void forEachSampledState(const MechanismModel& model, const State& start, const Visit& visit) {
  const double energy = model.energy(start).total();  // E0, what the motion has to spend
  for (int i = 0; i < kCrankSamples; ++i) {
    const double q1 = 2 * M_PI * i / kCrankSamples;
    State x;
    x.q1 = q1;
    x.q2 = model.geometry(q1, 0.0).pin_b.x() + model.springRestLength();
    // The crank's speed there if all of E0 - V went into it: a light crank (small M11) swings
    // fast, and its centripetal terms are rates of their own.
    // One energy at u = (1, 0) gives both: its potential (the speeds' share is kinetic only)
    // and M11 = 2 T (T = u^T M u / 2), without assembling the equations for one entry.
    State unit_crank_speed = x;
    unit_crank_speed.u1 = 1.0;
    const EnergyTerms at_unit_speed = model.energy(unit_crank_speed);
    const double kinetic = energy - at_unit_speed.potentialTotal();
    const double m11 = 2.0 * at_unit_speed.kinetic;
    if (!visit(x)) return;
    if (!(kinetic > 0.0)) continue;  // no speed to spend: the moving state is the one at rest
    State moving = x;
    moving.u1 = std::sqrt(2.0 * kinetic / m11);
    if (!visit(moving)) return;
  }
}

}  // namespace

double fastestRate(const MechanismModel& model, const State& x, double torque) {
  return spectralRadius(jacobianOf(GeneratedMechanism(withMotorLineAsDamper(model)), x, torque));
}

StiffestConfiguration stiffestConfiguration(const MechanismModel& model, const State& start) {
  const GeneratedMechanism equations(withMotorLineAsDamper(model));
  StiffestConfiguration stiffest;
  forEachSampledState(model, start, [&](const State& at) {
    const double rate = spectralRadius(jacobianOf(equations, at, 0.0));
    if (!std::isfinite(rate)) {
      stiffest = {std::numeric_limits<double>::quiet_NaN(), at.q1, at.u1};
      return false;
    }
    if (rate > stiffest.rate) stiffest = {rate, at.q1, at.u1};
    return true;
  });
  return stiffest;
}

bool ratesWithin(const MechanismModel& model, const State& start, double step, double limit) {
  const GeneratedMechanism equations(withMotorLineAsDamper(model));
  const auto within = [&](const State& at) {
    const Eigen::Matrix4d A = jacobianOf(equations, at, 0.0);
    if (spectralRadiusBound(A) * step <= limit) return true;  // bound >= rate: rate * step too
    return spectralRadius(A) * step <= limit;                 // NaN: false
  };
  bool all = within(start);
  if (all) forEachSampledState(model, start, [&](const State& at) { return all = within(at); });
  return all;
}

}  // namespace kane_sim
