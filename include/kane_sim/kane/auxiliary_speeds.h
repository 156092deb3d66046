// Non-contributing (constraint) forces brought into evidence with auxiliary generalized speeds,
// as in Kane & Levinson, "Dynamics: Theory and Applications", ch. 4, and SymPy's
// KanesMethod(u_auxiliary=...):
//
//   A reaction force does no work in any motion the constraints allow, so it is absent from
//   Kane's equations F*_r + F_r = 0. To see it, let the system move in a way that breaks the
//   constraint, with an auxiliary speed ũ_s (a motion the real system never makes): every body
//   and every point gets partial velocities ∂ṽ/∂ũ_s (and ∂ω̃/∂ũ_s), and the reaction now does
//   work. Kane's equation for ũ_s, taken at ũ = 0 (the real motion),
//
//       F̃*_s + F̃_s = 0,   F̃*_s = Σ ∂ṽ/∂ũ_s · (-M a) + ∂ω̃/∂ũ_s · (-I α - ω × I ω),
//                          F̃_s  = Σ ∂ṽ/∂ũ_s · F (known loads) + Σ_j C_sj λ_j (reactions),
//
//   is linear in the unknown reaction components λ_j. With as many auxiliary speeds as unknowns,
//   C λ = -(F̃*_s + F̃_s(known)) gives them; a good choice of motions makes C triangular (each
//   new motion brings in one new reaction), as the textbook does.
//
// a and α are the bodies' actual accelerations (from u and u'), so u' must come from Kane's
// equations first. Nothing here knows the textbook's mechanism.
#ifndef KANE_SIM_KANE_AUXILIARY_SPEEDS_H
#define KANE_SIM_KANE_AUXILIARY_SPEEDS_H

#include <Eigen/Dense>

#include "kane_sim/kane/kane_method.h"

namespace kane_sim {
namespace kane {

// Partial velocities with respect to K auxiliary speeds: column s is ∂ṽ/∂ũ_s (or ∂ω̃/∂ũ_s).
template <int K>
using AuxiliaryPartials = Eigen::Matrix<double, 3, K>;

// The auxiliary motion of one rigid body: its mass center's and its frame's partial velocities.
template <int K>
struct AuxiliaryMotion {
  AuxiliaryPartials<K> velocity = AuxiliaryPartials<K>::Zero();          // ∂ṽ_CG/∂ũ_s
  AuxiliaryPartials<K> angular_velocity = AuxiliaryPartials<K>::Zero();  // ∂ω̃/∂ũ_s

  // A point P of the body at r_CG->P: ∂ṽ_P/∂ũ_s = ∂ṽ_CG/∂ũ_s + ∂ω̃/∂ũ_s × r.
  AuxiliaryPartials<K> atPoint(const Eigen::Vector3d& from_mass_center) const {
    AuxiliaryPartials<K> v = velocity;
    for (int s = 0; s < K; ++s) v.col(s) += angular_velocity.col(s).cross(from_mass_center);
    return v;
  }
};

// Kane's equations for K auxiliary speeds, accumulated term by term.
template <int K>
struct AuxiliaryEquations {
  using Vector = Eigen::Matrix<double, K, 1>;
  using Matrix = Eigen::Matrix<double, K, K>;

  Vector inertia_forces = Vector::Zero();         // F̃*_s
  Vector active_forces = Vector::Zero();          // F̃_s of the known loads
  Matrix reaction_coefficients = Matrix::Zero();  // C_sj: F̃_s of reaction j per unit λ_j

  // λ from C λ = -(F̃* + F̃). Rank-revealing, so a configuration where the constraints cannot
  // tell two reactions apart (C singular: e.g. two colinear forces at one point) still gives a
  // finite answer (the least-squares one), flagged by `determinate`.
  Vector solveReactions(bool* determinate = nullptr) const {
    const Eigen::ColPivHouseholderQR<Matrix> qr(reaction_coefficients);
    if (determinate) *determinate = qr.rank() == K;
    if (qr.rank() == K) return qr.solve(Vector(-(inertia_forces + active_forces)));
    return reaction_coefficients.completeOrthogonalDecomposition().solve(
        Vector(-(inertia_forces + active_forces)));
  }
};

// F̃*_s += ∂ṽ/∂ũ_s · (-M a), a = V u' + remainder: a particle (or a mass center).
template <int N, int K>
void addAuxiliaryInertiaForces(const Particle<N>& p, const AuxiliaryPartials<K>& aux_velocity,
                               const Speeds<N>& u_dot, AuxiliaryEquations<K>* eq) {
  const Eigen::Vector3d a = p.partial_velocity * u_dot + p.acceleration_remainder;
  eq->inertia_forces.noalias() -= p.mass * aux_velocity.transpose() * a;
}

// A rigid body: its mass center's share, plus ∂ω̃/∂ũ_s · (-I α - ω × I ω).
template <int N, int K>
void addAuxiliaryInertiaForces(const RigidBody<N>& body, const AuxiliaryMotion<K>& aux,
                               const Speeds<N>& u, const Speeds<N>& u_dot,
                               AuxiliaryEquations<K>* eq) {
  addAuxiliaryInertiaForces(body.mass_center, aux.velocity, u_dot, eq);
  const auto I = body.principal_moments.asDiagonal();
  const Eigen::Vector3d omega = body.angularVelocity(u);
  const Eigen::Vector3d alpha =
      body.partial_angular_velocity * u_dot + body.angular_acceleration_remainder;
  const Eigen::Vector3d inertia_torque = -(I * alpha) - omega.cross(I * omega);
  eq->inertia_forces.noalias() += aux.angular_velocity.transpose() * inertia_torque;
}

// A known force F at a point with partial velocities ∂ṽ_P/∂ũ_s (or a torque T on a frame with
// ∂ω̃/∂ũ_s): F̃_s += ∂ṽ_P/∂ũ_s · F.
template <int K>
void addAuxiliaryActiveForces(const Eigen::Vector3d& force_or_torque,
                              const AuxiliaryPartials<K>& aux_partials, AuxiliaryEquations<K>* eq) {
  eq->active_forces.noalias() += aux_partials.transpose() * force_or_torque;
}

// Reaction j: λ_j along `direction` on body b at P, and -λ_j on body a at P (Newton's third law;
// a fixed support has no motion). Its power per unit λ_j under ũ_s is
// direction · (∂ṽ_P,b/∂ũ_s - ∂ṽ_P,a/∂ũ_s): the constraint broken by ũ_s.
template <int K>
void addReaction(int j, const Eigen::Vector3d& direction,
                 const AuxiliaryPartials<K>& relative_aux_velocity, AuxiliaryEquations<K>* eq) {
  eq->reaction_coefficients.col(j).noalias() += relative_aux_velocity.transpose() * direction;
}

}  // namespace kane
}  // namespace kane_sim

#endif  // KANE_SIM_KANE_AUXILIARY_SPEEDS_H
