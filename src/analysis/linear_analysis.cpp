#include "kane_sim/analysis/linear_analysis.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>
#include <type_traits>

#include <Eigen/Eigenvalues>

namespace kane_sim {
namespace {

// Five-point central difference of a (scalar or Eigen vector) function of one variable: error
// O(h^4). The result is evaluated here: an Eigen expression would outlive its temporaries.
template <class F>
auto derivative(const F& f, double x0, double h) {
  using Result = std::decay_t<decltype(f(x0))>;
  const Result result =
      ((f(x0 - 2 * h) - f(x0 + 2 * h)) + 8.0 * (f(x0 + h) - f(x0 - h))) / (12.0 * h);
  return result;
}

double stepFor(double value) { return 1e-3 * (1.0 + std::abs(value)); }

// F_r (active) + F*_r at u' = 0 with u = 0: what must vanish at a static equilibrium.
SpeedVector staticForcing(const MechanismModel& model, double q1, double q2, double torque) {
  return model.equations(State{q1, q2, 0.0, 0.0}, torque).forcing();
}

std::string format(double value) {
  std::ostringstream out;
  out.precision(6);
  out << value;
  return out.str();
}

// q2 where slider 4 is in equilibrium for a crank held at q1 (F_2 = 0), by Newton from the
// spring's rest position below slider 3.
double balancedQ2(const MechanismModel& model, double q1) {
  double q2 = model.geometry(q1, 0.0).pin_b.x() + model.springRestLength();
  for (int iteration = 0; iteration < 60; ++iteration) {
    const auto f2 = [&](double q) { return staticForcing(model, q1, q, 0.0)[1]; };
    const double value = f2(q2);
    const double slope = derivative([&](double q) { return f2(q); }, q2, stepFor(q2));
    if (!(std::abs(slope) > 1e-12))
      throw AnalysisError(
          "slider 4 has no static equilibrium: nothing along the rail holds it against gravity "
          "(mechanism.spring_stiffness is 0)");
    const double step = value / slope;
    q2 -= step;
    if (std::abs(step) <= 1e-15 * (1.0 + std::abs(q2))) break;
  }
  return q2;
}

// The crank torque that holds the crank at q1 (slider 4 balanced): -F_1 at M_m = 0.
double holdingTorque(const MechanismModel& model, double q1) {
  return -staticForcing(model, q1, balancedQ2(model, q1), 0.0)[0];
}

constexpr double kQuarterTurn = M_PI / 2;

}  // namespace

HoldingLimit maxHoldingTorque(const MechanismModel& model) {
  // The first maximum of the holding torque on [0, pi/2): sampled, then refined by golden
  // section. (For the textbook's mechanism it is 4 g L (m + M1 + M2) sin q1, largest at pi/2.)
  constexpr int kSamples = 400;
  const double top = kQuarterTurn * (1.0 - 1e-12);
  int best = 0;
  double best_value = holdingTorque(model, 0.0);
  for (int i = 1; i <= kSamples; ++i) {
    const double value = holdingTorque(model, top * i / kSamples);
    if (value < best_value) break;
    best = i;
    best_value = value;
  }
  double lo = top * std::max(0, best - 1) / kSamples;
  double hi = top * std::min(kSamples, best + 1) / kSamples;
  const double ratio = (std::sqrt(5.0) - 1) / 2;
  for (int i = 0; i < 100 && hi - lo > 1e-14; ++i) {
    const double a = hi - ratio * (hi - lo), b = lo + ratio * (hi - lo);
    if (holdingTorque(model, a) < holdingTorque(model, b))
      lo = a;
    else
      hi = b;
  }
  const double q1 = std::min((lo + hi) / 2, top);
  return {std::max(holdingTorque(model, q1), best_value), q1};
}

State staticEquilibrium(const MechanismModel& model, double torque) {
  if (!std::isfinite(torque))
    throw AnalysisError("torque " + format(torque) + " N m is not finite");
  const HoldingLimit limit = maxHoldingTorque(model);
  if (torque != 0.0 && !(limit.torque > 1e-9 * std::abs(torque)))
    throw AnalysisError("a crank torque of " + format(torque) +
                        " N m has no equilibrium: with mechanism.gravity " +
                        format(model.parameters().gravity) +
                        " nothing holds the crank against a torque (it turns over)");
  if (std::abs(torque) > limit.torque)
    throw AnalysisError("a crank torque of " + format(torque) +
                        " N m is beyond what gravity can hold: at most " + format(limit.torque) +
                        " N m either way (reached at |q1| = " + format(limit.q1) +
                        " rad); beyond it the crank turns over");
  // The holding torque rises from 0 at q1 = 0 to the limit: bisect on that branch (the crank
  // hangs below O, |q1| < pi/2: the stable one). The mechanism is symmetric in q1 -> -q1.
  const double sign = torque < 0 ? -1.0 : 1.0;
  double lo = 0.0, hi = limit.q1;
  for (int i = 0; i < 200 && hi - lo > 1e-16 * (1.0 + hi); ++i) {
    const double mid = (lo + hi) / 2;
    (sign * holdingTorque(model, sign * mid) < std::abs(torque) ? lo : hi) = mid;
  }
  const double q1 = sign * (lo + hi) / 2;
  return State{q1, balancedQ2(model, q1), 0.0, 0.0};
}

LinearModel linearize(const MechanismModel& model, const State& x, double torque) {
  LinearModel linear;
  linear.operating_point = x;
  linear.torque = torque;
  const Eigen::Vector4d x0(x.q1, x.q2, x.u1, x.u2);
  const auto rates = [&](const Eigen::Vector4d& v, double m) {
    const OdeState d = model.stateDerivative(State{v[0], v[1], v[2], v[3]}, m);
    return Eigen::Vector4d(d[0], d[1], d[2], d[3]);
  };
  const auto forcing = [&](const Eigen::Vector4d& v) {
    return Eigen::Vector2d(model.equations(State{v[0], v[1], v[2], v[3]}, torque).forcing());
  };
  // A law with a rate scale of its own (smoothed Coulomb friction bends within v_s of rest): the
  // speeds' step must stay well inside that bend (1/100 of it: the stencil's error ~ (h / v_s)^4
  // ~ 1e-8 of the slope F_c / v_s).
  const generated::RateScale scale = generated::smallestRateScale(model.constants());
  const auto step = [&](int j) {
    const double h = stepFor(x0[j]);
    return j >= 2 ? std::min(h, 1e-2 * scale.value) : h;  // infinite: no such law in use
  };
  if (scale.constant >= 0) {
    const std::string key = generated::kConstantKeys[scale.constant];
    linear.notes.push_back(
        "Coulomb friction is linearized as a damper of F_c / " + key +
        " at each joint: true of the smoothed law for speeds well below " + key +
        ", not of dry friction (whose slope at rest is unbounded and which holds any equilibrium "
        "within a band of loads); the damping ratios are the smoothing's");
  }
  for (int j = 0; j < 4; ++j) {
    const auto along = [&](double value) {
      Eigen::Vector4d v = x0;
      v[j] = value;
      return v;
    };
    linear.A.col(j) = derivative([&](double s) { return rates(along(s), torque); }, x0[j], step(j));
    const Eigen::Vector2d dforcing =
        derivative([&](double s) { return forcing(along(s)); }, x0[j], step(j));
    (j < 2 ? linear.stiffness.col(j) : linear.damping.col(j - 2)) = -dforcing;
  }
  linear.B = derivative([&](double m) { return rates(x0, m); }, torque, stepFor(torque));
  linear.mass = model.equations(x, torque).mass_matrix;
  return linear;
}

ModalAnalysis modalAnalysis(const LinearModel& linear) {
  ModalAnalysis result;
  // Undamped: K phi = w^2 M phi. K is the Hessian of the potential (a constant torque has one,
  // -M_m q1), symmetric up to the differences' rounding.
  const Eigen::Matrix2d K = (linear.stiffness + linear.stiffness.transpose()) / 2;
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> undamped(K, linear.mass);
  // A stiffness eigenvalue within the differences' noise (~1e-10 of the largest) is zero: a
  // neutral direction (gravity 0 leaves the crank without a restoring moment), not a mode of
  // some microhertz.
  const double scale = undamped.eigenvalues().cwiseAbs().maxCoeff();
  for (int i = 0; i < 2; ++i) {
    const double w2 = undamped.eigenvalues()[i];
    Mode mode;
    if (std::abs(w2) <= kNeutralStiffness * scale || scale == 0.0) {
      mode.neutral = true;
    } else if (!(w2 > 0)) {
      throw AnalysisError("the operating point is not a stable equilibrium (stiffness eigenvalue " +
                          format(w2) + "): no natural frequency");
    } else {
      mode.natural_frequency_hz = std::sqrt(w2) / (2 * M_PI);
    }
    Eigen::Vector2d shape = undamped.eigenvectors().col(i);
    Eigen::Index largest = 0;
    shape.cwiseAbs().maxCoeff(&largest);
    mode.shape = shape / shape[largest];
    result.modes.push_back(mode);
  }
  // Damped: A's eigenvalues, each assigned to the undamped mode that dominates its eigenvector
  // (the configuration part phi of (phi, lambda phi) in modal coordinates eta = Phi^T M phi),
  // so that a mode's two eigenvalues, complex conjugates or two real ones when overdamped, are
  // taken together whatever their sizes.
  const Eigen::EigenSolver<Eigen::Matrix4d> damped(linear.A);
  const Eigen::Matrix2cd to_modal =
      (undamped.eigenvectors().transpose() * linear.mass).cast<std::complex<double>>();
  std::vector<std::complex<double>> of_mode[2];
  for (int i = 0; i < 4; ++i) {
    const std::complex<double> lambda = damped.eigenvalues()[i];
    result.eigenvalues.push_back(lambda);
    const Eigen::Vector2cd eta = to_modal * damped.eigenvectors().col(i).head<2>();
    of_mode[std::abs(eta[1]) > std::abs(eta[0]) ? 1 : 0].push_back(lambda);
  }
  std::sort(result.eigenvalues.begin(), result.eigenvalues.end(), [](auto a, auto b) {
    return std::abs(a) != std::abs(b) ? std::abs(a) < std::abs(b) : a.imag() < b.imag();
  });
  for (int k = 0; k < 2; ++k) {
    Mode& mode = result.modes[k];
    if (mode.neutral || of_mode[k].size() != 2) continue;  // zeta undefined: NaN
    const std::complex<double> a = of_mode[k][0], b = of_mode[k][1];
    // lambda1 lambda2 = w^2 and -(lambda1 + lambda2) = 2 zeta w, for a conjugate pair and for two
    // real roots (overdamped, zeta > 1) alike.
    const double w = std::sqrt(std::abs(a * b));
    const double zeta = -(a + b).real() / (2 * w);
    // Without damping the real parts are rounding noise (~1e-15 of |lambda|): report 0 then.
    mode.damping_ratio = std::abs(zeta) < 1e-12 ? 0.0 : zeta;
  }
  return result;
}

}  // namespace kane_sim
