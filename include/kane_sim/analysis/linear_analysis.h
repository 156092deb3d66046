// Linear analysis of the mechanism, as SymPy's Linearizer or Drake's Linearize give it: the
// state-space model about a state (x = (q1, q2, u1, u2), input M_m: x' = A x + B M_m), its
// eigenvalues, the undamped natural frequencies and mode shapes, and the damping ratios.
//
// Derivatives are exact: the generated equations' own, differentiated symbolically by the code
// generator (model/generated_jacobian.h), every load included, the motor line's torque-speed
// slope chained in. Two laws are not smooth everywhere: the motor line's corner (|M_m| at the
// limit) takes the side motorLineTorque takes, and the contact (impulses and a resting
// constraint the simulator adds) is not in the equations linearized.
#ifndef KANE_SIM_ANALYSIS_LINEAR_ANALYSIS_H
#define KANE_SIM_ANALYSIS_LINEAR_ANALYSIS_H

#include <array>
#include <complex>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "kane_sim/analysis/equilibria.h"
#include "kane_sim/model/mechanism_model.h"

namespace kane_sim {

struct LinearModel {
  State operating_point;
  double torque = 0.0;
  Eigen::Matrix4d A = Eigen::Matrix4d::Zero();     // d x'/d x, rows and columns (q1, q2, u1, u2)
  Eigen::Vector4d B = Eigen::Vector4d::Zero();     // d x'/d M_m
  Eigen::Matrix2d mass = Eigen::Matrix2d::Zero();  // M (Kane's mass matrix)
  // K = -M d u'/d q and C = -M d u'/d u: at a static equilibrium (u' = 0), -d F/d q and -d F/d u
  // of the forcing F (M u' = F).
  Eigen::Matrix2d stiffness = Eigen::Matrix2d::Zero();
  Eigen::Matrix2d damping = Eigen::Matrix2d::Zero();
  // What the linear model leaves out or approximates, in words (analyze's "notes").
  std::vector<std::string> notes;
};
LinearModel linearize(const MechanismModel& model, const State& x, double torque);

// A stiffness eigenvalue within this fraction of the largest one is zero (K's rounding is
// ~1e-15 relative): the equilibrium is neutral along that mode.
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
  // "stable" (K positive definite: Lagrange-Dirichlet), "neutral" (K singular: a zero one within
  // kNeutralStiffness is a neutral mode) or "unstable" (K has a negative eigenvalue, A one with a
  // positive real part; no modes: an unstable equilibrium has no natural frequency).
  std::string stability;
};
// At a static equilibrium (K and C are the forcing's derivatives there).
ModalAnalysis modalAnalysis(const LinearModel& linear);

}  // namespace kane_sim

#endif  // KANE_SIM_ANALYSIS_LINEAR_ANALYSIS_H
