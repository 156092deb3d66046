// Tick pacing and loop statistics, driven with synthetic time points (no sleeping).
#include <chrono>

#include <gtest/gtest.h>

#include "loop/loop_stats.h"
#include "loop/tick_scheduler.h"

namespace kane_sim {
namespace {

using Clock = TickScheduler::Clock;
using std::chrono::microseconds;

TEST(TickScheduler, TicksAreDueOnAFixedGridFromTheAnchor) {
  TickScheduler s(0.001, 0.1);
  const Clock::time_point t0{};
  s.anchor(t0);
  for (int n = 0; n < 5; ++n) {
    EXPECT_EQ(s.due(), t0 + microseconds(1000 * n));
    const auto timing = s.start(s.due() + microseconds(30));  // 30 µs late each time
    EXPECT_NEAR(timing.lateness, 30e-6, 1e-9);
    EXPECT_FALSE(timing.overrun);
  }
}

TEST(TickScheduler, ShortHiccupIsCaughtUpWithoutDrift) {
  TickScheduler s(0.001, 0.1);
  const Clock::time_point t0{};
  s.anchor(t0);
  const auto late = s.start(t0 + microseconds(5000));  // the first tick 5 ms late
  EXPECT_TRUE(late.overrun);
  EXPECT_EQ(late.skipped, 0.0);
  EXPECT_EQ(s.due(), t0 + microseconds(1000));  // the grid did not move: catch up
}

TEST(TickScheduler, LongStallReanchorsAndReportsTheLag) {
  TickScheduler s(0.001, 0.1);
  const Clock::time_point t0{};
  s.anchor(t0);
  const auto stall = s.start(t0 + microseconds(300000));
  EXPECT_NEAR(stall.skipped, 0.3, 1e-9);
  EXPECT_EQ(s.due(), t0 + microseconds(301000));
}

TEST(TickScheduler, FreeRunningNeverWaits) {
  TickScheduler s(0.0, 0.1);
  s.anchor(Clock::time_point{});
  EXPECT_TRUE(s.freeRunning());
  EXPECT_EQ(s.start(Clock::time_point{} + std::chrono::seconds(10)).lateness, 0.0);
}

TEST(LoopStats, PercentilesRatesAndWindowReset) {
  LoopStats stats;
  for (int i = 1; i <= 1000; ++i) stats.recordTick(i * 1e-6, i > 995, 0.0);
  const LoopStats::Summary s = stats.takeSummary(2.0, 1.0);
  EXPECT_EQ(s.ticks, 1000u);
  EXPECT_EQ(s.overruns, 5u);
  EXPECT_NEAR(s.lateness_p50, 500e-6, 1e-12);
  EXPECT_NEAR(s.lateness_p99, 990e-6, 1e-12);
  EXPECT_NEAR(s.lateness_max, 1000e-6, 1e-12);
  EXPECT_NEAR(s.physics_rate, 500.0, 1e-9);
  EXPECT_NEAR(s.real_time_factor, 0.5, 1e-12);
  EXPECT_EQ(stats.takeSummary(1.0, 1.0).ticks, 0u);
}

// WARN on sustained lateness only: a few overrun ticks in every window (5 of 1000 on a shared
// machine) never warn; more than the fraction for `late_windows` windows in a row does, and one
// good window clears it. Dropped lag makes a window late whatever the fraction.
TEST(LoopHealth, WarnsOnSustainedLatenessOnly) {
  LoopHealth health(0.05, 3);
  LoopStats::Summary few;
  few.ticks = 1000;
  few.overruns = 5;
  for (int i = 0; i < 20; ++i) EXPECT_FALSE(health.update(few));
  LoopStats::Summary many = few;
  many.overruns = 51;
  EXPECT_FALSE(health.update(many));
  EXPECT_FALSE(health.update(many));
  EXPECT_TRUE(health.update(many));
  EXPECT_EQ(health.consecutiveLateWindows(), 3);
  EXPECT_FALSE(health.update(few)) << "one window on time clears it";
  LoopStats::Summary lag = few;
  lag.skipped = 0.2;
  LoopHealth strict(0.05, 1);
  EXPECT_TRUE(strict.update(lag));
}

}  // namespace
}  // namespace kane_sim
