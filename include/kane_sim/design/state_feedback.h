// A state-feedback law about an equilibrium, as a controller runs it:
//   M_m = torque - K (x - state),   x = (q1, q2, u1, u2)
// with the crank's error taken within (-pi, pi] when the mechanism repeats every turn. What
// `design lqr` writes and a controller reads (design/lqr_file.h). ROS-free.
#ifndef KANE_SIM_DESIGN_STATE_FEEDBACK_H
#define KANE_SIM_DESIGN_STATE_FEEDBACK_H

#include <cmath>

#include <Eigen/Core>

#include "kane_sim/model/state.h"

namespace kane_sim {

struct StateFeedback {
  Eigen::Vector4d state = Eigen::Vector4d::Zero();  // x_eq
  double torque = 0.0;                              // M_eq [N m]
  Eigen::RowVector4d K = Eigen::RowVector4d::Zero();
  bool periodic = true;  // no crank spring: the equations repeat every turn

  double command(const State& x) const {
    Eigen::Vector4d error = Eigen::Vector4d(x.q1, x.q2, x.u1, x.u2) - state;
    if (periodic) error[0] = std::remainder(error[0], 2 * M_PI);
    return torque - K.dot(error);
  }
};

}  // namespace kane_sim

#endif  // KANE_SIM_DESIGN_STATE_FEEDBACK_H
