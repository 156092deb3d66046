// Loop health over a reporting window: tick lateness percentiles, overruns, achieved physics
// rate and real-time factor. ROS-free; the node turns a Summary into diagnostics.
#ifndef KANE_SIM_SIM_LOOP_STATS_H
#define KANE_SIM_SIM_LOOP_STATS_H

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

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_LOOP_STATS_H
