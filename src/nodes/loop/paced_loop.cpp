#include "loop/paced_loop.h"

#include <algorithm>
#include <chrono>
#include <thread>

namespace kane_sim {

void PacedLoop::setPeriod(double period) {
  scheduler_ = TickScheduler(period, max_lag_);
  anchor();
}

bool PacedLoop::waitForTick(ros::CallbackQueue& queue, const std::function<bool()>& interrupted) {
  if (scheduler_.freeRunning()) return !interrupted();
  using Clock = TickScheduler::Clock;
  const auto due = scheduler_.due();
  const auto precise =
      std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(kPreciseWait));
  for (auto now = Clock::now(); now + precise < due && !interrupted(); now = Clock::now()) {
    const double remaining = std::chrono::duration<double>(due - now).count() - kPreciseWait;
    queue.callAvailable(ros::WallDuration(std::min(remaining, kWaitSlice)));
  }
  if (interrupted()) return false;
  std::this_thread::sleep_until(due);
  return true;
}

}  // namespace kane_sim
