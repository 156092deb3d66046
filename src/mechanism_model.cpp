#include "kane_sim/mechanism_model.h"

#include <cmath>

namespace kane_sim {
namespace {

const Eigen::Vector3d kI = Eigen::Vector3d::UnitX();  // i, vertical, down
const Eigen::Vector3d kK = Eigen::Vector3d::UnitZ();  // k, out of the plane

// Principal central moments of a slender rod in the plane: only I_z matters for planar motion
// (ω and α are along k), the in-plane moments are left zero.
Eigen::Vector3d planarInertia(double i_z) { return Eigen::Vector3d(0, 0, i_z); }

}  // namespace

MechanismModel::MechanismModel(const MechanismParameters& parameters, const State& spring_free)
    : parameters_(parameters),
      spring_free_(spring_free),
      spring_free_separation_(4.0 * parameters.rod_half_length * std::cos(spring_free.q1) -
                              spring_free.q2) {}

MechanismGeometry MechanismModel::geometry(double q1, double q2) const {
  return geometry(q1, std::cos(q1), std::sin(q1), q2);
}

MechanismGeometry MechanismModel::geometry(double q1, double c, double s, double q2) const {
  const double L = parameters_.rod_half_length;
  MechanismGeometry g;
  g.pivot_o = Eigen::Vector3d::Zero();
  g.pin_a = Eigen::Vector3d(2 * L * c, 2 * L * s, 0);
  g.pin_b = Eigen::Vector3d(4 * L * c, 0, 0);            // r_B
  g.point_c = Eigen::Vector3d(q2, 0, 0);                 // r_C
  g.rod1_center = Eigen::Vector3d(L * c, L * s, 0);      // r_C1
  g.rod2_center = Eigen::Vector3d(3 * L * c, L * s, 0);  // r_C2
  g.rod1_angle = q1;
  g.rod2_angle = -q1;
  return g;
}

double MechanismModel::springElongation(double q1, double q2) const {
  return springElongationFromCos(std::cos(q1), q2);
}

double MechanismModel::springElongationFromCos(double cos_q1, double q2) const {
  return (4.0 * parameters_.rod_half_length * cos_q1 - q2) - spring_free_separation_;
}

MechanismModel::Bodies MechanismModel::bodies(const State& x, double motor_torque) const {
  const MechanismParameters& p = parameters_;
  const double L = p.rod_half_length;  // L
  const double m = p.rod_mass;         // m
  const double g = p.gravity;          // g
  const double c = std::cos(x.q1);
  const double s = std::sin(x.q1);
  const double u1_sq = x.u1 * x.u1;
  const MechanismGeometry geo = geometry(x.q1, c, s, x.q2);
  const double spring_force = -p.spring_stiffness * springElongationFromCos(c, x.q2);  // F_eB · i

  Bodies b;
  // Rigid body 1, rod OA: v_C1 = u1 L (-sin q1, cos q1), ω10 = u1 k.
  RigidBodyTerms<kNumSpeeds>& rod1 = b[kRod1];
  rod1.mass = m;
  rod1.principal_moments = planarInertia(p.rod_inertia);  // I1z
  rod1.mass_center_position = geo.rod1_center;
  rod1.partial_velocity.col(0) << -L * s, L * c, 0;                  // ∂v_C1/∂u1
  rod1.partial_angular_velocity.col(0) = kK;                         // ∂ω10/∂u1
  rod1.acceleration_remainder << -L * u1_sq * c, -L * u1_sq * s, 0;  // a_C1 at u1' = 0
  rod1.applied_force = m * g * kI;                                   // G1
  rod1.applied_torque = motor_torque * kK;                           // M_m

  // Rigid body 2, rod AB: v_C2 = u1 L (-3 sin q1, cos q1), ω20 = -u1 k.
  RigidBodyTerms<kNumSpeeds>& rod2 = b[kRod2];
  rod2.mass = m;
  rod2.principal_moments = planarInertia(p.rod_inertia);  // I2z
  rod2.mass_center_position = geo.rod2_center;
  rod2.partial_velocity.col(0) << -3 * L * s, L * c, 0;
  rod2.partial_angular_velocity.col(0) = -kK;
  rod2.acceleration_remainder << -3 * L * u1_sq * c, -L * u1_sq * s, 0;
  rod2.applied_force = m * g * kI;  // G2

  // Rigid body 3, slider at B: v_B = -4 L u1 sin q1 i; gravity G3 and the spring F_eB.
  RigidBodyTerms<kNumSpeeds>& slider3 = b[kSlider3];
  slider3.mass = p.slider3_mass;  // M1
  slider3.mass_center_position = geo.pin_b;
  slider3.partial_velocity.col(0) << -4 * L * s, 0, 0;
  slider3.acceleration_remainder << -4 * L * u1_sq * c, 0, 0;
  slider3.applied_force = (p.slider3_mass * g + spring_force) * kI;

  // Rigid body 4, slider at C: v_C = u2 i; gravity G4 and the spring F_eC = -F_eB.
  RigidBodyTerms<kNumSpeeds>& slider4 = b[kSlider4];
  slider4.mass = p.slider4_mass;  // M2
  slider4.mass_center_position = geo.point_c;
  slider4.partial_velocity.col(1) = kI;  // ∂v_C/∂u2
  slider4.applied_force = (p.slider4_mass * g - spring_force) * kI;
  return b;
}

MechanismModel::Forces MechanismModel::generalizedForces(const State& x,
                                                         double motor_torque) const {
  const Bodies b = bodies(x, motor_torque);
  const SpeedVector u = x.speeds();
  Forces forces;
  for (const auto& body : b) accumulateBody(body, u, &forces);
  return forces;
}

EnergyTerms MechanismModel::energy(const State& x) const {
  const Bodies b = bodies(x, 0.0);
  const SpeedVector u = x.speeds();
  EnergyTerms e;
  for (const auto& body : b) {
    e.kinetic += kineticEnergy(body, u);
    e.gravitational -= body.mass * parameters_.gravity * body.mass_center_position.dot(kI);
  }
  const double elongation = springElongation(x.q1, x.q2);
  e.spring = 0.5 * parameters_.spring_stiffness * elongation * elongation;
  return e;
}

}  // namespace kane_sim
