// Time-varying LQR along a plan, as Drake's FiniteHorizonLinearQuadraticRegulator designs it: the
// gain K(t) = R^-1 B(t)' P(t) that keeps the mechanism on the plan, P from the Riccati
// differential equation integrated backward from the plan's end,
//
//   -P' = A' P + P A - P B R^-1 B' P + Q,   P(T) = P_final (the goal equilibrium's LQR),
//
// A(t), B(t) the exact linearization (GeneratedMechanism::linearization) about the plan's state
// and torque. ROS-free.
#ifndef KANE_SIM_DESIGN_TVLQR_H
#define KANE_SIM_DESIGN_TVLQR_H

#include <Eigen/Core>

#include "kane_sim/design/lqr.h"
#include "kane_sim/design/plan.h"
#include "kane_sim/model/mechanism_model.h"

namespace kane_sim {

// Fills every row's K of `plan` (its states and torques set). Integrates with rk4, one step per
// row (A and B at the rows; their mean in between). Throws RiccatiError when P stops being
// finite (weights that make the equation blow up).
void fillTimeVaryingLqr(const MechanismModel& model, const LqrWeights& weights,
                        const Eigen::Matrix4d& P_final, Plan* plan);

}  // namespace kane_sim

#endif  // KANE_SIM_DESIGN_TVLQR_H
