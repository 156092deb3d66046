// The node's physics ticks on the wall clock: a TickScheduler (steady clock, catch-up, re-anchor
// past max_lag) and the wait for the next tick, which serves ROS callbacks meanwhile in slices
// of at most kWaitSlice and sleeps the last kPreciseWait exactly, so a slow tick (a low
// real_time_factor) never makes the node deaf and a 1 kHz tick keeps its deadline. ROS-thin:
// a ros::CallbackQueue, no master; unit-tested alone.
#ifndef KANE_SIM_NODES_LOOP_PACED_LOOP_H
#define KANE_SIM_NODES_LOOP_PACED_LOOP_H

#include <functional>

#include <ros/callback_queue.h>

#include "loop/tick_scheduler.h"

namespace kane_sim {

class PacedLoop {
 public:
  static constexpr double kWaitSlice = 0.05;     // [s] wall
  static constexpr double kPreciseWait = 0.002;  // [s] wall

  // period: wall seconds per tick, 0 = free-running; max_lag: see TickScheduler.
  PacedLoop(double period, double max_lag) : max_lag_(max_lag), scheduler_(period, max_lag) {}

  // A new period (a new real_time_factor), from now on.
  void setPeriod(double period);
  // The next tick is due now (after a pause, at start).
  void anchor() { scheduler_.anchor(TickScheduler::Clock::now()); }

  // Serves `queue` until the next tick is due; returns false (at once) when `interrupted()`
  // turns true meanwhile (shutdown, pause from a callback).
  bool waitForTick(ros::CallbackQueue& queue, const std::function<bool()>& interrupted);
  // The due tick starts now: its lateness, overrun, and lag dropped.
  TickScheduler::Timing startTick() { return scheduler_.start(TickScheduler::Clock::now()); }

 private:
  double max_lag_;
  TickScheduler scheduler_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_LOOP_PACED_LOOP_H
