// The wall-clock side of the node's publishing, ROS-free: the real-time factor achieved between
// two publishes, whether a publish period of wall time has passed since the last one (refused
// steps and pauses keep wall-stamped topics flowing at that pace), and the /diagnostics window.
#ifndef KANE_SIM_NODES_LOOP_PUBLISH_PACE_H
#define KANE_SIM_NODES_LOOP_PUBLISH_PACE_H

#include <chrono>

namespace kane_sim {

class PublishPace {
 public:
  using Clock = std::chrono::steady_clock;

  // publish_rate [Hz]: the wall-clock pace of publishes when sim time does not advance them.
  explicit PublishPace(double publish_rate) : publish_period_(1.0 / publish_rate) {}

  // Both the last publish and the diagnostics window start here.
  void start(Clock::time_point now, double sim_time);
  // A publish at `now` of the state at `sim_time`: the real-time factor achieved since the last
  // one (sim time per wall time; the previous figure when no wall time passed).
  double published(Clock::time_point now, double sim_time);
  double realTimeFactor() const { return real_time_factor_; }
  // Wall seconds since the last publish, and whether a publish period has passed.
  double sinceLastPublish(Clock::time_point now) const;
  bool dueByWallClock(Clock::time_point now) const {
    return sinceLastPublish(now) >= publish_period_;
  }

  // The diagnostics window: its wall length so far, and closing it at `now` (the next one
  // starts there); closeWindow returns the sim time it covered.
  double windowWall(Clock::time_point now) const;
  double closeWindow(Clock::time_point now, double sim_time);

 private:
  double publish_period_;  // [s] wall
  Clock::time_point last_publish_wall_;
  double last_publish_sim_ = 0.0;
  double real_time_factor_ = 0.0;
  Clock::time_point window_start_wall_;
  double window_start_sim_ = 0.0;
};

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_LOOP_PUBLISH_PACE_H
