// A plan as a controller runs it against readings: the plan's clock starts at the first reading's
// stamp (or at a restart), each reading answered with the tracking law
//   M_m = M_m(t) - K(t) (x - x(t)),  t = stamp - start,
// stamps in whole nanoseconds as messages carry them (so a node and an offline loop that give the
// same stamps compute the same t to the bit),
// clamped to the drive's limit; past the plan's end its last row (the goal's LQR) holds. What the
// tracking_controller node and the offline closed loop (sim/closed_loop.h) both run. ROS-free.
#ifndef KANE_SIM_DESIGN_PLAN_FOLLOWER_H
#define KANE_SIM_DESIGN_PLAN_FOLLOWER_H

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>

#include "kane_sim/design/plan.h"
#include "kane_sim/model/state.h"

namespace kane_sim {

class PlanFollower {
 public:
  PlanFollower(Plan plan, double torque_limit)
      : plan_(std::move(plan)), torque_limit_(torque_limit) {}

  // The torque for a reading of state `x` stamped `stamp` [ns]; nullopt for a reading it cannot
  // use (a value not finite): the caller keeps its last command. A stamp before the start (the
  // clock went back: a restarted simulation) restarts the plan there.
  std::optional<double> command(std::int64_t stamp, const State& x) {
    if (!x.isFinite()) return std::nullopt;
    if (!started_ || stamp < start_) {
      started_ = true;
      start_ = stamp;
    }
    const double torque = plan_.command(planTime(stamp), x);
    if (!std::isfinite(torque)) return std::nullopt;
    return std::clamp(torque, -torque_limit_, torque_limit_);
  }

  // The next reading starts the plan again.
  void restart() { started_ = false; }
  // [s] of the plan at `stamp` [ns] (0 before the first reading).
  double planTime(std::int64_t stamp) const {
    return started_ ? static_cast<double>(stamp - start_) * 1e-9 : 0.0;
  }
  const Plan& plan() const { return plan_; }
  double torqueLimit() const { return torque_limit_; }

 private:
  Plan plan_;
  double torque_limit_;
  bool started_ = false;
  std::int64_t start_ = 0;  // [ns] the plan's t = 0
};

}  // namespace kane_sim

#endif  // KANE_SIM_DESIGN_PLAN_FOLLOWER_H
