#include "kane_sim/analysis/equilibria.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>

#include "kane_sim/analysis/linear_analysis.h"
#include "kane_sim/model/generated_mechanism.h"

namespace kane_sim {
namespace {

std::string format(double value) {
  std::ostringstream out;
  out.precision(6);
  out << value;
  return out.str();
}

// q2 where slider 4 is in equilibrium for a crank held at rest at q1 (u2' = 0), by Newton from
// the spring's rest position below slider 3 with the exact slope d u2'/d q2.
double balancedQ2(const MechanismModel& model, double q1) {
  const GeneratedMechanism equations(model);
  double q2 = model.geometry(q1, 0.0).pin_b.x() + model.springRestLength();
  for (int iteration = 0; iteration < 60; ++iteration) {
    const State at{q1, q2, 0.0, 0.0};
    const double value = model.accelerations(at, 0.0)[1];
    const double slope = equations.linearization(at, 0.0).A(3, 1);
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

// The crank moment that holds the crank at rest at q1 (slider 4 balanced).
double holdingTorque(const MechanismModel& model, double q1) {
  return model.holdingMoment(State{q1, balancedQ2(model, q1), 0.0, 0.0});
}

constexpr double kQuarterTurn = M_PI / 2;

// q1 wrapped into (-pi, pi].
double wrapAngle(double q1) {
  const double wrapped = std::remainder(q1, 2 * M_PI);
  return wrapped <= -M_PI ? wrapped + 2 * M_PI : wrapped;
}

// The widest search: 720 samples a turn, ~30 ms a turn (a weaker crank spring spreads its
// equilibria further: analyze --q1 holds the crank at any angle).
constexpr double kWidestSearch = 200.0;  // [rad]

// Every equilibrium under `torque` with q1 in [from, to] (q1 wrapped into (-pi, pi] when the
// equations repeat every turn).
std::vector<Equilibrium> equilibriaIn(const MechanismModel& model, double torque, double from,
                                      double to);

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
  if (model.parameters().crank_spring_stiffness != 0.0) {
    // The crank spring holds any torque somewhere: the stable equilibrium nearest the hanging
    // crank (q1 = 0) among all of them.
    const State* best = nullptr;
    // The turn about the hanging crank first (a weak spring spreads its equilibria over many
    // turns); all of them when none is stable there.
    std::vector<Equilibrium> found = equilibriaIn(model, torque, -M_PI, M_PI);
    if (std::none_of(found.begin(), found.end(),
                     [](const Equilibrium& e) { return e.stability == "stable"; }))
      found = equilibria(model, torque);
    for (const Equilibrium& e : found)
      if (e.stability == "stable" && (!best || std::abs(e.state.q1) < std::abs(best->q1)))
        best = &e.state;
    if (!best)
      throw AnalysisError("a crank torque of " + format(torque) +
                          " N m has no stable equilibrium (" + std::to_string(found.size()) +
                          " unstable or neutral ones: analyze --equilibria lists them)");
    return *best;
  }
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

HeldEquilibrium equilibriumAt(const MechanismModel& model, double q1) {
  if (!std::isfinite(q1) || std::abs(q1) > 1e6)
    throw AnalysisError("crank angle q1 " + format(q1) +
                        " rad is not a finite angle within 1e6 rad");
  const State state{q1, balancedQ2(model, q1), 0.0, 0.0};
  return {state, model.holdingMoment(state)};
}

namespace {

// The root of f in [lo, hi] where f(lo), f(hi) differ in sign, by bisection to ~1e-15 rad.
double bisect(const std::function<double(double)>& f, double lo, double hi) {
  const bool lo_negative = f(lo) < 0;
  for (int k = 0; k < 200 && hi - lo > 1e-15 * (1.0 + std::abs(hi)); ++k) {
    const double mid = (lo + hi) / 2;
    ((f(mid) < 0) == lo_negative ? lo : hi) = mid;
  }
  return (lo + hi) / 2;
}

// The extremum of f in [lo, hi] (a maximum when `maximum`), by golden section.
double extremum(const std::function<double(double)>& f, double lo, double hi, bool maximum) {
  const double ratio = (std::sqrt(5.0) - 1) / 2;
  for (int i = 0; i < 200 && hi - lo > 1e-15 * (1.0 + std::abs(hi)); ++i) {
    const double a = hi - ratio * (hi - lo), b = lo + ratio * (hi - lo);
    ((f(a) < f(b)) == maximum ? lo : hi) = (f(a) < f(b)) == maximum ? a : b;
  }
  return (lo + hi) / 2;
}

}  // namespace

std::vector<Equilibrium> equilibria(const MechanismModel& model, double torque) {
  if (!std::isfinite(torque))
    throw AnalysisError("torque " + format(torque) + " N m is not finite");
  // Where to look: one turn, (-pi, pi], when the equations repeat every turn; with a crank spring
  // (k_t) the holding moment is k_t (q1 - q1_0) plus a bounded part G (gravity and the spring:
  // the same mechanism without k_t), so every equilibrium lies within (torque +- G) / k_t of q1_0.
  const double k_t = model.parameters().crank_spring_stiffness;
  if (k_t == 0.0) return equilibriaIn(model, torque, -M_PI, M_PI);
  MechanismParameters without = model.parameters();
  without.crank_spring_stiffness = 0.0;
  const double bounded = maxHoldingTorque(MechanismModel(without, model.springRestLength())).torque;
  const double center = model.parameters().crank_spring_rest_angle + torque / k_t;
  const double reach = std::abs(bounded / k_t) + 0.1;
  if (!(2 * reach <= kWidestSearch) || !(std::abs(center) < 1e6))
    throw AnalysisError("with mechanism.crank_spring_stiffness " + format(k_t) +
                        " N m/rad the equilibria under " + format(torque) + " N m spread over " +
                        format(2 * reach) + " rad about q1 = " + format(center) +
                        " rad, more than a search covers (" + format(kWidestSearch) +
                        " rad): analyze --q1 holds the crank at any angle");
  return equilibriaIn(model, torque, center - reach, center + reach);
}

namespace {

std::vector<Equilibrium> equilibriaIn(const MechanismModel& model, double torque, double from,
                                      double to) {
  const double k_t = model.parameters().crank_spring_stiffness;
  const std::function<double(double)> excess = [&](double q1) {
    return holdingTorque(model, q1) - torque;
  };
  // 720 samples a turn, offset by half a step from -pi, 0 and pi (the textbook's equilibria): a
  // root lies inside an interval, not on its end. A sign change is bisected; where the samples
  // turn (an extremum between them) the extremum is found, and when it crosses the torque (two
  // roots close together: near the holding limit, a fold) each side is bisected.
  const int samples = std::max(720, static_cast<int>(std::ceil((to - from) / (2 * M_PI) * 720)));
  const double step = (to - from) / samples;
  std::vector<double> q(samples + 1), f(samples + 1);
  for (int i = 0; i <= samples; ++i) {
    q[i] = from - step / 2 + i * step;
    f[i] = excess(q[i]);
  }
  double largest = 0.0;
  for (double value : f) largest = std::max(largest, std::abs(value));
  // The size of the moments at play: the torque, the spring's k L^2, gravity's on every body, k_t.
  const MechanismParameters& p = model.parameters();
  const double L = p.rod_half_length;
  const double scale =
      std::abs(torque) + p.spring_stiffness * L * L +
      (2 * p.rod_mass + p.slider3_mass + p.slider4_mass) * std::abs(p.gravity) * L + std::abs(k_t);
  if (largest <= 1e-12 * scale)
    throw AnalysisError("every crank angle is an equilibrium under " + format(torque) +
                        " N m: nothing turns the crank (mechanism.gravity 0, no crank spring)");
  std::vector<double> roots;
  for (int i = 0; i < samples; ++i) {
    if (f[i] == 0.0) roots.push_back(q[i]);
    if ((f[i] < 0) != (f[i + 1] < 0) && f[i] != 0.0 && f[i + 1] != 0.0)
      roots.push_back(bisect(excess, q[i], q[i + 1]));
    if (i == 0) continue;
    const bool peak = f[i] > f[i - 1] && f[i] >= f[i + 1];
    const bool dip = f[i] < f[i - 1] && f[i] <= f[i + 1];
    if (!peak && !dip) continue;
    const double at = extremum(excess, q[i - 1], q[i + 1], peak);
    const double value = excess(at);
    // Crossing between two samples of the same sign: two roots the samples missed.
    const bool one_sign = (f[i - 1] < 0) == (f[i] < 0) && (f[i] < 0) == (f[i + 1] < 0);
    if (one_sign && value != 0.0 && (value < 0) != (f[i] < 0)) {
      roots.push_back(bisect(excess, q[i - 1], at));
      roots.push_back(bisect(excess, at, q[i + 1]));
    }
  }
  const bool periodic = k_t == 0.0;
  std::vector<Equilibrium> found;
  for (double root : roots) {
    const double q1 = periodic ? wrapAngle(root) : root;
    if (std::any_of(found.begin(), found.end(), [&](const Equilibrium& e) {
          const double apart = e.state.q1 - q1;
          return std::abs(periodic ? wrapAngle(apart) : apart) < 1e-9;
        }))
      continue;
    Equilibrium e;
    e.state = State{q1, balancedQ2(model, q1), 0.0, 0.0};
    const ModalAnalysis modal = modalAnalysis(linearize(model, e.state, torque));
    e.stability = modal.stability;
    double fastest = 0.0;
    e.largest_real_eigenvalue = -INFINITY;
    for (const auto& lambda : modal.eigenvalues) {
      e.largest_real_eigenvalue = std::max(e.largest_real_eigenvalue, lambda.real());
      fastest = std::max(fastest, std::abs(lambda));
    }
    // Rounding's real parts of an undamped pair (~1e-15 of |lambda|) are 0.
    if (std::abs(e.largest_real_eigenvalue) <= 1e-12 * fastest) e.largest_real_eigenvalue = 0.0;
    found.push_back(e);
  }
  std::sort(found.begin(), found.end(),
            [](const Equilibrium& x, const Equilibrium& y) { return x.state.q1 < y.state.q1; });
  return found;
}

}  // namespace

}  // namespace kane_sim
