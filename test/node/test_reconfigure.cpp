// Runtime reconfiguration through dynamic_reconfigure (test/node/reconfigure.test): the clamp
// follows torque_limit at once, a physical parameter changes u' from the next step and its
// energy jump lands in parameter_energy, a value the config loader refuses is reverted, and
// `rosrun dynamic_reconfigure dynparam set` works as doc/guide/node.md says.
#include <sched.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

#include <gtest/gtest.h>
#include <rosgraph_msgs/Log.h>
#include <std_srvs/Empty.h>
#include <tf2_msgs/TFMessage.h>

#include "kane_sim/MechanismState.h"
#include "node_test_utils.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

// Whether a thread of the kane_sim_node on this test's master runs SCHED_FIFO (found in /proc by
// its name and its ROS_MASTER_URI: other tests' nodes may run beside it).
bool nodeRunsSchedFifo() {
  const char* master = std::getenv("ROS_MASTER_URI");
  if (!master) return false;
  const std::string want = std::string("ROS_MASTER_URI=") + master;
  for (const auto& proc : std::filesystem::directory_iterator("/proc")) {
    std::string comm;
    std::getline(std::ifstream(proc.path() / "comm"), comm);
    if (comm != "kane_sim_node") continue;
    std::ifstream environ(proc.path() / "environ");
    bool ours = false;
    for (std::string var; std::getline(environ, var, '\0');) ours |= var == want;
    if (!ours) continue;
    std::error_code error;
    for (const auto& task : std::filesystem::directory_iterator(proc.path() / "task", error))
      if (sched_getscheduler(std::stoi(task.path().filename())) == SCHED_FIFO) return true;
  }
  return false;
}

class Reconfigure : public test::SimNodeTest {
 protected:
  double set(const std::string& name, double value) { return test::reconfigure(name, value); }
};

// /tf_static is sent once (latched): a reconfiguration rewrites robot_description, not the
// static tf (it was re-sent at every reconfiguration).
TEST_F(Reconfigure, TheStaticTfIsNotSentAgain) {
  test::Recorder<tf2_msgs::TFMessage> statics(nh_, "/tf_static");
  ASSERT_TRUE(test::waitFor([&] { return statics.messages().size() == 1; }, 5.0))
      << "the latched /tf_static did not arrive";
  EXPECT_EQ(set("slider4_mass", 0.9), 0.9);
  EXPECT_EQ(set("slider4_mass", 0.8), 0.8);
  test::sleepWall(0.5);
  EXPECT_EQ(statics.messages().size(), 1u);
}

TEST_F(Reconfigure, TorqueLimitClampsTheCommandInForce) {
  test::send(torque_, 10.0);
  ASSERT_TRUE(waitForState([](const MechanismState& m) { return m.applied_torque == 10.0; }, 5));
  EXPECT_EQ(set("torque_limit", 4.0), 4.0);
  ASSERT_TRUE(waitForState([](const MechanismState& m) { return m.applied_torque == 4.0; }, 5))
      << "applied " << state_.last().applied_torque;
  EXPECT_EQ(state_.last().commanded_torque, 10.0);
  // Through the command-line tool, as a user would (PATH's python3 must be Debian's).
  const test::CommandResult cli = test::runCommand(
      "PATH=/usr/bin:$PATH rosrun dynamic_reconfigure dynparam set /kane_sim torque_limit 2.5");
  EXPECT_EQ(cli.exit_code, 0) << cli.out << cli.err;
  EXPECT_TRUE(waitForState([](const MechanismState& m) { return m.applied_torque == 2.5; }, 5))
      << "applied " << state_.last().applied_torque;
  set("torque_limit", 50.0);
  test::send(torque_, 0.0);
}

// One name per parameter: after a change the parameter server holds the value in force under
// the config's own name (and no flat duplicate), so the recipe of doc/guide/node.md `rosparam get
// /kane_sim > now.yaml; analyze --config now.yaml` analyses the mechanism in force, without a
// warning.
TEST_F(Reconfigure, TheParameterServerHoldsTheConfigInForceUnderItsOwnNames) {
  ASSERT_EQ(set("spring_stiffness", 400.0), 400.0);
  double k = 0.0;
  EXPECT_TRUE(ros::param::get("/kane_sim/mechanism/spring_stiffness", k));
  EXPECT_EQ(k, 400.0);
  EXPECT_FALSE(ros::param::has("/kane_sim/spring_stiffness")) << "a flat duplicate";
  EXPECT_FALSE(ros::param::has("/kane_sim/torque_limit")) << "a flat duplicate";
  const test::CommandResult recipe = test::runCommand(
      "PATH=/usr/bin:$PATH; f=$(mktemp --suffix .yaml) && rosparam get /kane_sim > $f && "
      "rosrun kane_sim analyze --config $f --json; rc=$?; rm -f $f; exit $rc");
  ASSERT_EQ(recipe.exit_code, 0) << recipe.out << recipe.err;
  EXPECT_EQ(recipe.err.find("unknown"), std::string::npos) << recipe.err;
  // The slider mode at q1 = 0 is sqrt(k / M2) = sqrt(400 / 0.8) rad/s: the new mechanism's.
  const double expected_hz = std::sqrt(400.0 / 0.8) / (2 * M_PI);
  EXPECT_NE(recipe.out.find("\"natural_frequencies_hz\""), std::string::npos) << recipe.out;
  const size_t at = recipe.out.find("natural_frequencies_hz");
  const std::string list = recipe.out.substr(at, recipe.out.find(']', at) - at);
  const double second = std::stod(list.substr(list.find(',') + 1));
  EXPECT_NEAR(second, expected_hz, 1e-6) << list;
  ASSERT_EQ(set("spring_stiffness", 200.0), 200.0);
}

// The .cfg's ranges no longer clamp before the loader sees a value: out-of-rule values are
// refused by the loader's rules and messages (not turned into the range's end: torque_limit -50
// became 0, the motor off; crank_damping -5 became 0; gravity inf became 100; rod_mass -1 was
// refused as "got 0"); a value beyond a GUI bound that the loader accepts is taken as it is.
TEST_F(Reconfigure, ValuesReachTheLoaderUnclamped) {
  test::Recorder<rosgraph_msgs::Log> log(nh_, "/rosout");
  test::sleepWall(0.5);
  EXPECT_EQ(set("torque_limit", -50.0), 50.0);
  EXPECT_EQ(set("crank_damping", -5.0), 0.0);
  EXPECT_EQ(set("spring_damping", NAN), 0.0);
  EXPECT_EQ(set("gravity", INFINITY), 9.81);
  EXPECT_EQ(set("rod_mass", -1.0), 1.0);
  EXPECT_EQ(set("gravity", 150.0), 150.0) << "beyond the slider's 100 but a valid config";
  EXPECT_EQ(set("gravity", 9.81), 9.81);
  const char* messages[] = {"config key 'command.torque_limit' must be >= 0, got -50",
                            "config key 'damping.crank_joint' must be >= 0, got -5",
                            "config key 'damping.spring' must be finite, got",
                            "config key 'mechanism.gravity' must be finite, got '.inf'",
                            "config key 'mechanism.rod_mass' must be > 0, got -1"};
  for (const char* text : messages)
    EXPECT_TRUE(test::waitFor(
        [&] {
          for (const auto& m : log.messages())
            if (m.msg.find(text) != std::string::npos) return true;
          return false;
        },
        5.0))
        << "no log line with: " << text;
}

// The damper beside the spring, then slider 4's friction, switched on at run time: each takes
// power out of the motion (its own entry of load_powers, <= 0), booked in D.
TEST_F(Reconfigure, TheSpringDamperAndFrictionTakePowerOnceSwitchedOn) {
  for (const auto& [name, load] :
       {std::pair<std::string, std::string>{"spring_damping", "spring_damper"},
        {"slider4_friction", "slider4_friction"}}) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(
        waitForState([&](const MechanismState& m) { return test::loadPower(m, load) == 0.0; }, 5));
    const double before = state_.last().dissipated_energy;
    EXPECT_EQ(set(name, 3.0), 3.0);
    ASSERT_TRUE(
        waitForState([&](const MechanismState& m) { return test::loadPower(m, load) < 0.0; }, 5))
        << "the sliders move in the free swing";
    EXPECT_TRUE(
        waitForState([&](const MechanismState& m) { return m.dissipated_energy > before; }, 5));
    EXPECT_EQ(set(name, 0.0), 0.0);
  }
}

// Gravity 0 and a heavier slider 4 at rest: slider 4's u2' becomes the spring's force / M2
// alone, and the jump of the total energy is booked in parameter_energy.
TEST_F(Reconfigure, PhysicalParametersApplyFromTheNextStepWithTheirEnergyBooked) {
  std_srvs::Empty empty;
  ASSERT_TRUE(ros::service::call("kane_sim/pause", empty));
  test::sleepWall(0.1);
  const MechanismState before = state_.last();
  EXPECT_EQ(set("gravity", 0.0), 0.0);
  EXPECT_EQ(set("slider4_mass", 1.6), 1.6);
  ASSERT_TRUE(ros::service::call("kane_sim/unpause", empty));
  const std::uint32_t changes = before.parameter_changes + 2;  // counted since start
  ASSERT_TRUE(
      waitForState([&](const MechanismState& m) { return m.parameter_changes == changes; }, 5));
  ASSERT_TRUE(ros::service::call("kane_sim/pause", empty));
  test::sleepWall(0.1);
  const MechanismState m = state_.last();
  // F2 = M2 g + k e with g = 0: u2' = k e / M2 (k = 200 N/m, e > 0 compressed pushes C down).
  EXPECT_NEAR(m.u_dot[1], 200.0 * m.spring_elongation / 1.6, 1e-9);
  // The gravitational energy went to 0 at the change: that is the booked jump (plus the
  // kinetic change of M2 0.8 -> 1.6 at u2).
  EXPECT_NEAR(m.gravitational_energy, 0.0, 1e-12);
  EXPECT_NE(m.parameter_energy, 0.0);
  const double ledger_before = before.total_energy - before.motor_work - before.parameter_energy;
  const double ledger_after = m.total_energy - m.motor_work - m.parameter_energy;
  EXPECT_NEAR(ledger_after, ledger_before, 1e-5) << "E - W - parameter_energy is conserved";
  ASSERT_TRUE(ros::service::call("kane_sim/unpause", empty));
}

// The loader's rules: rod_mass 0 is refused (must be > 0) and reverted; the node goes on.
// reconfigure.yaml asks for simulation.realtime_priority; as root the loop gets SCHED_FIFO, and
// real_time_factor 0 would then busy-spin a core at real-time priority (a 5 ms sleep's p99 went
// 1.1 -> 5.8 ms beside it): refused at run time, other factors taken.
TEST_F(Reconfigure, RealTimeFactorZeroIsRefusedUnderSchedFifo) {
  if (!nodeRunsSchedFifo()) {
    ASSERT_NE(geteuid(), 0u) << "root, yet the node's loop did not get SCHED_FIFO";
    GTEST_SKIP() << "no privileges for SCHED_FIFO: nothing to refuse";
  }
  EXPECT_EQ(set("real_time_factor", 0.0), 1.0);
  EXPECT_EQ(set("real_time_factor", 2.0), 2.0);
  EXPECT_EQ(set("real_time_factor", 1.0), 1.0);
}

TEST_F(Reconfigure, RefusedValuesAreRevertedAndNamed) {
  EXPECT_EQ(set("rod_mass", 0.0), 1.0);
  EXPECT_EQ(set("real_time_factor", 0.0001), 1.0) << "0 or >= 1e-3";
  const size_t n = state_.count();
  EXPECT_TRUE(state_.waitForCount(n + 10, 5.0)) << "the node keeps running";
}

}  // namespace
}  // namespace kane_sim
