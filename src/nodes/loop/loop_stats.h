// Loop health over a reporting window: tick lateness percentiles, overruns, achieved physics
// rate and real-time factor. ROS-free; the node turns a Summary into diagnostics.
#ifndef KANE_SIM_NODES_LOOP_LOOP_STATS_H
#define KANE_SIM_NODES_LOOP_LOOP_STATS_H

#include <cstdint>
#include <vector>

namespace kane_sim {

class LoopStats {
 public:
  struct Summary {
    std::uint64_t ticks = 0;
    std::uint64_t overruns = 0;
    double lateness_p50 = 0.0;      // [s]
    double lateness_p99 = 0.0;      // [s]
    double lateness_max = 0.0;      // [s]
    double physics_rate = 0.0;      // [Hz] ticks per wall second
    double real_time_factor = 0.0;  // sim seconds per wall second
    double skipped = 0.0;           // [s] lag dropped by re-anchoring
  };

  void recordTick(double lateness, bool overrun, double skipped);
  // Closes the window that lasted `wall_seconds` and advanced sim time by `sim_seconds`.
  Summary takeSummary(double wall_seconds, double sim_seconds);

 private:
  std::vector<double> lateness_;
  std::uint64_t overruns_ = 0;
  double skipped_ = 0.0;
};

// Whether the loop is behind its schedule in a way worth a warning: a window is late when more
// than `overrun_fraction` of its ticks overran or lag was dropped, and the loop is behind once
// `late_windows` consecutive windows were late. A shared machine makes a few ticks late all the
// time (5 of 1000 overran in 19 of 20 s on a loaded 2-core VM); that is no news, sustained
// lateness is.
class LoopHealth {
 public:
  LoopHealth(double overrun_fraction, int late_windows)
      : overrun_fraction_(overrun_fraction), late_windows_(late_windows) {}
  // The window just closed; returns whether the loop is behind now.
  bool update(const LoopStats::Summary& window) {
    const bool late =
        window.skipped > 0.0 || static_cast<double>(window.overruns) >
                                    overrun_fraction_ * static_cast<double>(window.ticks);
    consecutive_ = late ? consecutive_ + 1 : 0;
    return behind();
  }
  bool behind() const { return consecutive_ >= late_windows_; }
  int consecutiveLateWindows() const { return consecutive_; }

 private:
  double overrun_fraction_;
  int late_windows_;
  int consecutive_ = 0;
};

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_LOOP_LOOP_STATS_H
