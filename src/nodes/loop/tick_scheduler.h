// Wall-clock pacing of physics ticks on a steady clock (immune to system clock jumps).
//
// Tick n is due at anchor + n * period. A late tick runs at once, so short hiccups are caught
// up and sim time does not drift from wall time; when the loop is more than `max_lag` behind,
// it re-anchors and reports how far it fell behind instead of bursting to catch up.
#ifndef KANE_SIM_NODES_LOOP_TICK_SCHEDULER_H
#define KANE_SIM_NODES_LOOP_TICK_SCHEDULER_H

#include <chrono>
#include <cstdint>

namespace kane_sim {

class TickScheduler {
 public:
  using Clock = std::chrono::steady_clock;

  struct Timing {
    double lateness = 0.0;  // [s] how long after its due time the tick started, >= 0
    bool overrun = false;   // the tick started more than one period late
    double skipped = 0.0;   // [s] lag dropped by re-anchoring (0 when on schedule)
  };

  // period: wall seconds per tick (physics step / real_time_factor); 0 = free-running.
  TickScheduler(double period, double max_lag);

  void anchor(Clock::time_point now);  // the next tick is due now
  bool freeRunning() const { return period_ <= 0.0; }
  Clock::time_point due() const;        // when the next tick is due
  Timing start(Clock::time_point now);  // the due tick starts at `now`

 private:
  double period_;
  double max_lag_;
  Clock::time_point anchor_;
  std::uint64_t ticks_since_anchor_ = 0;
};

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_LOOP_TICK_SCHEDULER_H
