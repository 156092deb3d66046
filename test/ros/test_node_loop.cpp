// The node's loop parts, each alone and without a master: stamps (sim epoch, monotonic wall
// stamps, the /use_sim_time check), the master watch (a fake getPid), the /diagnostics status of
// a window, and the paced wait that serves callbacks.
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <thread>

#include <gtest/gtest.h>
#include <ros/callback_queue.h>
#include <ros/time.h>

#include "kane_sim/ros/messages.h"
#include "loop/lockstep_gate.h"
#include "loop/loop_diagnostics.h"
#include "loop/master_watch.h"
#include "loop/paced_loop.h"
#include "loop/publish_pace.h"
#include "loop/realtime.h"
#include "loop/stamp_clock.h"

namespace kane_sim {
namespace {

class NodeLoop : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { ros::Time::init(); }
};

TEST_F(NodeLoop, SimStampsAreSimTimeOnTheEpoch) {
  StampClock clock(true);
  // The wall clock plays no part; the epoch keeps stamps of a fresh run clear of zero.
  EXPECT_EQ(clock.stamp(0.0, ros::WallTime(5, 0)), ros::Time(kSimEpochSeconds, 0));
  EXPECT_EQ(clock.stamp(12.5, ros::WallTime(1000, 0)), ros::Time(kSimEpochSeconds + 12, 500000000));
}

// A moved state (reset, set_state) at an unchanged sim time gets a stamp after every earlier
// one; the states after it are stamped with their sim time again.
TEST_F(NodeLoop, AMovedStateIsStampedAfterEveryEarlierStamp) {
  StampClock clock(true);
  const ros::Time before = clock.stamp(1.0, ros::WallTime(0, 0));
  EXPECT_EQ(clock.stamp(1.0, ros::WallTime(0, 0)), before);  // the same state: the same stamp
  clock.forceNext();
  const ros::Time moved = clock.stamp(1.0, ros::WallTime(0, 0));
  EXPECT_EQ(moved, before + ros::Duration(0, 1000));
  clock.forceNext();
  EXPECT_EQ(clock.stamp(1.0, ros::WallTime(0, 0)), moved + ros::Duration(0, 1000));
  EXPECT_EQ(clock.stamp(1.001, ros::WallTime(0, 0)), ros::Time(kSimEpochSeconds + 1, 1000000));
}

// Lockstep: the first answer to the state awaiting one is applied; a second controller's
// answer (or another torque) is dropped and said once; an answer to an earlier state is late;
// one stamped with a time never published (now()) is named, with the stamp awaited.
// The timeout's report: that nothing came, or that commands came but matched no state.
TEST_F(NodeLoop, LockstepGateTimeoutReportSaysWhetherCommandsCame) {
  LockstepGate gate;
  gate.published(ros::Time(10, 0));
  EXPECT_EQ(gate.timeoutReport(1.5, 1.0, false),
            "lockstep: no torque_command_stamped for the state at t = 1.500000 s within 1 s; "
            "holding the last command and stepping on");
  EXPECT_EQ(gate.answer(ros::Time(99, 0), "/ctrl", 1.0), LockstepGate::Verdict::kUnknown);
  const std::string report = gate.timeoutReport(1.5, 1.0, true);
  EXPECT_NE(report.find("1 torque_command_stamped arrived for the state at t = 1.500000 s "
                        "(stamped 10.000000000) but matched no published state (the last "
                        "stamped 99.000000000)"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("commanding 0 N m"), std::string::npos) << report;
}

TEST_F(NodeLoop, LockstepGateAppliesTheFirstAnswerAndNamesTheRest) {
  LockstepGate gate;
  EXPECT_TRUE(gate.answered()) << "nothing published: nothing awaits an answer";
  const ros::Time s1(100, 0), s2(100, 10000000);
  gate.published(s1);
  EXPECT_FALSE(gate.answered());
  EXPECT_EQ(gate.answer(s1, "/ctrl_a", 2.0), LockstepGate::Verdict::kApply);
  EXPECT_TRUE(gate.answered());
  // The same controller answering a repeat of the state with the same torque: quietly dropped.
  EXPECT_EQ(gate.answer(s1, "/ctrl_a", 2.0), LockstepGate::Verdict::kDuplicate);
  EXPECT_EQ(gate.warning(), "");
  EXPECT_EQ(gate.answer(s1, "/ctrl_b", -3.0), LockstepGate::Verdict::kDuplicate);
  EXPECT_NE(gate.warning().find("/ctrl_b answered the state stamped 100.000000000 with -3 N m "
                                "after /ctrl_a answered it with 2 N m; the first answer is "
                                "applied"),
            std::string::npos)
      << gate.warning();
  gate.published(s1);  // a repeat of the state: nothing new awaits an answer
  EXPECT_TRUE(gate.answered());
  gate.published(s2);
  EXPECT_FALSE(gate.answered());
  EXPECT_EQ(gate.answer(s2, "/ctrl_a", 1.0), LockstepGate::Verdict::kApply);
  EXPECT_EQ(gate.answer(s2, "/ctrl_b", 5.0), LockstepGate::Verdict::kDuplicate);
  EXPECT_EQ(gate.warning(), "") << "said once";
  EXPECT_EQ(gate.answer(s1, "/ctrl_a", 2.0), LockstepGate::Verdict::kLate);
  gate.published(ros::Time(100, 20000000));
  const ros::Time now_stamp(1700000000, 123);
  EXPECT_EQ(gate.answer(now_stamp, "/wall_ctrl", 1.0), LockstepGate::Verdict::kUnknown);
  EXPECT_NE(gate.warning().find("from /wall_ctrl stamped 1700000000.000000123 matches no "
                                "joint_states this node published (the state awaiting an "
                                "answer is stamped 100.020000000)"),
            std::string::npos)
      << gate.warning();
  EXPECT_EQ(gate.unknownSinceState(), 1u);
  EXPECT_EQ(gate.lastUnknownStamp(), now_stamp);
  EXPECT_FALSE(gate.answered());
  gate.release();  // the timeout
  EXPECT_TRUE(gate.answered());
  EXPECT_EQ(gate.answer(ros::Time(100, 20000000), "/slow", 1.0), LockstepGate::Verdict::kDuplicate)
      << "released by the timeout: an answer after it is too late for that state";
}

TEST_F(NodeLoop, WallStampsNeverGoBackwards) {
  StampClock clock(false);
  double back = -1;
  EXPECT_EQ(clock.stamp(0, ros::WallTime(100, 0), &back), ros::Time(100, 0));
  EXPECT_EQ(back, 0.0);
  // The system clock steps back 2 s: held 1 µs after the last stamp, and the step is reported.
  const ros::Time held = clock.stamp(0, ros::WallTime(98, 0), &back);
  EXPECT_EQ(held, ros::Time(100, 1000));
  EXPECT_DOUBLE_EQ(back, 2.0);
  // The same reading twice: still strictly increasing.
  EXPECT_GT(clock.stamp(0, ros::WallTime(98, 0)), held);
  // Caught up: wall time again.
  EXPECT_EQ(clock.stamp(0, ros::WallTime(101, 0), &back), ros::Time(101, 0));
  EXPECT_EQ(back, 0.0);
}

TEST_F(NodeLoop, UseSimTimeDisagreementIsSaidOncePerDisagreement) {
  StampClock wall(false);
  EXPECT_EQ(wall.checkUseSimTime(false), "");
  const std::string warning = wall.checkUseSimTime(true);
  EXPECT_NE(warning.find("/use_sim_time is true but this node runs on the wall clock"),
            std::string::npos);
  EXPECT_EQ(wall.checkUseSimTime(true), "");  // once
  EXPECT_EQ(wall.checkUseSimTime(false), "");
  EXPECT_EQ(wall.checkUseSimTime(true), warning);  // again after they agreed
  StampClock sim(true);
  EXPECT_NE(sim.checkUseSimTime(false).find("/use_sim_time is false"), std::string::npos);
}

// Waits until `condition` holds, at most `limit`.
template <typename Condition>
bool eventually(Condition condition, std::chrono::milliseconds limit) {
  const auto end = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < end) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return condition();
}

TEST_F(NodeLoop, MasterWatchReportsANewPidOnce) {
  std::atomic<int> pid{100};
  std::atomic<bool> up{true};
  std::atomic<int> questions{0};
  MasterWatch watch(
      [&](int* out) {
        ++questions;
        *out = pid;
        return up.load();
      },
      std::chrono::milliseconds(5));
  ASSERT_TRUE(eventually([&] { return questions > 3; }, std::chrono::seconds(2)));
  EXPECT_FALSE(watch.restarted());  // the same master all along
  up = false;                       // down: not yet a new master
  pid = 200;
  const int asked = questions;
  ASSERT_TRUE(eventually([&] { return questions > asked + 3; }, std::chrono::seconds(2)));
  EXPECT_FALSE(watch.restarted());
  up = true;  // back with another pid: one restart
  bool seen = false;
  ASSERT_TRUE(
      eventually([&] { return seen = seen || watch.restarted(); }, std::chrono::seconds(2)));
  const int after = questions;
  ASSERT_TRUE(eventually([&] { return questions > after + 3; }, std::chrono::seconds(2)));
  EXPECT_FALSE(watch.restarted());  // reported once
}

LoopStats::Summary window(std::uint64_t ticks, std::uint64_t overruns, double skipped = 0.0) {
  LoopStats::Summary s;
  s.ticks = ticks;
  s.overruns = overruns;
  s.skipped = skipped;
  s.physics_rate = static_cast<double>(ticks);
  return s;
}

std::string value(const diagnostic_msgs::DiagnosticStatus& status, const std::string& key) {
  for (const auto& kv : status.values)
    if (kv.key == key) return kv.value;
  return "<missing>";
}

TEST_F(NodeLoop, DiagnosticsWarnOnSustainedLatenessOnly) {
  DiagnosticsSettings settings;  // 5 % of a window, 3 windows
  LoopDiagnostics diagnostics(settings);
  LoopDiagnostics::LoopState loop{"/kane_sim", "/", false, false, 1000.0, 1.0, 1.0};
  using Status = diagnostic_msgs::DiagnosticStatus;
  EXPECT_EQ(diagnostics.close(window(1000, 10), 1.0, loop).level, Status::OK);   // 1 %: not late
  EXPECT_EQ(diagnostics.close(window(1000, 100), 1.0, loop).level, Status::OK);  // late once
  EXPECT_EQ(diagnostics.close(window(1000, 100), 1.0, loop).level, Status::OK);  // twice
  const Status behind = diagnostics.close(window(1000, 100), 1.0, loop);         // three times
  EXPECT_EQ(behind.level, Status::WARN);
  EXPECT_NE(behind.message.find("behind schedule for 3 s: 100 of 1000 ticks overran"),
            std::string::npos)
      << behind.message;
  EXPECT_EQ(diagnostics.close(window(1000, 0), 1.0, loop).level, Status::OK);
  loop.paused = true;  // paused: never a warning, target 0
  const Status paused = diagnostics.close(window(0, 0, 0.5), 1.0, loop);
  EXPECT_EQ(paused.level, Status::OK);
  EXPECT_EQ(paused.message, "paused");
  EXPECT_EQ(value(paused, "physics rate target [Hz]"), "0");
  EXPECT_EQ(paused.name, "kane_sim: physics loop (/kane_sim)");
}

TEST_F(NodeLoop, DiagnosticsCountTheWindowAndStartAnew) {
  LoopDiagnostics diagnostics{DiagnosticsSettings{}};
  const LoopDiagnostics::LoopState loop{"/kane_sim", "/", false, false, 1000.0, 1.0, 2.0};
  for (int i = 0; i < 10; ++i) diagnostics.commandReceived(i % 5 == 0);
  diagnostics.stepRefused("first");
  diagnostics.stepRefused("u1 went non-finite");
  const auto stalled = diagnostics.close(window(1000, 0), 2.0, loop);
  EXPECT_EQ(stalled.level, diagnostic_msgs::DiagnosticStatus::ERROR);
  EXPECT_NE(stalled.message.find("physics stalled: 2 steps refused"), std::string::npos);
  EXPECT_NE(stalled.message.find("u1 went non-finite"), std::string::npos);  // the last reason
  EXPECT_EQ(value(stalled, "torque commands received [1/s]"), "5");          // 10 in 2 s
  EXPECT_EQ(value(stalled, "torque commands rejected or clamped"), "2");
  EXPECT_EQ(value(stalled, "physics steps refused"), "2");
  const auto next = diagnostics.close(window(1000, 0), 1.0, loop);
  EXPECT_EQ(next.level, diagnostic_msgs::DiagnosticStatus::OK);
  EXPECT_EQ(value(next, "torque commands received [1/s]"), "0");
  EXPECT_EQ(value(next, "physics steps refused"), "0");
}

// A callback that counts its calls, as a subscription's would be served.
struct Counting : ros::CallbackInterface {
  explicit Counting(std::atomic<int>* calls) : calls_(calls) {}
  CallResult call() override {
    ++*calls_;
    return Success;
  }
  std::atomic<int>* calls_;
};

TEST_F(NodeLoop, LockstepTimeoutsAreCountedAndWarned) {
  LoopDiagnostics diagnostics{DiagnosticsSettings{}};
  const LoopDiagnostics::LoopState loop{"/kane_sim", "/", false, false, 1000.0, 0.0, 1.0};
  diagnostics.lockstepTimedOut();
  diagnostics.lockstepTimedOut();
  const auto late = diagnostics.close(window(100, 0), 1.0, loop);
  EXPECT_EQ(late.level, diagnostic_msgs::DiagnosticStatus::WARN);
  EXPECT_NE(late.message.find("lockstep: 2 states got no torque_command_stamped in time"),
            std::string::npos)
      << late.message;
  EXPECT_EQ(value(late, "lockstep timeouts"), "2");
  EXPECT_EQ(diagnostics.close(window(100, 0), 1.0, loop).level,
            diagnostic_msgs::DiagnosticStatus::OK);
}

// In a child process (the test's own scheduling stays as it is): `check` returns the exit code.
template <typename Check>
int inChild(Check check) {
  const pid_t pid = fork();
  if (pid == 0) _exit(check());
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 100;
}

TEST_F(NodeLoop, RealtimeIsRefusedWithTheReasonWithoutPrivileges) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to become an unprivileged user";
  const int code = inChild([] {
    if (setgid(65534) != 0 || setuid(65534) != 0) return 10;  // nobody
    const RealtimeResult r = makeRealtime(10);
    if (r.scheduled) return 11;
    if (r.problem.find("SCHED_FIFO priority 10 refused") == std::string::npos) return 12;
    if (r.problem.find("rtprio") == std::string::npos) return 13;
    return sched_getscheduler(0) == SCHED_OTHER ? 0 : 14;
  });
  EXPECT_EQ(code, 0);
}

TEST_F(NodeLoop, RealtimeSchedulesFifoAndLocksMemoryWhenPermitted) {
  if (geteuid() != 0) GTEST_SKIP() << "SCHED_FIFO needs root (or an rtprio limit)";
  const int code = inChild([] {
    const RealtimeResult r = makeRealtime(10);
    if (!r.scheduled || !r.memory_locked || !r.problem.empty()) return 20;
    sched_param param{};
    int policy = 0;
    if (pthread_getschedparam(pthread_self(), &policy, &param) != 0) return 21;
    return policy == SCHED_FIFO && param.sched_priority == 10 ? 0 : 22;
  });
  EXPECT_EQ(code, 0);
}

TEST_F(NodeLoop, PacedWaitServesCallbacksAndKeepsTheDeadline) {
  ros::CallbackQueue queue;
  PacedLoop loop(0.2, 0.1);  // a slow tick: 200 ms
  loop.anchor();
  loop.startTick();  // tick 0 now; tick 1 due in 200 ms
  std::atomic<int> served{0};
  const auto start = std::chrono::steady_clock::now();
  // A callback posted during the wait is served long before the tick (the node never goes deaf).
  std::thread poster([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    queue.addCallback(boost::make_shared<Counting>(&served));
  });
  std::chrono::steady_clock::time_point served_at{};
  EXPECT_TRUE(loop.waitForTick(queue, [&] {
    if (served && served_at == std::chrono::steady_clock::time_point{})
      served_at = std::chrono::steady_clock::now();
    return false;
  }));
  const double waited =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  poster.join();
  EXPECT_EQ(served, 1);
  // Served within a wait slice (50 ms) of being posted at 20 ms, plus scheduling slack.
  EXPECT_LT(std::chrono::duration<double>(served_at - start).count(), 0.020 + 0.05 + 0.05);
  EXPECT_GE(waited, 0.2 - 1e-3);  // not before the tick is due
  EXPECT_LT(waited, 0.2 + 0.1);   // nor long after (a loaded shared machine: 100 ms slack)
  // Interrupted (a pause from a callback): returns at once, false.
  loop.startTick();
  const auto t = std::chrono::steady_clock::now();
  EXPECT_FALSE(loop.waitForTick(queue, [] { return true; }));
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count(), 0.05);
}

}  // namespace
// The node's realtime policy: off at 0; never with real_time_factor 0 (said why); otherwise
// what makeRealtime achieved, said either way.
TEST(RealtimePolicy, OffAtZeroAndRefusedWhenTheLoopNeverSleeps) {
  const RealtimePolicy off = applyRealtimePolicy(0, 1.0);
  EXPECT_FALSE(off.scheduled);
  EXPECT_TRUE(off.report.empty());
  const RealtimePolicy free_running = applyRealtimePolicy(10, 0.0);
  EXPECT_FALSE(free_running.scheduled);
  EXPECT_TRUE(free_running.warn);
  EXPECT_NE(free_running.report.find("simulation.realtime_priority 10 ignored"), std::string::npos)
      << free_running.report;
}

// The publish pace on a fake clock: the real-time factor between two publishes, the wall-clock
// publish period, the diagnostics window's wall length and the sim time it covered.
TEST(PublishPace, RealTimeFactorWallClockPeriodAndWindow) {
  using Clock = PublishPace::Clock;
  const Clock::time_point t0{};
  PublishPace pace(100.0);  // 10 ms
  pace.start(t0, 5.0);
  EXPECT_FALSE(pace.dueByWallClock(t0 + std::chrono::milliseconds(9)));
  EXPECT_TRUE(pace.dueByWallClock(t0 + std::chrono::milliseconds(10)));
  EXPECT_DOUBLE_EQ(pace.published(t0 + std::chrono::milliseconds(20), 5.04), 2.0);
  EXPECT_DOUBLE_EQ(pace.published(t0 + std::chrono::milliseconds(20), 5.04), 2.0)
      << "no wall time passed: the last figure stands";
  EXPECT_NEAR(pace.sinceLastPublish(t0 + std::chrono::milliseconds(25)), 0.005, 1e-12);
  EXPECT_NEAR(pace.windowWall(t0 + std::chrono::seconds(1)), 1.0, 1e-12);
  EXPECT_DOUBLE_EQ(pace.closeWindow(t0 + std::chrono::seconds(1), 7.0), 2.0);
  EXPECT_NEAR(pace.windowWall(t0 + std::chrono::milliseconds(1500)), 0.5, 1e-12);
}

}  // namespace kane_sim
