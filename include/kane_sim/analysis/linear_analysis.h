// Linear analysis of the mechanism, as SymPy's Linearizer or Drake's Linearize give it: the
// static equilibrium under a constant crank torque, the state-space model about it
// (x = (q1, q2, u1, u2), input M_m: x' = A x + B M_m), its eigenvalues, the undamped natural
// frequencies and mode shapes, and the damping ratios.
//
// Derivatives are 4th-order central differences (five-point stencil, Richardson) of the same
// Kane equations the simulator integrates: truncation O(h^4) ~ 1e-13 with h = 1e-3, rounding
// ~ 1e-13 relative, so the entries are good to ~1e-10 relative — better than the 1e-8 asked of
// them — while every model option (damping, the motor line, contact) is covered without a second
// derivation. Differences need smoothness: the motor line's corner (|M_m| at the limit) and the
// contact's first touch are not differentiable; an operating point on them gives one-sided mixes.
#ifndef KANE_SIM_ANALYSIS_LINEAR_ANALYSIS_H
#define KANE_SIM_ANALYSIS_LINEAR_ANALYSIS_H

#include <array>
#include <complex>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

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

struct LinearModel {
  State operating_point;
  double torque = 0.0;
  Eigen::Matrix4d A = Eigen::Matrix4d::Zero();     // d x'/d x, rows and columns (q1, q2, u1, u2)
  Eigen::Vector4d B = Eigen::Vector4d::Zero();     // d x'/d M_m
  Eigen::Matrix2d mass = Eigen::Matrix2d::Zero();  // M (Kane's mass matrix)
  Eigen::Matrix2d stiffness = Eigen::Matrix2d::Zero();  // K = -d forcing / d q at u = 0
  Eigen::Matrix2d damping = Eigen::Matrix2d::Zero();    // C = -d forcing / d u
  // What the linear model leaves out or approximates, in words (analyze's "notes").
  std::vector<std::string> notes;
};
LinearModel linearize(const MechanismModel& model, const State& x, double torque);

// A stiffness eigenvalue within this fraction of the largest one is zero (the differences'
// noise is ~1e-10 relative): the equilibrium is neutral along that mode.
constexpr double kNeutralStiffness = 1e-8;

struct Mode {
  double natural_frequency_hz = 0.0;  // undamped: sqrt of an eigenvalue of M^-1 K, / 2 pi
  // From the two eigenvalues of A that belong to this mode: -(l1 + l2) / (2 sqrt(l1 l2)), for a
  // conjugate pair (< 1) or two real ones (overdamped, > 1); 0 without damping. NaN where it is
  // undefined: a neutral mode, or eigenvalues that could not be told apart between the modes.
  double damping_ratio = std::numeric_limits<double>::quiet_NaN();
  bool neutral = false;  // no restoring stiffness along this shape: frequency 0, zeta NaN
  Eigen::Vector2d shape = Eigen::Vector2d::Zero();  // (q1 [rad], q2 [m]), largest entry +-1
};
struct ModalAnalysis {
  std::vector<std::complex<double>> eigenvalues;  // of A, by |lambda| then imaginary part
  std::vector<Mode> modes;                        // ascending natural frequency
};
// Throws AnalysisError when K has a negative eigenvalue (an unstable equilibrium has no natural
// frequency); a zero one (within kNeutralStiffness) is a neutral mode.
ModalAnalysis modalAnalysis(const LinearModel& linear);

}  // namespace kane_sim

#endif  // KANE_SIM_ANALYSIS_LINEAR_ANALYSIS_H
