#include "kane_sim/model/constraint_forces.h"

#include "kane_sim/kane/auxiliary_speeds.h"

namespace kane_sim {
namespace {

// The reaction components λ_j, in the order of the auxiliary speeds that bring each one in.
enum Reaction { kRailSlider4, kPinBx, kPinBy, kPinAx, kPinAy, kPinOx, kPinOy, kRailSlider3 };
constexpr int kNumReactions = 8;  // pins O, A, B (2 each) and the two rails: 3n - mobility - 0
using Aux = kane::AuxiliaryPartials<kNumReactions>;

const Eigen::Vector3d kI = Eigen::Vector3d::UnitX();
const Eigen::Vector3d kJ = Eigen::Vector3d::UnitY();
const Eigen::Vector3d kK = Eigen::Vector3d::UnitZ();

}  // namespace

ConstraintForces constraintForces(const MechanismModel& model, const State& x,
                                  const SpeedVector& u_dot, double motor_command,
                                  double contact_force) {
  const MechanismKinematics k = model.kinematics(x);
  MechanismLoads loads = model.loads(k, x, motor_command);
  MechanismModel::addContactLoads(k, contact_force, &loads);
  return constraintForces(k, loads, x, u_dot);
}

ConstraintForces constraintForces(const MechanismKinematics& k, const MechanismLoads& loads,
                                  const State& x, const SpeedVector& u_dot) {
  const MechanismGeometry& g = k.geometry;
  const SpeedVector u = x.speeds();

  // The auxiliary motions, each breaking one more constraint than those before it, so that
  // C is triangular (each equation brings in one new reaction):
  kane::AuxiliaryMotion<kNumReactions> rod1, rod2;   // bodies 1, 2
  Aux slider3 = Aux::Zero(), slider4 = Aux::Zero();  // bodies 3, 4 (particles)
  // ũ1: slider 4 leaves its rail along j: the rail's normal force N4.
  slider4.col(0) = kJ;
  // ũ2: slider 3 alone along i, rod 2 still: pin B opens along i (B_x).
  slider3.col(1) = kI;
  // ũ3: slider 3 alone along j: pin B along j (B_y) and slider 3's rail (N3).
  slider3.col(2) = kJ;
  // ũ4, ũ5: rod 2 and slider 3 translate along i, j: pin A opens (A_x; A_y and N3).
  rod2.velocity.col(3) = slider3.col(3) = kI;
  rod2.velocity.col(4) = slider3.col(4) = kJ;
  // ũ6, ũ7: both rods and slider 3 translate along i, j: pin O opens (O_x; O_y and N3).
  rod1.velocity.col(5) = rod2.velocity.col(5) = slider3.col(5) = kI;
  rod1.velocity.col(6) = rod2.velocity.col(6) = slider3.col(6) = kJ;
  // ũ8: rod 2 turns about A, carrying slider 3 with B: pins hold, slider 3 leaves its rail at
  // (B - A) · i = 2 L cos q1 per unit (N3 alone).
  rod2.angular_velocity.col(7) = kK;
  rod2.velocity.col(7) = kK.cross(g.rod2_center - g.pin_a);
  slider3.col(7) = kK.cross(g.pin_b - g.pin_a);

  kane::AuxiliaryEquations<kNumReactions> eq;
  // F̃*_s: every body's inertia force and torque under the auxiliary motions.
  kane::addAuxiliaryInertiaForces(k.rod1, rod1, u, u_dot, &eq);
  kane::addAuxiliaryInertiaForces(k.rod2, rod2, u, u_dot, &eq);
  kane::addAuxiliaryInertiaForces(k.slider3, slider3, u_dot, &eq);
  kane::addAuxiliaryInertiaForces(k.slider4, slider4, u_dot, &eq);
  // F̃_s of the known loads: each force at its point of its body, each torque on its body's
  // frame, under the auxiliary motions (the list of F_r, eq 16).
  const kane::AuxiliaryMotion<kNumReactions>* rods[] = {&rod1, &rod2};
  const Eigen::Vector3d* rod_centers[] = {&g.rod1_center, &g.rod2_center};
  const Aux* sliders[] = {&slider3, &slider4};
  for (const MechanismLoad& l : loads) {
    const bool rod = l.body == kRod1 || l.body == kRod2;
    if (l.load.kind == kane::Load<kNumSpeeds>::kTorqueOnFrame) {
      // The sliders are particles: nothing in the model puts a torque on them.
      if (rod) kane::addAuxiliaryActiveForces(l.load.vector, rods[l.body]->angular_velocity, &eq);
    } else if (rod) {
      const Aux at_point = rods[l.body]->atPoint(l.load.point - *rod_centers[l.body]);
      kane::addAuxiliaryActiveForces(l.load.vector, at_point, &eq);
    } else {
      kane::addAuxiliaryActiveForces(l.load.vector, *sliders[l.body - kSlider3], &eq);
    }
  }
  // The reactions, each on the second body from the first (the ground has no motion).
  const Aux o_on_rod1 = rod1.atPoint(g.pivot_o - g.rod1_center);
  const Aux a_rod2_from_rod1 =
      rod2.atPoint(g.pin_a - g.rod2_center) - rod1.atPoint(g.pin_a - g.rod1_center);
  const Aux b_slider3_from_rod2 = slider3 - rod2.atPoint(g.pin_b - g.rod2_center);
  kane::addReaction(kPinOx, kI, o_on_rod1, &eq);
  kane::addReaction(kPinOy, kJ, o_on_rod1, &eq);
  kane::addReaction(kPinAx, kI, a_rod2_from_rod1, &eq);
  kane::addReaction(kPinAy, kJ, a_rod2_from_rod1, &eq);
  kane::addReaction(kPinBx, kI, b_slider3_from_rod2, &eq);
  kane::addReaction(kPinBy, kJ, b_slider3_from_rod2, &eq);
  kane::addReaction(kRailSlider3, kJ, slider3, &eq);
  kane::addReaction(kRailSlider4, kJ, slider4, &eq);

  ConstraintForces f;
  const Eigen::Matrix<double, kNumReactions, 1> lambda = eq.solveReactions(&f.determinate);
  f.pin_o = {lambda[kPinOx], lambda[kPinOy]};
  f.pin_a = {lambda[kPinAx], lambda[kPinAy]};
  f.pin_b = {lambda[kPinBx], lambda[kPinBy]};
  f.rail_slider3 = lambda[kRailSlider3];
  f.rail_slider4 = lambda[kRailSlider4];
  f.spring = loadVector(loads, LoadName::kSpring, kSlider4).x();
  return f;
}

}  // namespace kane_sim
