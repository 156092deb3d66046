// LQR at an equilibrium of the mechanism, as Drake's LinearQuadraticRegulator designs it: the
// crank held at rest at q1 (any angle; q1 = pi is upright and unstable) by its holding moment
// M_eq, the exact linearization there (analysis/linear_analysis.h), and the gain K that
// minimizes the integral of x~' Q x~ + R M~^2 for x~ = x - x_eq, M~ = M_m - M_eq:
//
//   M_m = M_eq - K (x - x_eq),   x = (q1, q2, u1, u2),   K = R^-1 B' P   (1 x 4)
//
// P the stabilizing solution of the Riccati equation (design/riccati.h) on the states the torque
// can move; a mode it cannot move is left as it is (refused if it grows). ROS-free.
#ifndef KANE_SIM_DESIGN_LQR_H
#define KANE_SIM_DESIGN_LQR_H

#include <complex>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "kane_sim/analysis/equilibria.h"
#include "kane_sim/config/config.h"
#include "kane_sim/design/state_feedback.h"
#include "kane_sim/model/mechanism_model.h"

namespace kane_sim {

struct LqrWeights {
  Eigen::Matrix4d Q = Eigen::Matrix4d::Zero();  // on (q1 [rad], q2 [m], u1 [rad/s], u2 [m/s])
  double R = 0.0;                               // on M_m [N m]
};

// Bryson's rule: each weight 1 / (the deviation that is acceptable)^2: 0.1 rad of the crank,
// 0.01 m of slider 4, 1 rad/s and 0.1 m/s, and the whole torque limit (command.torque_limit; the
// largest holding moment when there is none).
LqrWeights defaultLqrWeights(const Config& config, const MechanismModel& model);

struct LqrDesign {
  HeldEquilibrium equilibrium;  // x_eq and the holding moment M_eq
  Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
  Eigen::Vector4d B = Eigen::Vector4d::Zero();
  LqrWeights weights;
  Eigen::Matrix4d P = Eigen::Matrix4d::Zero();
  std::vector<std::complex<double>> open_loop;    // eigenvalues of A, by real part
  std::vector<std::complex<double>> closed_loop;  // of A - B K, by real part
  double riccati_residual = 0.0;                  // relative, on the controllable states
  // The law: x_eq, M_eq and K; periodic (the crank's error within (-pi, pi], so a crank that
  // arrives a turn away is held, not unwound) when no crank spring breaks the turn's symmetry.
  StateFeedback feedback;
  // The states the crank's torque can move (Kalman's decomposition; 4 x r, orthonormal): the
  // Riccati equation is solved there, P = T P1 T'. r < 4 at q1 = 0 and pi, where slider 4's
  // oscillation is out of the crank's reach; `notes` then says so.
  Eigen::MatrixXd controllable_basis;
  // A controller samples the law: 5 times the fastest closed-loop |eigenvalue| [readings/s] is
  // a rule of thumb for the readings it needs (|lambda| dt <= 0.2); slower, raise R.
  double sample_rate_needed = 0.0;
  std::vector<std::string> notes;
};

// Throws AnalysisError (no equilibrium at q1) or RiccatiError (bad weights, or no stabilizing
// gain: the slider uncontrollable, e.g. with no spring), in words.
LqrDesign designLqr(const MechanismModel& model, double q1, const LqrWeights& weights);

}  // namespace kane_sim

#endif  // KANE_SIM_DESIGN_LQR_H
