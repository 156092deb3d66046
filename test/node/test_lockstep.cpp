// Lockstep (test/node/lockstep.test, and lockstep_hog.test with two busy processes competing for
// the cores): the node steps past a published state only once the controller's
// torque_command_stamped answers it, so the trajectory is the offline driver's under the same
// law (pd_law.h, sampled at every publish, torque held between) bit for bit, whatever the load.
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Float64.h>

#include "controlled_run.h"
#include "kane_sim/MechanismState.h"
#include "kane_sim/TorqueCommandStamped.h"
#include "kane_sim/sim/sim_driver.h"
#include "node_test_utils.h"

namespace kane_sim {
namespace {

using test::Recorder;

// Two processes spinning on a core each while the test runs (killed when it ends).
class CpuHog {
 public:
  explicit CpuHog(bool on) {
    for (int i = 0; on && i < 2; ++i) {
      const pid_t pid = fork();
      if (pid == 0) {
        volatile unsigned long spin = 0;
        for (;;) ++spin;
      }
      if (pid > 0) pids_.push_back(pid);
    }
  }
  ~CpuHog() {
    for (pid_t pid : pids_) {
      kill(pid, SIGKILL);
      waitpid(pid, nullptr, 0);
    }
  }
  size_t size() const { return pids_.size(); }

 private:
  std::vector<pid_t> pids_;
};

TEST(Lockstep, TheTrajectoryIsTheOfflineOneBitForBitWhateverTheLoad) {
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  bool hog_on = false;
  pnh.getParam("hog", hog_on);
  Recorder<sensor_msgs::JointState> js(nh, "joint_states");
  ros::Time paused_stamp;
  ASSERT_TRUE(test::awaitPausedStart(&js, &paused_stamp));
  CpuHog hog(hog_on);
  ASSERT_EQ(hog.size(), hog_on ? 2u : 0u);
  constexpr size_t kPublishes = 300;  // 3 s of sim time at 100 Hz
  ASSERT_TRUE(test::runUnpausedFor(js, kPublishes + 2));

  // Offline: the node's own config, the controller's gains, the law at every publish.
  test::ControlledRun run;
  ASSERT_TRUE(test::readControlledRun(&run));
  const Config& config = run.config;
  const PdGains& gains = run.gains;
  const double setpoint = run.setpoint;
  SimDriver driver(config, {});
  // The paused state may be repeated (once a second) after the clear: not a stepped state.
  const std::vector<sensor_msgs::JointState> recorded = test::steppedMessages(js, paused_stamp);
  ASSERT_GE(recorded.size(), kPublishes);
  // The first message after unpausing is the first stepped state; the paused one was answered.
  const int ticks_per_publish = static_cast<int>(
      wholeStepsPerPeriod(config.simulation.physics_rate, config.simulation.publish_rate));
  size_t compared = 0;
  for (size_t k = 0; k < kPublishes; ++k) {
    const State& x = driver.simulator().state();
    driver.command(pdTorque(gains, setpoint, x.q1, x.u1));
    for (int i = 0; i < ticks_per_publish; ++i) ASSERT_TRUE(driver.step());
    const sensor_msgs::JointState& m = recorded[k];
    const Snapshot s = driver.snapshot();
    ASSERT_EQ(m.position.size(), 4u);
    for (int j = 0; j < 4; ++j) {
      EXPECT_EQ(m.position[j], s.joints.position[j]) << "publish " << k << " joint " << j;
      EXPECT_EQ(m.velocity[j], s.joints.velocity[j]) << "publish " << k << " joint " << j;
    }
    EXPECT_EQ(m.effort[0], s.joints.effort[0]) << "publish " << k;
    ++compared;
    if (::testing::Test::HasFailure()) break;
  }
  EXPECT_EQ(compared, kPublishes);
  // The controller did move the crank: a comparison of a mechanism at rest would prove little.
  EXPECT_GT(std::abs(recorded[kPublishes - 1].position[0] - config.initial_state.q1), 0.2);
}

}  // namespace
}  // namespace kane_sim

namespace kane_sim {
namespace {

// Nobody answers: each published state waits lockstep_timeout (0.05 s wall) and then the
// fallback zeroes the torque; /diagnostics counts the timeouts and says WARN.
TEST(LockstepFallback, WithoutAnswersEachStateWaitsThenTheFallbackApplies) {
  ros::NodeHandle nh;
  Recorder<MechanismState> state(nh, "mechanism_state");
  Recorder<diagnostic_msgs::DiagnosticArray> diagnostics(nh, "/diagnostics");
  ros::Publisher torque = nh.advertise<std_msgs::Float64>("torque_command", 10);
  ASSERT_TRUE(state.waitForCount(3, 20.0));
  ASSERT_TRUE(test::waitFor([&] { return torque.getNumSubscribers() > 0; }, 5.0));
  std_msgs::Float64 five;
  five.data = 5.0;
  torque.publish(five);  // a plain command: applied, but it answers no state
  const double t0 = state.last().sim_time;
  test::sleepWall(1.0);
  // ~1 publish period (10 ms of sim time) per 0.05 s of wall time: about 0.2 s, far from the
  // 1 s a free-running wall-clock sim would cover. Loose bounds: a loaded machine is slower.
  const double advanced = state.last().sim_time - t0;
  EXPECT_GT(advanced, 0.05);
  EXPECT_LT(advanced, 0.5);
  // The fallback zeroed the command after the first timeout following it.
  EXPECT_EQ(state.last().applied_torque, 0.0);
  ASSERT_TRUE(diagnostics.waitForCount(2, 5.0));
  bool warned = false;
  for (const auto& array : diagnostics.messages())
    for (const auto& status : array.status)
      for (const auto& kv : status.values)
        if (kv.key == "lockstep timeouts" && std::stod(kv.value) > 5)
          warned = status.level == diagnostic_msgs::DiagnosticStatus::WARN;
  EXPECT_TRUE(warned);

  // Hostile answers on the stamped topic: NaN, ±inf, 1e308 for the state in force. Refused or
  // clamped as on torque_command; the node runs on and publishes only finite numbers.
  ros::Publisher stamped = nh.advertise<TorqueCommandStamped>("torque_command_stamped", 10);
  ASSERT_TRUE(test::waitFor([&] { return stamped.getNumSubscribers() > 0; }, 5.0));
  for (const double hostile : {std::nan(""), HUGE_VAL, -HUGE_VAL, 1e308}) {
    TorqueCommandStamped answer;
    answer.header.stamp = state.last().header.stamp;
    answer.torque = hostile;
    stamped.publish(answer);
    test::sleepWall(0.1);
  }
  const double before = state.last().sim_time;
  test::sleepWall(0.5);
  EXPECT_GT(state.last().sim_time, before);
  for (const auto& m : state.messages()) {
    EXPECT_TRUE(std::isfinite(m.applied_torque));
    EXPECT_LE(std::abs(m.applied_torque), 50.0);
  }
}

}  // namespace
}  // namespace kane_sim

namespace kane_sim {
namespace {

// Lockstep from the first step (lockstep_start.test: not paused, the controller started beside
// the node): the initial state goes out again once the controller is connected, its answer
// drives the first step, and every state after follows the offline driver under the same law.
// (The first publish period once ran open-loop: the state at t = 0 went out before anyone
// listened, and the first step waited out the timeout with 0 N m.)
TEST(LockstepStart, TheControllersAnswerToTheInitialStateDrivesTheFirstStep) {
  ros::NodeHandle nh;
  Recorder<MechanismState> states(nh, "mechanism_state");
  ASSERT_TRUE(states.waitForCount(100, 30.0));
  test::ControlledRun run;
  ASSERT_TRUE(test::readControlledRun(&run));
  const Config& config = run.config;
  const std::vector<MechanismState> got = states.messages();
  SimDriver driver(config, {});
  const auto ticks_per_publish = static_cast<std::uint64_t>(
      wholeStepsPerPeriod(config.simulation.physics_rate, config.simulation.publish_rate));
  size_t compared = 0;
  for (const MechanismState& m : got) {
    const auto tick = static_cast<std::uint64_t>(std::llround(m.sim_time * 1000.0));
    ASSERT_EQ(tick % ticks_per_publish, 0u) << m.sim_time;
    while (driver.ticks() < tick) {
      const State& x = driver.simulator().state();
      driver.command(pdTorque(run.gains, run.setpoint, x.q1, x.u1));
      for (std::uint64_t i = 0; i < ticks_per_publish; ++i) ASSERT_TRUE(driver.step());
    }
    const State& x = driver.simulator().state();
    ASSERT_EQ(m.q[0], x.q1) << "t = " << m.sim_time;
    ASSERT_EQ(m.u[0], x.u1) << "t = " << m.sim_time;
    ++compared;
  }
  EXPECT_GE(compared, 100u);
}

}  // namespace
}  // namespace kane_sim
