// The seed's mechanism ("Kane equations - Example 1") written on the generic Kane code.
//
// Frame (0): origin O at the crank pivot, i vertical pointing down (gravity is +g i), j
// horizontal, k = i x j. Bodies in the seed's numbering: 1 = rod OA, 2 = rod AB (both 2L long,
// mass m), 3 = slider at B (M1), 4 = slider at C (M2), both on the i axis. A massless spring k
// joins 3 and 4 and is unstretched at the initial configuration (q10, q20).
#ifndef KANE_SIM_MECHANISM_MODEL_H
#define KANE_SIM_MECHANISM_MODEL_H

#include <array>

#include <Eigen/Core>

#include "kane_sim/config.h"
#include "kane_sim/kane_equations.h"
#include "kane_sim/state.h"

namespace kane_sim {

enum Body { kRod1 = 0, kRod2 = 1, kSlider3 = 2, kSlider4 = 3, kNumBodies = 4 };

// Where everything is for given (q1, q2), in frame (0). One source for positions: the dynamics,
// the energy, tf and markers all read them from here.
struct MechanismGeometry {
  Eigen::Vector3d pivot_o;      // O, the crank's ground pivot
  Eigen::Vector3d pin_a;        // A = 2L (cos q1, sin q1)
  Eigen::Vector3d pin_b;        // B = (4L cos q1, 0), also slider 3's mass center
  Eigen::Vector3d point_c;      // C = (q2, 0), slider 4's mass center
  Eigen::Vector3d rod1_center;  // C1
  Eigen::Vector3d rod2_center;  // C2
  double rod1_angle;            // angle of rod 1 (O -> A) about k, from i:  q1
  double rod2_angle;            // angle of rod 2 (A -> B) about k, from i: -q1
};

struct EnergyTerms {
  double kinetic = 0.0;        // T  [J]
  double gravitational = 0.0;  // V_g = -Σ m g (r · i)  [J], zero at the level of O
  double spring = 0.0;         // V_s = ½ k e²  [J]
  double total() const { return kinetic + gravitational + spring; }
};

class MechanismModel {
 public:
  using Bodies = std::array<RigidBodyTerms<kNumSpeeds>, kNumBodies>;
  using Forces = GeneralizedForces<kNumSpeeds>;

  // spring_free: the configuration (q10, q20) at which the spring is unstretched.
  MechanismModel(const MechanismParameters& parameters, const State& spring_free);

  MechanismGeometry geometry(double q1, double q2) const;

  // Kinematics (eqs 1-4) and applied loads (eqs 14, 15 and M_m) of every body.
  Bodies bodies(const State& x, double motor_torque) const;

  // F*_r (as mass matrix + remainder) and F_r, eqs (12) and (16).
  Forces generalizedForces(const State& x, double motor_torque) const;

  // u' from F*_r + F_r = 0, eq (18).
  SpeedVector accelerations(const State& x, double motor_torque) const {
    return generalizedForces(x, motor_torque).solveAccelerations();
  }

  // e = (x_B - x_C) - (x_B0 - x_C0) [m]; F_eB = -k e i, F_eC = +k e i (eq 15).
  double springElongation(double q1, double q2) const;

  EnergyTerms energy(const State& x) const;

  const MechanismParameters& parameters() const { return parameters_; }
  const State& springFreeState() const { return spring_free_; }

 private:
  // The same with cos q1 and sin q1 already at hand: the hot path evaluates them once.
  MechanismGeometry geometry(double q1, double cos_q1, double sin_q1, double q2) const;
  double springElongationFromCos(double cos_q1, double q2) const;

  MechanismParameters parameters_;
  State spring_free_;
  double spring_free_separation_;  // x_B0 - x_C0 = 4L cos q10 - q20
};

}  // namespace kane_sim

#endif  // KANE_SIM_MECHANISM_MODEL_H
