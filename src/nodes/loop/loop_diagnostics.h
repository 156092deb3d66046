// The physics loop's /diagnostics status, one per 1 s window: what happened in the window
// (commands received and refused, steps refused and why), lateness judged by LoopHealth
// (sustained lateness only), the loop's state (paused, stopped at the time limit). ROS-thin: it
// builds the diagnostic_msgs status, the node publishes it; unit-tested without a master.
#ifndef KANE_SIM_NODES_LOOP_LOOP_DIAGNOSTICS_H
#define KANE_SIM_NODES_LOOP_LOOP_DIAGNOSTICS_H

#include <cstdint>
#include <string>

#include <diagnostic_msgs/DiagnosticStatus.h>

#include "kane_sim/config/config.h"
#include "loop/loop_stats.h"

namespace kane_sim {

class LoopDiagnostics {
 public:
  explicit LoopDiagnostics(const DiagnosticsSettings& settings)
      : health_(settings.overrun_fraction, settings.late_windows) {}

  void commandReceived(bool refused) {
    ++commands_;
    if (refused) ++commands_refused_;
  }
  void lockstepTimedOut() { ++lockstep_timeouts_; }
  void stepRefused(const std::string& why) {
    ++steps_refused_;
    last_refusal_ = why;
  }

  // What the status reports besides the window's summary.
  struct LoopState {
    std::string node_name;  // "/kane_sim"
    std::string node_namespace;
    bool paused = false;
    bool stopped_at_time_limit = false;
    double physics_rate = 0.0;      // [Hz] configured
    double real_time_factor = 0.0;  // configured
    double sim_time = 0.0;          // [s]
  };

  // Closes the window (`wall_window` seconds long): its status, and the counters start anew.
  // OK on schedule or paused, WARN when behind for late_windows windows, ERROR while steps are
  // refused.
  diagnostic_msgs::DiagnosticStatus close(const LoopStats::Summary& summary, double wall_window,
                                          const LoopState& loop);

 private:
  LoopHealth health_;
  std::uint64_t commands_ = 0;
  std::uint64_t commands_refused_ = 0;
  std::uint64_t steps_refused_ = 0;
  std::uint64_t lockstep_timeouts_ = 0;
  std::string last_refusal_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_LOOP_LOOP_DIAGNOSTICS_H
