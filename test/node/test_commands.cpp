// torque_command handling of a running sim (test/node/torque.test, test/node/commands.test).
#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Float64.h>

#include "../test_helpers.h"
#include "kane_sim/MechanismState.h"
#include "kane_sim/simulator.h"
#include "node_test_utils.h"

namespace kane_sim {
namespace {

using test::Recorder;

using test::send;

// A steady 10 N m for 0.5 s moves q1 by roughly ½ (τ / M11) t² ≈ 2 rad more than the unforced
// motion; demand 0.3 rad against the offline simulator at the same sim time.
TEST(Torque, PositiveTorqueRaisesQ1AndShowsInEffortAndState) {
  ros::NodeHandle nh;
  Recorder<MechanismState> state(nh, "mechanism_state");
  Recorder<sensor_msgs::JointState> js(nh, "joint_states");
  ros::Publisher torque = test::connectedPublisher<std_msgs::Float64>(nh, "torque_command");
  ASSERT_TRUE(state.waitForCount(1, 15.0));
  send(torque, 10.0);
  ASSERT_TRUE(test::waitFor([&] { return state.last().applied_torque == 10.0; }, 2.0));
  for (int i = 0; i < 5; ++i) {  // keep commanding, well inside the 0.5 s timeout
    test::sleepWall(0.1);
    send(torque, 10.0);
  }
  const MechanismState driven = state.last();
  EXPECT_EQ(driven.applied_torque, 10.0);
  EXPECT_EQ(driven.commanded_torque, 10.0);
  EXPECT_EQ(js.last().effort[0], 10.0);

  Simulator unforced(test::defaultConfig());
  while (unforced.time() < driven.sim_time - 1e-9) unforced.step();
  EXPECT_GT(driven.q[0], unforced.state().q1 + 0.3)
      << "driven " << driven.q[0] << " unforced " << unforced.state().q1
      << " at t = " << driven.sim_time;
}

TEST(Commands, NonFiniteCommandIsIgnored) {
  ros::NodeHandle nh;
  Recorder<MechanismState> state(nh, "mechanism_state");
  ros::Publisher torque = test::connectedPublisher<std_msgs::Float64>(nh, "torque_command");
  ASSERT_TRUE(state.waitForCount(1, 15.0));
  send(torque, 5.0);
  ASSERT_TRUE(test::waitFor([&] { return state.last().applied_torque == 5.0; }, 2.0));
  state.clear();
  for (double bad : {std::nan(""), std::numeric_limits<double>::infinity(),
                     -std::numeric_limits<double>::infinity()})
    send(torque, bad);
  test::sleepWall(0.2);  // < command.timeout (0.5 s)
  const auto msgs = state.messages();
  ASSERT_GT(msgs.size(), 5u);
  for (const auto& m : msgs) {
    EXPECT_EQ(m.applied_torque, 5.0);
    EXPECT_EQ(m.commanded_torque, 5.0);
    EXPECT_TRUE(std::isfinite(m.q[0]) && std::isfinite(m.u[0]) && std::isfinite(m.total_energy));
  }
}

TEST(Commands, OverLimitCommandIsClamped) {
  ros::NodeHandle nh;
  Recorder<MechanismState> state(nh, "mechanism_state");
  ros::Publisher torque = test::connectedPublisher<std_msgs::Float64>(nh, "torque_command");
  ASSERT_TRUE(state.waitForCount(1, 15.0));
  send(torque, 80.0);  // command.torque_limit is 20 in commands.yaml
  ASSERT_TRUE(test::waitFor([&] { return state.last().commanded_torque == 80.0; }, 2.0));
  EXPECT_EQ(state.last().applied_torque, 20.0);
  send(torque, -1e300);
  ASSERT_TRUE(test::waitFor([&] { return state.last().commanded_torque == -1e300; }, 2.0));
  EXPECT_EQ(state.last().applied_torque, -20.0);
}

TEST(Commands, TimeoutZeroesTheTorqueAndNextCommandResumes) {
  ros::NodeHandle nh;
  Recorder<MechanismState> state(nh, "mechanism_state");
  ros::Publisher torque = test::connectedPublisher<std_msgs::Float64>(nh, "torque_command");
  ASSERT_TRUE(state.waitForCount(1, 15.0));
  send(torque, 3.0);
  ASSERT_TRUE(test::waitFor([&] { return state.last().applied_torque == 3.0; }, 2.0));
  const double on_at = state.last().sim_time;
  ASSERT_TRUE(test::waitFor([&] { return state.last().applied_torque == 0.0; }, 3.0));
  // Zeroed after command.timeout (0.5 s sim time), not before; one publish period of slack.
  EXPECT_GE(state.last().sim_time - on_at, 0.5 - 0.011);
  EXPECT_EQ(state.last().commanded_torque, 3.0);
  send(torque, 4.0);
  ASSERT_TRUE(test::waitFor([&] { return state.last().applied_torque == 4.0; }, 2.0));
}

}  // namespace
}  // namespace kane_sim
