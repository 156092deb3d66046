#include "loop/tick_scheduler.h"

#include <algorithm>

namespace kane_sim {

TickScheduler::TickScheduler(double period, double max_lag) : period_(period), max_lag_(max_lag) {}

void TickScheduler::anchor(Clock::time_point now) {
  anchor_ = now;
  ticks_since_anchor_ = 0;
}

TickScheduler::Clock::time_point TickScheduler::due() const {
  if (freeRunning()) return anchor_;
  return anchor_ + std::chrono::duration_cast<Clock::duration>(
                       std::chrono::duration<double>(period_ * ticks_since_anchor_));
}

TickScheduler::Timing TickScheduler::start(Clock::time_point now) {
  Timing timing;
  if (freeRunning()) return timing;
  timing.lateness = std::max(0.0, std::chrono::duration<double>(now - due()).count());
  timing.overrun = timing.lateness > period_;
  if (timing.lateness > max_lag_) {
    timing.skipped = timing.lateness;
    anchor(now);
  }
  ++ticks_since_anchor_;
  return timing;
}

}  // namespace kane_sim
