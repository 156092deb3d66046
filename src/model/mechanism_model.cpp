#include "kane_sim/model/mechanism_model.h"

#include <cmath>

namespace kane_sim {
namespace {

const Eigen::Vector3d kI = Eigen::Vector3d::UnitX();  // i, vertical, down
const Eigen::Vector3d kK = Eigen::Vector3d::UnitZ();  // k, out of the plane

// Principal central moments of a slender rod in the plane: only I_z matters for planar motion
// (ω and α are along k), the in-plane moments are left zero.
Eigen::Vector3d planarInertia(double i_z) { return Eigen::Vector3d(0, 0, i_z); }

MechanismGeometry geometryFromTrig(double L, double q1, double c, double s, double q2) {
  MechanismGeometry g;
  g.rod_length = 2 * L;
  g.pin_a = Eigen::Vector3d(2 * L * c, 2 * L * s, 0);
  g.pin_b = Eigen::Vector3d(4 * L * c, 0, 0);            // r_B
  g.point_c = Eigen::Vector3d(q2, 0, 0);                 // r_C
  g.rod1_center = Eigen::Vector3d(L * c, L * s, 0);      // r_C1
  g.rod2_center = Eigen::Vector3d(3 * L * c, L * s, 0);  // r_C2
  g.rod1_angle = q1;
  g.rod2_angle = -q1;
  return g;
}

}  // namespace

MechanismGeometry mechanismGeometry(double rod_half_length, double q1, double q2) {
  return geometryFromTrig(rod_half_length, q1, std::cos(q1), std::sin(q1), q2);
}

MechanismModel::MechanismModel(const MechanismParameters& parameters, double spring_rest_length)
    : parameters_(parameters), spring_rest_length_(spring_rest_length) {}

MechanismKinematics MechanismModel::kinematics(const State& x) const {
  const MechanismParameters& p = parameters_;
  const double L = p.rod_half_length;  // L
  const double c = std::cos(x.q1);
  const double s = std::sin(x.q1);
  const double u1_sq = x.u1 * x.u1;

  MechanismKinematics k;
  k.geometry = geometryFromTrig(L, x.q1, c, s, x.q2);
  const MechanismGeometry& g = k.geometry;

  // Rigid body 1, rod OA: v_C1 = u1 L (-sin q1, cos q1), ω10 = u1 k (eqs 1, 3, 4).
  k.rod1.mass_center.mass = p.rod_mass;  // m
  k.rod1.mass_center.position = g.rod1_center;
  k.rod1.mass_center.partial_velocity.col(0) << -L * s, L * c, 0;                  // ∂v_C1/∂u1
  k.rod1.mass_center.acceleration_remainder << -L * u1_sq * c, -L * u1_sq * s, 0;  // a_C1, u1'=0
  k.rod1.principal_moments = planarInertia(p.rod_inertia);                         // I1z
  k.rod1.partial_angular_velocity.col(0) = kK;                                     // ∂ω10/∂u1

  // Rigid body 2, rod AB: v_C2 = u1 L (-3 sin q1, cos q1), ω20 = -u1 k.
  k.rod2.mass_center.mass = p.rod_mass;
  k.rod2.mass_center.position = g.rod2_center;
  k.rod2.mass_center.partial_velocity.col(0) << -3 * L * s, L * c, 0;
  k.rod2.mass_center.acceleration_remainder << -3 * L * u1_sq * c, -L * u1_sq * s, 0;
  k.rod2.principal_moments = planarInertia(p.rod_inertia);  // I2z
  k.rod2.partial_angular_velocity.col(0) = -kK;

  // Body 3, slider at B: v_B = -4 L u1 sin q1 i.
  k.slider3.mass = p.slider3_mass;  // M1
  k.slider3.position = g.pin_b;
  k.slider3.partial_velocity.col(0) << -4 * L * s, 0, 0;
  k.slider3.acceleration_remainder << -4 * L * u1_sq * c, 0, 0;

  // Body 4, slider at C: v_C = u2 i.
  k.slider4.mass = p.slider4_mass;  // M2
  k.slider4.position = g.point_c;
  k.slider4.partial_velocity.col(1) = kI;  // ∂v_C/∂u2
  return k;
}

MechanismLoads MechanismModel::loads(const MechanismKinematics& k, double motor_torque) const {
  const MechanismParameters& p = parameters_;
  MechanismLoads l;
  // Eq (14): gravity at each mass center, along +i.
  const kane::Particle<kNumSpeeds>* centers[kNumBodies] = {&k.rod1.mass_center, &k.rod2.mass_center,
                                                           &k.slider3, &k.slider4};
  for (int b = 0; b < kNumBodies; ++b) {
    l.gravity[b].force = centers[b]->mass * p.gravity * kI;  // G1 = m g i, ..., G4 = M2 g i
    l.gravity[b].partial_velocity = centers[b]->partial_velocity;
  }
  // Eq (15): F_eB = -k e i at B, F_eC = -F_eB at C.
  const double e = springElongation(k.geometry);
  l.spring_on_slider3.force = -p.spring_stiffness * e * kI;
  l.spring_on_slider3.partial_velocity = k.slider3.partial_velocity;
  l.spring_on_slider4.force = -l.spring_on_slider3.force;
  l.spring_on_slider4.partial_velocity = k.slider4.partial_velocity;
  // The driver moment M_m = M_m k acts on rod 1.
  l.motor.torque = motor_torque * kK;
  l.motor.partial_angular_velocity = k.rod1.partial_angular_velocity;
  return l;
}

MechanismModel::Equations MechanismModel::equations(const MechanismKinematics& k,
                                                    const MechanismLoads& l, const State& x) {
  const SpeedVector u = x.speeds();
  Equations eq;
  // F*_r, eq (12): the sum over the four bodies of eqs (5)-(7).
  kane::addInertiaForces(k.rod1, u, &eq);
  kane::addInertiaForces(k.rod2, u, &eq);
  kane::addInertiaForces(k.slider3, &eq);
  kane::addInertiaForces(k.slider4, &eq);
  // F_r, eq (16): each load on the partial velocities of where it acts.
  for (const auto& g : l.gravity) kane::addActiveForces(g, &eq);
  kane::addActiveForces(l.spring_on_slider3, &eq);
  kane::addActiveForces(l.spring_on_slider4, &eq);
  kane::addActiveForces(l.motor, &eq);
  return eq;
}

MechanismModel::Equations MechanismModel::equations(const State& x, double motor_torque) const {
  const MechanismKinematics k = kinematics(x);
  return equations(k, loads(k, motor_torque), x);
}

OdeState MechanismModel::stateDerivative(const State& x, double motor_torque) const {
  const SpeedVector u_dot = accelerations(x, motor_torque);
  return {x.u1, x.u2, u_dot[0], u_dot[1]};  // q1' = u1, q2' = u2 (eq 1); u1', u2' (eq 18)
}

EnergyTerms MechanismModel::energy(const MechanismKinematics& k, const State& x) const {
  const SpeedVector u = x.speeds();
  const double g = parameters_.gravity;
  EnergyTerms e;
  e.kinetic = kane::kineticEnergy(k.rod1, u) + kane::kineticEnergy(k.rod2, u) +
              kane::kineticEnergy(k.slider3, u) + kane::kineticEnergy(k.slider4, u);
  for (const kane::Particle<kNumSpeeds>* p :
       {&k.rod1.mass_center, &k.rod2.mass_center, &k.slider3, &k.slider4})
    e.gravitational -= p->mass * g * p->position.dot(kI);
  const double elongation = springElongation(k.geometry);
  e.spring = 0.5 * parameters_.spring_stiffness * elongation * elongation;
  return e;
}

JointValues MechanismModel::jointValues(const MechanismKinematics& k, const State& x,
                                        double motor_torque) {
  const MechanismGeometry& g = k.geometry;
  const SpeedVector u = x.speeds();
  const double w1 = k.rod1.angularVelocity(u).z();
  const double w2 = k.rod2.angularVelocity(u).z();
  JointValues j;
  j.position = {g.rod1_angle, g.rod2_angle - g.rod1_angle, g.pin_b.x(), g.point_c.x()};
  j.velocity = {w1, w2 - w1, k.slider3.velocity(u).x(), k.slider4.velocity(u).x()};
  j.effort = {motor_torque, 0.0, 0.0, 0.0};
  return j;
}

}  // namespace kane_sim
