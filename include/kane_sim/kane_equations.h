// Generic Kane's method for holonomic systems with N generalized speeds.
//
// Each rigid body contributes what the seed's eqs (5)-(7) and (16) need: its partial velocities
// and partial angular velocities, the parts of its accelerations that do not multiply u', and
// the resultant force and moment applied to it. This file knows nothing about any particular
// mechanism; the seed's mechanism is written on top of it in mechanism_model.h.
#ifndef KANE_SIM_KANE_EQUATIONS_H
#define KANE_SIM_KANE_EQUATIONS_H

#include <Eigen/Dense>

namespace kane_sim {

// One rigid body RB, described in the fixed frame (0), at one instant.
template <int N>
struct RigidBodyTerms {
  using PartialMatrix = Eigen::Matrix<double, 3, N>;

  double mass = 0.0;  // M of RB
  // I-bar = I_x ii + I_y jj + I_z kk: the seed's eq (7) takes the central principal axes parallel
  // to i, j, k, so the dyadic is diagonal and stored as (I_x, I_y, I_z).
  Eigen::Vector3d principal_moments = Eigen::Vector3d::Zero();
  Eigen::Vector3d mass_center_position = Eigen::Vector3d::Zero();  // r_CG
  PartialMatrix partial_velocity = PartialMatrix::Zero();          // column r: dv_CG/du_r
  PartialMatrix partial_angular_velocity = PartialMatrix::Zero();  // column r: dω/du_r
  // a_CG = partial_velocity * u' + acceleration_remainder (the u'-free part, e.g. centripetal).
  Eigen::Vector3d acceleration_remainder = Eigen::Vector3d::Zero();
  // α = partial_angular_velocity * u' + angular_acceleration_remainder.
  Eigen::Vector3d angular_acceleration_remainder = Eigen::Vector3d::Zero();
  // Resultant of the applied forces, acting at the mass center (gravity, springs, ...).
  Eigen::Vector3d applied_force = Eigen::Vector3d::Zero();
  // Resultant applied moment on RB (driver moments, ...).
  Eigen::Vector3d applied_torque = Eigen::Vector3d::Zero();

  // v_CG and ω follow from the partial velocities because the mechanism is scleronomic.
  template <typename SpeedVector>
  Eigen::Vector3d velocity(const SpeedVector& u) const {
    return partial_velocity * u;
  }
  template <typename SpeedVector>
  Eigen::Vector3d angularVelocity(const SpeedVector& u) const {
    return partial_angular_velocity * u;
  }
};

// F*_r is affine in u': F*(u') = -mass_matrix * u' + inertia_remainder.
template <int N>
struct GeneralizedForces {
  using Vector = Eigen::Matrix<double, N, 1>;
  using Matrix = Eigen::Matrix<double, N, N>;

  Matrix mass_matrix = Matrix::Zero();
  Vector inertia_remainder = Vector::Zero();  // F*_r at u' = 0 (velocity-product terms)
  Vector active = Vector::Zero();             // F_r, eq (16)

  Vector inertia(const Vector& u_dot) const {  // F*_r, eq (12)
    return -mass_matrix * u_dot + inertia_remainder;
  }
  // Kane's dynamical equations (18), F*_r + F_r = 0, solved for u'.
  // M is symmetric positive definite (kinetic energy ½ u·M·u > 0 for u ≠ 0). Up to 4x4 Eigen
  // inverts it in closed form (cofactors), which is well-conditioned here and cheaper than a
  // factorisation; larger systems use Cholesky.
  Vector solveAccelerations() const {
    if constexpr (N <= 4) {
      return mass_matrix.inverse() * (inertia_remainder + active);
    } else {
      return mass_matrix.llt().solve(inertia_remainder + active);
    }
  }
};

// Adds one body's share of eqs (5)-(7) and (16) to `forces`. u is the generalized speed vector.
template <int N>
inline void accumulateBody(const RigidBodyTerms<N>& body, const Eigen::Matrix<double, N, 1>& u,
                           GeneralizedForces<N>* forces) {
  const auto& V = body.partial_velocity;
  const auto& W = body.partial_angular_velocity;

  // Translation: F_in = -M a_CG (6) splits into the part that multiplies u' (the mass matrix)
  // and the part that does not; F_r gains dv/du_r · R (16).
  forces->mass_matrix.noalias() += body.mass * V.transpose() * V;
  forces->inertia_remainder.noalias() -= body.mass * V.transpose() * body.acceleration_remainder;
  forces->active.noalias() += V.transpose() * body.applied_force;

  // Rotation: T_in = -α·I - ω × (I·ω) (7) and dω/du_r · T (16). Every term carries a partial
  // angular velocity, so a body that no speed turns (a slider) contributes none: skip the work.
  if (W.isZero(0.0)) return;
  const Eigen::Vector3d omega = body.angularVelocity(u);
  const auto I = body.principal_moments.asDiagonal();
  forces->mass_matrix.noalias() += W.transpose() * I * W;
  const Eigen::Vector3d torque_remainder =
      -(I * body.angular_acceleration_remainder) - omega.cross(I * omega);
  forces->inertia_remainder.noalias() += W.transpose() * torque_remainder;
  forces->active.noalias() += W.transpose() * body.applied_torque;
}

// Kinetic energy of one body: ½ M v·v + ½ ω·I·ω.
template <int N>
double kineticEnergy(const RigidBodyTerms<N>& body, const Eigen::Matrix<double, N, 1>& u) {
  const Eigen::Vector3d v = body.velocity(u);
  const Eigen::Vector3d omega = body.angularVelocity(u);
  return 0.5 * body.mass * v.squaredNorm() +
         0.5 * omega.dot(body.principal_moments.asDiagonal() * omega);
}

}  // namespace kane_sim

#endif  // KANE_SIM_KANE_EQUATIONS_H
