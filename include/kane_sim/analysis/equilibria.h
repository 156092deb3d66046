// The mechanism's static equilibria (u = 0, u' = 0): slider 4 balanced on the spring for a crank
// angle, the crank moment that holds the crank there, and every equilibrium under a constant
// crank torque around the whole turn, stable (hanging, q1 = 0) or not (upright, q1 = pi).
#ifndef KANE_SIM_ANALYSIS_EQUILIBRIA_H
#define KANE_SIM_ANALYSIS_EQUILIBRIA_H

#include <stdexcept>
#include <string>
#include <vector>

#include "kane_sim/model/mechanism_model.h"

namespace kane_sim {

class AnalysisError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The largest constant crank torque gravity (and the spring) can balance with |q1| < pi/2 [N m],
// and the crank angle where it does [rad]. Torques are signed: the bound is symmetric here.
struct HoldingLimit {
  double torque = 0.0;
  double q1 = 0.0;
};
HoldingLimit maxHoldingTorque(const MechanismModel& model);

// The equilibrium under `torque` on the branch through q1 = 0 (the stable one, |q1| < pi/2),
// u = 0. Throws AnalysisError naming the limit when the torque is beyond it, or when slider 4
// has no equilibrium (no spring to hold it against gravity).
State staticEquilibrium(const MechanismModel& model, double torque);

// The crank held at q1 [rad] (any angle: q1 = pi is the crank upright, above O) with slider 4
// balanced, at rest, and the constant crank moment M_m [N m] that holds it there.
struct HeldEquilibrium {
  State state;
  double torque = 0.0;
};
HeldEquilibrium equilibriumAt(const MechanismModel& model, double q1);

// An equilibrium under a constant torque, and what its linearization says of it (modalAnalysis):
// stable, unstable or neutral.
struct Equilibrium {
  State state;
  std::string stability;                 // "stable", "unstable" or "neutral"
  double largest_real_eigenvalue = 0.0;  // of A [1/s]
};
// Every equilibrium under `torque` with q1 in (-pi, pi], in ascending q1: where the holding
// moment of equilibriumAt equals `torque` (sampled at 720 angles, each sign change refined by
// bisection to ~1e-15 rad). A root where the holding moment only touches `torque` (a fold) can
// be missed; for the textbook mechanism at 0 N m they are q1 = 0 (stable) and pi (unstable).
std::vector<Equilibrium> equilibria(const MechanismModel& model, double torque);

}  // namespace kane_sim

#endif  // KANE_SIM_ANALYSIS_EQUILIBRIA_H
