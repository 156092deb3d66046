#include "kane_sim/design/riccati.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>

namespace kane_sim {
namespace {

using Eigen::MatrixXd;

std::string shape(const MatrixXd& m) {
  return std::to_string(m.rows()) + " x " + std::to_string(m.cols());
}

void checkInputs(const MatrixXd& A, const MatrixXd& B, const MatrixXd& Q, const MatrixXd& R) {
  const Eigen::Index n = A.rows(), m = B.cols();
  if (n == 0 || A.cols() != n || B.rows() != n || m == 0 || Q.rows() != n || Q.cols() != n ||
      R.rows() != m || R.cols() != m)
    throw RiccatiError("the shapes do not agree: A " + shape(A) + ", B " + shape(B) + ", Q " +
                       shape(Q) + ", R " + shape(R));
  const std::pair<const MatrixXd*, const char*> named[] = {
      {&A, "A"}, {&B, "B"}, {&Q, "Q"}, {&R, "R"}};
  for (const auto& [matrix, name] : named)
    if (!matrix->allFinite()) throw RiccatiError(std::string(name) + " has a non-finite entry");
  checkRiccatiWeights(Q, R);
}

}  // namespace

void checkRiccatiWeights(const MatrixXd& Q, const MatrixXd& R) {
  if (!Q.allFinite()) throw RiccatiError("Q has a non-finite entry");
  if (!R.allFinite()) throw RiccatiError("R has a non-finite entry");
  const auto scale = [](const MatrixXd& x) { return std::max(x.cwiseAbs().maxCoeff(), 1e-300); };
  if (!(Q - Q.transpose()).isZero(1e-12 * scale(Q))) throw RiccatiError("Q is not symmetric");
  if (!(R - R.transpose()).isZero(1e-12 * scale(R))) throw RiccatiError("R is not symmetric");
  const Eigen::VectorXd q = Eigen::SelfAdjointEigenSolver<MatrixXd>(Q).eigenvalues();
  if (q.minCoeff() < -1e-12 * scale(Q))
    throw RiccatiError("Q is not positive semidefinite (an eigenvalue " +
                       std::to_string(q.minCoeff()) + ")");
  const Eigen::VectorXd r = Eigen::SelfAdjointEigenSolver<MatrixXd>(R).eigenvalues();
  if (!(r.minCoeff() > 0.0))
    throw RiccatiError("R is not positive definite (an eigenvalue " + std::to_string(r.minCoeff()) +
                       ")");
}

namespace {

// X solving A' X + X A = -C (A Hurwitz), through (I (x) A' + A' (x) I) vec X = -vec C.
MatrixXd lyapunov(const MatrixXd& A, const MatrixXd& C) {
  const Eigen::Index n = A.rows();
  const MatrixXd I = MatrixXd::Identity(n, n);
  MatrixXd kron(n * n, n * n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j)
      kron.block(i * n, j * n, n, n) = I(i, j) * A.transpose() + A(j, i) * I;
  const Eigen::VectorXd x =
      kron.fullPivLu().solve(-Eigen::Map<const Eigen::VectorXd>(C.data(), n * n));
  const MatrixXd X = Eigen::Map<const MatrixXd>(x.data(), n, n);
  return (X + X.transpose()) / 2;
}

bool hurwitz(const MatrixXd& A) {
  return Eigen::EigenSolver<MatrixXd>(A, false).eigenvalues().real().maxCoeff() < 0.0;
}

}  // namespace

double riccatiResidual(const MatrixXd& A, const MatrixXd& B, const MatrixXd& Q, const MatrixXd& R,
                       const MatrixXd& P) {
  const MatrixXd PA = P * A;
  const MatrixXd PBRBP = P * B * R.llt().solve(B.transpose() * P);
  const MatrixXd residual = PA.transpose() + PA - PBRBP + Q;
  const double scale = std::max({Q.norm(), PA.norm(), PBRBP.norm(), 1e-300});
  return residual.norm() / scale;
}

MatrixXd solveContinuousRiccati(const MatrixXd& A, const MatrixXd& B, const MatrixXd& Q,
                                const MatrixXd& R) {
  checkInputs(A, B, Q, R);
  const Eigen::Index n = A.rows();
  const Eigen::LLT<MatrixXd> r_factor(R);
  const MatrixXd G = B * r_factor.solve(B.transpose());
  MatrixXd Z(2 * n, 2 * n);
  Z << A, -G, -Q, -A.transpose();
  const char* kNoSolution =
      "no stabilizing solution: (A, B) is not stabilizable (a mode the input cannot move is "
      "unstable), or Q does not weigh an unstable mode, or the weights (or the plant) span more "
      "orders of magnitude than double precision resolves (scale Q and R toward 1)";
  // sign(H) by Newton's iteration Z <- (c Z + (c Z)^-1) / 2, c = |det Z|^(-1/2n).
  for (int iteration = 0; iteration < 100; ++iteration) {
    const Eigen::PartialPivLU<MatrixXd> lu(Z);
    const double det = std::abs(lu.determinant());
    if (!(det > 0.0) || !std::isfinite(det)) throw RiccatiError(kNoSolution);
    const double c = std::pow(det, -1.0 / static_cast<double>(2 * n));
    const MatrixXd next = (c * Z + lu.inverse() / c) / 2;
    const double change = (next - Z).norm() / std::max(next.norm(), 1e-300);
    Z = next;
    if (!Z.allFinite()) throw RiccatiError(kNoSolution);
    if (change < 1e-13) break;
  }
  // The stable subspace [I; P] is the null space of sign(H) + I:
  // [Z12; Z22 + I] P = -[Z11 + I; Z21].
  const MatrixXd I = MatrixXd::Identity(n, n);
  MatrixXd lhs(2 * n, n), rhs(2 * n, n);
  lhs << Z.topRightCorner(n, n), Z.bottomRightCorner(n, n) + I;
  rhs << -(Z.topLeftCorner(n, n) + I), -Z.bottomLeftCorner(n, n);
  MatrixXd P = lhs.colPivHouseholderQr().solve(rhs);
  P = (P + P.transpose()) / 2;
  // Newton-Kleinman: K = R^-1 B' P, (A - B K)' P+ + P+ (A - B K) = -(Q + K' R K).
  for (int step = 0; step < 3 && P.allFinite(); ++step) {
    const MatrixXd K = r_factor.solve(B.transpose() * P);
    const MatrixXd closed = A - B * K;
    if (!hurwitz(closed)) break;
    const MatrixXd next = lyapunov(closed, Q + K.transpose() * R * K);
    if (!next.allFinite()) break;
    P = next;
  }
  if (!P.allFinite() || !hurwitz(A - G * P) || !(riccatiResidual(A, B, Q, R, P) < 1e-8))
    throw RiccatiError(kNoSolution);
  return P;
}

}  // namespace kane_sim
