#include "kane_sim/analysis/linear_analysis.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "kane_sim/model/generated_mechanism.h"

namespace kane_sim {

LinearModel linearize(const MechanismModel& model, const State& x, double torque) {
  LinearModel linear;
  linear.operating_point = x;
  linear.torque = torque;
  const GeneratedMechanism::Linearization exact =
      GeneratedMechanism(model).linearization(x, torque);
  linear.A = exact.A;
  linear.B = exact.B;
  linear.mass = model.equations(x, torque).mass_matrix;
  // M u' = F: at a static equilibrium (u' = 0) d F/d q = M d u'/d q, and d F/d u = M d u'/d u.
  linear.stiffness = -linear.mass * linear.A.bottomLeftCorner<2, 2>();
  linear.damping = -linear.mass * linear.A.bottomRightCorner<2, 2>();
  const generated::RateScale scale = generated::smallestRateScale(model.constants());
  if (scale.constant >= 0) {
    const std::string key = generated::kConstantKeys[scale.constant];
    linear.notes.push_back(
        "Coulomb friction is linearized as a damper of F_c / " + key +
        " at each joint: true of the smoothed law for speeds well below " + key +
        ", not of dry friction (whose slope at rest is unbounded and which holds any equilibrium "
        "within a band of loads); the damping ratios are the smoothing's");
  }
  if (linear.B.isZero())
    linear.notes.push_back(
        "the motor line limits the torque at this speed: the command has no "
        "effect on the rates (B = 0), the line's slope is in A");
  return linear;
}

ModalAnalysis modalAnalysis(const LinearModel& linear) {
  ModalAnalysis result;
  // Undamped: K phi = w^2 M phi. K is the Hessian of the potential (a constant torque has one,
  // -M_m q1), symmetric up to rounding.
  const Eigen::Matrix2d K = (linear.stiffness + linear.stiffness.transpose()) / 2;
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix2d> undamped(K, linear.mass);
  // A stiffness eigenvalue within kNeutralStiffness of the largest is zero: a neutral direction
  // (gravity 0 leaves the crank without a restoring moment), not a mode of some microhertz.
  const double scale = undamped.eigenvalues().cwiseAbs().maxCoeff();
  result.stability = "stable";
  if (undamped.eigenvalues().minCoeff() < -kNeutralStiffness * scale) {
    // Unstable (the upright crank): A's eigenvalues, no modes to name.
    result.stability = "unstable";
    const Eigen::Vector4cd values = Eigen::EigenSolver<Eigen::Matrix4d>(linear.A).eigenvalues();
    result.eigenvalues.assign(values.data(), values.data() + 4);
    std::sort(result.eigenvalues.begin(), result.eigenvalues.end(), [](auto a, auto b) {
      return std::abs(a) != std::abs(b) ? std::abs(a) < std::abs(b) : a.imag() < b.imag();
    });
    return result;
  }
  for (int i = 0; i < 2; ++i) {
    const double w2 = undamped.eigenvalues()[i];
    Mode mode;
    if (std::abs(w2) <= kNeutralStiffness * scale || scale == 0.0) {
      mode.neutral = true;
      result.stability = "neutral";
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
