// Whether rk4 at a fixed step can integrate the mechanism: the one check behind the loader (at
// start-up and at every runtime reconfiguration) and set_state.
//
// rk4's region of absolute stability reaches 2.785 along the imaginary axis (an undamped mode of
// angular frequency w) and 2.785 along the negative real axis (a damped rate c/m): a linearised
// rate lambda is integrated stably only while |lambda| h stays below that. The rates depend on
// the configuration (the crank's inertia varies threefold with q1, so a damper's c/M11 does) and
// on the speeds (the centripetal terms), so the bound is taken over a sampled turn of the crank.
#ifndef KANE_SIM_ANALYSIS_STABILITY_H
#define KANE_SIM_ANALYSIS_STABILITY_H

#include "kane_sim/model/mechanism_model.h"

namespace kane_sim {

// |lambda| h at most this: rk4's limit 2.785 with a margin.
constexpr double kRk4StabilityLimit = 2.5;

// The largest |eigenvalue| of the linearised motion at x under `torque` [1/s]. The motor line,
// when on, acts within its band as a crank damper of torque_limit / w0 and is counted as one
// (its corner at u1 = 0 has no derivative). NaN when the linearisation is not finite.
double fastestRate(const MechanismModel& model, const State& x, double torque);

struct StiffestConfiguration {
  double rate = 0.0;  // [1/s] largest |eigenvalue| over the sampled states (NaN: not finite)
  double q1 = 0.0;    // [rad] where
  double u1 = 0.0;    // [rad/s] at what crank speed
};
// The fastest rate over the states the motion can reach from `start` without a torque: a turn of
// the crank (36 samples of q1, slider 4 where the spring is unstretched), each at rest and with
// the crank as fast as the start's energy lets it be there. A torque adds energy, so a driven
// motion can go beyond this; the simulator refuses a step rk4 cannot resolve.
StiffestConfiguration stiffestConfiguration(const MechanismModel& model, const State& start);
// Whether rate * step <= limit for fastestRate(model, start, 0) and every rate
// stiffestConfiguration samples (false when one is not finite): their answer, without their
// eigenvalues where a cheap upper bound already settles a state (a config's check: ~90 -> ~23
// us a mechanism, measured).
bool ratesWithin(const MechanismModel& model, const State& start, double step, double limit);

}  // namespace kane_sim

#endif  // KANE_SIM_ANALYSIS_STABILITY_H
