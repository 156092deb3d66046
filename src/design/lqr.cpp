#include "kane_sim/design/lqr.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "kane_sim/analysis/linear_analysis.h"
#include "kane_sim/design/riccati.h"
#include "kane_sim/format_number.h"

namespace kane_sim {
namespace {

std::vector<std::complex<double>> sortedEigenvalues(const Eigen::Matrix4d& A) {
  const Eigen::Vector4cd values = Eigen::EigenSolver<Eigen::Matrix4d>(A, false).eigenvalues();
  std::vector<std::complex<double>> out(values.data(), values.data() + 4);
  std::sort(out.begin(), out.end(), [](auto a, auto b) {
    return a.real() != b.real() ? a.real() < b.real() : a.imag() < b.imag();
  });
  return out;
}

Eigen::Vector4d vectorOf(const State& x) { return {x.q1, x.q2, x.u1, x.u2}; }

// Four significant digits, for a note's words.
std::string roughly(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", value);
  return text;
}

struct ControllableSubspace {
  Eigen::MatrixXd basis;               // 4 x r, orthonormal columns
  double uncontrollable_growth = 0.0;  // the largest real part of the rest's eigenvalues [1/s]
  double scale = 1.0;                  // the largest |eigenvalue| of A [1/s]
};

// The range of the controllability matrix [B, A B / s, A^2 B / s^2, A^3 B / s^3] (s = A's largest
// |eigenvalue|, so the columns are of one size), by SVD: singular values below 1e-9 of the
// largest are zero.
ControllableSubspace controllableSubspace(const Eigen::Matrix4d& A, const Eigen::Vector4d& B) {
  ControllableSubspace out;
  out.scale = std::max(
      Eigen::EigenSolver<Eigen::Matrix4d>(A, false).eigenvalues().cwiseAbs().maxCoeff(), 1e-300);
  Eigen::Matrix4d reach;
  Eigen::Vector4d column = B;
  for (int i = 0; i < 4; ++i) {
    reach.col(i) = column;
    column = A * column / out.scale;
  }
  const Eigen::JacobiSVD<Eigen::Matrix4d> svd(reach, Eigen::ComputeFullU);
  int rank = 0;
  for (int i = 0; i < 4; ++i)
    if (svd.singularValues()[i] > 1e-9 * svd.singularValues()[0]) ++rank;
  out.basis = svd.matrixU().leftCols(rank);
  if (rank < 4) {
    const Eigen::MatrixXd rest = svd.matrixU().rightCols(4 - rank);
    const Eigen::MatrixXd A22 = rest.transpose() * A * rest;
    out.uncontrollable_growth =
        Eigen::EigenSolver<Eigen::MatrixXd>(A22, false).eigenvalues().real().maxCoeff();
  }
  return out;
}

}  // namespace

LqrWeights defaultLqrWeights(const Config& config, const MechanismModel& model) {
  LqrWeights w;
  const Eigen::Vector4d acceptable(0.1, 0.01, 1.0, 0.1);
  w.Q = acceptable.cwiseInverse().cwiseAbs2().asDiagonal();
  double torque = config.command.torque_limit;
  // No finite limit: the largest holding moment (gravity's), or 1 N m without gravity.
  if (!std::isfinite(torque)) torque = maxHoldingTorque(model).torque;
  if (!(std::isfinite(torque) && torque > 0.0)) torque = 1.0;
  w.R = 1.0 / (torque * torque);
  return w;
}

LqrDesign designLqr(const MechanismModel& model, double q1, const LqrWeights& weights) {
  LqrDesign d;
  d.equilibrium = equilibriumAt(model, q1);
  const double limit = model.parameters().motor.torque_limit;
  if (!(limit > 0.0))
    throw AnalysisError("command.torque_limit is " + formatNumber(limit) +
                        " N m: the drive delivers no torque to control with");
  if (std::abs(d.equilibrium.torque) > limit)
    throw AnalysisError("holding the crank at q1 = " + formatNumber(q1) + " rad needs " +
                        formatNumber(d.equilibrium.torque) + " N m, beyond command.torque_limit " +
                        formatNumber(limit) + " N m");
  const LinearModel linear = linearize(model, d.equilibrium.state, d.equilibrium.torque);
  d.A = linear.A;
  d.B = linear.B;
  d.weights = weights;
  const Eigen::MatrixXd R = Eigen::MatrixXd::Constant(1, 1, weights.R);
  checkRiccatiWeights(weights.Q, R);  // on every state, before the controllable ones are taken
  // The controllable subspace (Kalman's decomposition): at q1 = 0 or pi the crank's lever on the
  // spring, 4 L sin q1, is 0 and slider 4's oscillation is out of the crank's reach. LQR acts on
  // what the crank can move; a mode it cannot is left as it is, refused if it grows.
  const ControllableSubspace split = controllableSubspace(d.A, d.B);
  d.controllable_basis = split.basis;
  const Eigen::MatrixXd T = split.basis;
  if (split.uncontrollable_growth > 1e-9 * split.scale)
    throw RiccatiError(
        "no stabilizing gain: a mode the crank's torque cannot move grows (at rate " +
        std::to_string(split.uncontrollable_growth) + " 1/s): (A, B) is not stabilizable here");
  const Eigen::MatrixXd P1 = solveContinuousRiccati(T.transpose() * d.A * T, T.transpose() * d.B,
                                                    T.transpose() * weights.Q * T, R);
  d.P = T * P1 * T.transpose();
  d.feedback.K = (d.B.transpose() * d.P) / weights.R;
  d.feedback.state = vectorOf(d.equilibrium.state);
  d.feedback.torque = d.equilibrium.torque;
  d.feedback.periodic = model.parameters().crank_spring_stiffness == 0.0;
  d.riccati_residual = riccatiResidual(T.transpose() * d.A * T, T.transpose() * d.B,
                                       T.transpose() * weights.Q * T, R, P1);
  d.open_loop = sortedEigenvalues(d.A);
  d.closed_loop = sortedEigenvalues(d.A - d.B * d.feedback.K);
  for (const auto& lambda : d.closed_loop)
    d.sample_rate_needed = std::max(d.sample_rate_needed, 5.0 * std::abs(lambda));
  const double asked = std::abs(d.equilibrium.torque) + 0.1 * std::abs(d.feedback.K[0]);
  if (asked > limit)
    d.notes.push_back("a crank 0.1 rad off asks for " + roughly(asked) +
                      " N m, beyond command.torque_limit " + formatNumber(limit) +
                      " N m: the law saturates there and may not bring it back (a larger R or "
                      "smaller Q gives a gentler gain)");
  if (T.cols() < 4)
    d.notes.push_back(std::to_string(4 - T.cols()) +
                      " of the 4 states cannot be moved by the crank's torque here (slider 4's "
                      "oscillation, when the crank's lever on the spring 4 L sin q1 is 0): its "
                      "eigenvalues stay in the closed loop as they are");
  return d;
}

}  // namespace kane_sim
