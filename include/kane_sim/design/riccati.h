// The continuous algebraic Riccati equation of LQR, A' P + P A - P B R^-1 B' P + Q = 0: its
// stabilizing solution P (A - B R^-1 B' P Hurwitz), as SciPy's solve_continuous_are and Drake's
// ContinuousAlgebraicRiccatiEquation give it. ROS-free.
#ifndef KANE_SIM_DESIGN_RICCATI_H
#define KANE_SIM_DESIGN_RICCATI_H

#include <stdexcept>

#include <Eigen/Core>

namespace kane_sim {

class RiccatiError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A n x n, B n x m, Q n x n symmetric positive semidefinite, R m x m symmetric positive definite.
// The matrix sign function of the Hamiltonian [A -G; -Q -A'] (G = B R^-1 B'; Newton's iteration
// with determinant scaling, Byers 1987, as Drake's), then Newton-Kleinman steps (one Lyapunov
// equation each, in Kronecker form: small n) to the equation's rounding. Throws RiccatiError,
// in words, for a bad shape, a non-finite entry, Q or R out of their cones, and when no
// stabilizing solution exists ((A, B) not stabilizable, or an unstable mode Q does not see).
Eigen::MatrixXd solveContinuousRiccati(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
                                       const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R);

// Q symmetric positive semidefinite, R symmetric positive definite, both finite; RiccatiError
// naming which otherwise.
void checkRiccatiWeights(const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R);

// ||A' P + P A - P B R^-1 B' P + Q|| / max(||Q||, ||A' P||, ...): the relative residual.
double riccatiResidual(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, const Eigen::MatrixXd& Q,
                       const Eigen::MatrixXd& R, const Eigen::MatrixXd& P);

}  // namespace kane_sim

#endif  // KANE_SIM_DESIGN_RICCATI_H
