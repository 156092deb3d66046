// The reaction (constraint) forces of the textbook example's mechanism, from Kane's method with
// auxiliary generalized speeds (kane/auxiliary_speeds.h): the forces the pins and the rails
// exert, which Kane's equations F*_r + F_r = 0 never contain (they do no work in the mechanism's
// motion). Every force is in frame (0): x = i down, y = j horizontal.
#ifndef KANE_SIM_MODEL_CONSTRAINT_FORCES_H
#define KANE_SIM_MODEL_CONSTRAINT_FORCES_H

#include <cmath>

#include <Eigen/Core>

#include "kane_sim/model/mechanism_model.h"
#include "kane_sim/model/state.h"

namespace kane_sim {

struct ConstraintForces {
  Eigen::Vector2d pin_o = Eigen::Vector2d::Zero();  // [N] (x, y) of the ground on rod 1 at O
  Eigen::Vector2d pin_a = Eigen::Vector2d::Zero();  // [N] of rod 1 on rod 2 at A
  Eigen::Vector2d pin_b = Eigen::Vector2d::Zero();  // [N] of rod 2 on slider 3 at B
  double rail_slider3 = 0.0;  // [N] of the rail on slider 3, along y (the rail's normal)
  double rail_slider4 = 0.0;  // [N] of the rail on slider 4, along y
  double spring = 0.0;        // [N] k e: the spring's push on slider 4 along +x (> 0 compressed)
  // False where the constraints cannot tell the reactions apart: at q1 = ±90° B passes through
  // O, rod 2 is square to the rail and the rail force on slider 3 is undetermined (the rigid
  // model's toggle point; near it the rail force grows as 1 / cos q1). The values are then
  // the least-squares split, finite.
  bool determinate = true;

  bool allFinite() const {
    return pin_o.allFinite() && pin_a.allFinite() && pin_b.allFinite() &&
           std::isfinite(rail_slider3) && std::isfinite(rail_slider4) && std::isfinite(spring);
  }
};

// The reactions at state x with accelerations u' (from the equations in use, constrained when
// the sliders rest on each other), the commanded crank moment (the motor line applies as in the
// equations) and the resting contact's force N on slider 4 along +x (0 when apart).
ConstraintForces constraintForces(const MechanismModel& model, const State& x,
                                  const SpeedVector& u_dot, double motor_command,
                                  double contact_force);
// The same from the kinematics and loads of x already at hand (the snapshot has them), the
// contact's entries among the loads.
ConstraintForces constraintForces(const MechanismKinematics& k, const MechanismLoads& loads,
                                  const State& x, const SpeedVector& u_dot);

}  // namespace kane_sim

#endif  // KANE_SIM_MODEL_CONSTRAINT_FORCES_H
