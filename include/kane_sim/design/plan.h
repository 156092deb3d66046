// A planned motion as a controller follows it and `simulate` plays it: rows on a uniform time grid
// from t = 0, each the reference state x = (q1, q2, u1, u2), the torque command M_m held from that
// row's time to the next, and the time-varying LQR gain K about it. Past the last row the plan
// holds its last row (the goal and the equilibrium's LQR gain). ROS-free.
#ifndef KANE_SIM_DESIGN_PLAN_H
#define KANE_SIM_DESIGN_PLAN_H

#include <cmath>
#include <stdexcept>
#include <vector>

#include <Eigen/Core>

#include "kane_sim/model/state.h"

namespace kane_sim {

class PlanError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

struct PlanPoint {
  double t = 0.0;                                     // [s] from the plan's start
  Eigen::Vector4d x = Eigen::Vector4d::Zero();        // q1 [rad], q2 [m], u1 [rad/s], u2 [m/s]
  double torque = 0.0;                                // M_m [N m], the feedforward
  Eigen::RowVector4d K = Eigen::RowVector4d::Zero();  // M_m = torque - K (x_measured - x)
};

struct Plan {
  std::vector<PlanPoint> points;  // t_i = i * step
  double step = 0.0;              // [s] the rows' spacing
  // The crank's error taken within (-pi, pi] (no crank spring: the equations repeat every turn).
  bool periodic = true;

  double duration() const { return points.empty() ? 0.0 : points.back().t; }

  // The reference at t: the state and the gain interpolated linearly between the rows around t,
  // the torque of the row in force (held over its step, as a command is); before 0 the first
  // row, from the last row's time on the last.
  PlanPoint at(double t) const {
    if (points.empty()) throw PlanError("the plan has no rows");
    if (!(t > 0.0)) return points.front();  // NaN too: the start
    const double position = t / step;
    if (position >= static_cast<double>(points.size() - 1)) return points.back();
    const size_t row = static_cast<size_t>(position);
    const double s = position - static_cast<double>(row);
    const PlanPoint& a = points[row];
    const PlanPoint& b = points[row + 1];
    PlanPoint p = a;
    p.t = t;
    p.x = a.x + s * (b.x - a.x);
    p.K = a.K + s * (b.K - a.K);
    return p;
  }

  // The tracking law: M_m = torque(t) - K(t) (x - x_ref(t)).
  double command(double t, const State& x) const {
    const PlanPoint p = at(t);
    Eigen::Vector4d error = Eigen::Vector4d(x.q1, x.q2, x.u1, x.u2) - p.x;
    if (periodic) error[0] = std::remainder(error[0], 2 * M_PI);
    return p.torque - p.K.dot(error);
  }
};

}  // namespace kane_sim

#endif  // KANE_SIM_DESIGN_PLAN_H
