// Kane's method for holonomic, scleronomic systems with N generalized speeds, in the vocabulary
// of the textbook example and of SymPy's KanesMethod (sympy/physics/mechanics/kane.py):
//
//   bodies    - particles (mass at a point) and rigid bodies (mass, central inertia), each
//               carrying its partial velocities ∂v/∂u_r (and ∂ω/∂u_r) and the u'-free parts of
//               its accelerations;
//   loads     - forces acting at points (with that point's partial velocities) and torques
//               acting on frames (with that frame's partial angular velocities).
//
// Generalized inertia forces F*_r (eqs 5-7, 12) are affine in u': F* = -M u' + F*(u' = 0), with
// M the mass matrix; generalized active forces F_r (eq 16) are the loads projected on the
// partial velocities. Kane's equations F*_r + F_r = 0 (eq 18) are M u' = forcing, forcing =
// F*(u' = 0) + F_r (SymPy's `mass_matrix` and `forcing`).
//
// Nothing here knows the textbook's mechanism; model/mechanism_model.h is written on top.
#ifndef KANE_SIM_KANE_KANE_METHOD_H
#define KANE_SIM_KANE_KANE_METHOD_H

#include <Eigen/Dense>

namespace kane_sim {
namespace kane {

template <int N>
using Speeds = Eigen::Matrix<double, N, 1>;  // u_1 ... u_N, or u'
template <int N>
using PartialVelocities = Eigen::Matrix<double, 3, N>;  // column r: ∂v/∂u_r (or ∂ω/∂u_r)

// A particle P of mass M at r_P (a slider: its orientation never enters the dynamics).
template <int N>
struct Particle {
  double mass = 0.0;                                                     // M
  Eigen::Vector3d position = Eigen::Vector3d::Zero();                    // r_P in frame (0)
  PartialVelocities<N> partial_velocity = PartialVelocities<N>::Zero();  // ∂v_P/∂u_r
  // a_P = partial_velocity · u' + acceleration_remainder (centripetal and similar terms).
  Eigen::Vector3d acceleration_remainder = Eigen::Vector3d::Zero();

  template <typename U>
  Eigen::Vector3d velocity(const U& u) const {  // v_P = Σ_r ∂v_P/∂u_r u_r (scleronomic)
    return partial_velocity * u;
  }
};

// A rigid body RB: a particle at its mass center plus the central inertia dyadic. Eq (7) takes
// the central principal axes parallel to i, j, k, so the dyadic is diag(I_x, I_y, I_z).
template <int N>
struct RigidBody {
  Particle<N> mass_center;                                      // M, r_CG, ∂v_CG/∂u_r, a_CG
  Eigen::Vector3d principal_moments = Eigen::Vector3d::Zero();  // (I_x, I_y, I_z)
  PartialVelocities<N> partial_angular_velocity = PartialVelocities<N>::Zero();  // ∂ω/∂u_r
  // α = partial_angular_velocity · u' + angular_acceleration_remainder.
  Eigen::Vector3d angular_acceleration_remainder = Eigen::Vector3d::Zero();

  template <typename U>
  Eigen::Vector3d angularVelocity(const U& u) const {
    return partial_angular_velocity * u;
  }
};

// One load, as an entry of SymPy's `loads` list ((point or frame, vector)): a force applied at a
// point P, with P's partial velocities ∂v_P/∂u_r, or a torque (couple) applied to a frame, with
// the frame's partial angular velocities ∂ω/∂u_r. Both enter F_r (eq 16) the same way, the
// vector dotted with the partials; the kind and the point say where it acts (for reactions).
template <int N>
struct Load {
  enum Kind { kForceAtPoint, kTorqueOnFrame };
  Kind kind = kForceAtPoint;
  Eigen::Vector3d vector = Eigen::Vector3d::Zero();  // F [N] or T [N m], frame (0)
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   // r_P (a force's point of application)
  PartialVelocities<N> partials = PartialVelocities<N>::Zero();  // ∂v_P/∂u_r or ∂ω/∂u_r
};

// F at the particle's point (a particle, or a rigid body's mass center).
template <int N>
Load<N> forceAt(const Particle<N>& point, const Eigen::Vector3d& force) {
  return {Load<N>::kForceAtPoint, force, point.position, point.partial_velocity};
}
// T on the rigid body's frame.
template <int N>
Load<N> torqueOn(const RigidBody<N>& body, const Eigen::Vector3d& torque) {
  return {Load<N>::kTorqueOnFrame, torque, body.mass_center.position,
          body.partial_angular_velocity};
}

// Kane's equations at one instant, accumulated term by term.
template <int N>
struct KaneEquations {
  using Vector = Speeds<N>;
  using Matrix = Eigen::Matrix<double, N, N>;

  Matrix mass_matrix = Matrix::Zero();        // M: F*_r = -M u' + inertia_remainder
  Vector inertia_remainder = Vector::Zero();  // F*_r at u' = 0 (velocity-product terms)
  Vector active_forces = Vector::Zero();      // F_r, eq (16)

  Vector forcing() const { return inertia_remainder + active_forces; }  // M u' = forcing
  Vector inertiaForces(const Vector& u_dot) const {                     // F*_r, eq (12)
    return -mass_matrix * u_dot + inertia_remainder;
  }
  // F*_r + F_r = 0 (18) solved for u'. M is symmetric positive definite (T = ½ u·M·u > 0 for
  // u ≠ 0). Up to 4x4 Eigen inverts in closed form (cofactors), well-conditioned here and cheaper
  // than a factorisation; larger systems use Cholesky.
  Vector solveAccelerations() const {
    if constexpr (N <= 4) {
      return mass_matrix.inverse() * forcing();
    } else {
      return mass_matrix.llt().solve(forcing());
    }
  }
};

// Eqs (5), (6) for a particle: F*_r += ∂v_P/∂u_r · (-M a_P).
template <int N>
void addInertiaForces(const Particle<N>& p, KaneEquations<N>* eq) {
  const auto& V = p.partial_velocity;
  eq->mass_matrix.noalias() += p.mass * V.transpose() * V;
  eq->inertia_remainder.noalias() -= p.mass * V.transpose() * p.acceleration_remainder;
}

// Eqs (5)-(7) for a rigid body: the mass center's share as a particle, plus
// F*_r += ∂ω/∂u_r · T_in, T_in = -α·I - ω × (I·ω).
template <int N>
void addInertiaForces(const RigidBody<N>& body, const Speeds<N>& u, KaneEquations<N>* eq) {
  addInertiaForces(body.mass_center, eq);
  const auto& W = body.partial_angular_velocity;
  const auto I = body.principal_moments.asDiagonal();
  const Eigen::Vector3d omega = body.angularVelocity(u);
  eq->mass_matrix.noalias() += W.transpose() * I * W;
  const Eigen::Vector3d torque_remainder =
      -(I * body.angular_acceleration_remainder) - omega.cross(I * omega);
  eq->inertia_remainder.noalias() += W.transpose() * torque_remainder;
}

// Eq (16), one term: F_r += ∂v_P/∂u_r · F (a force), ∂ω/∂u_r · T (a torque).
template <int N>
void addActiveForces(const Load<N>& load, KaneEquations<N>* eq) {
  eq->active_forces.noalias() += load.partials.transpose() * load.vector;
}

// The power of a load at speeds u: F · v_P, T · ω.
template <int N>
double power(const Load<N>& load, const Speeds<N>& u) {
  return load.vector.dot(load.partials * u);
}

// Kinetic energy: ½ M v·v, plus ½ ω·I·ω for a rigid body.
template <int N>
double kineticEnergy(const Particle<N>& p, const Speeds<N>& u) {
  return 0.5 * p.mass * p.velocity(u).squaredNorm();
}
template <int N>
double kineticEnergy(const RigidBody<N>& body, const Speeds<N>& u) {
  const Eigen::Vector3d omega = body.angularVelocity(u);
  return kineticEnergy(body.mass_center, u) +
         0.5 * omega.dot(body.principal_moments.asDiagonal() * omega);
}

}  // namespace kane
}  // namespace kane_sim

#endif  // KANE_SIM_KANE_KANE_METHOD_H
