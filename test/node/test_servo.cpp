// command.mode position through the node (test/node/servo.test): the setpoint topic, the servo's
// state, the effort joint_states reports and the refusals, as a user drives them.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <rosgraph_msgs/Log.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Float64.h>

#include "kane_sim/ServoState.h"
#include "node_test_utils.h"

namespace kane_sim {
namespace {

class Servo : public test::SimNodeTest {};

using test::Recorder;
using test::send;

TEST_F(Servo, SetpointsMoveAndHoldTheCrankAndTheStateReportsIt) {
  Recorder<rosgraph_msgs::Log> rosout(nh_, "/rosout");
  Recorder<ServoState> servo(nh_, "servo_state");
  Recorder<sensor_msgs::JointState> js(nh_, "joint_states");
  ros::Publisher setpoint = test::connectedPublisher<std_msgs::Float64>(nh_, "servo_setpoint");
  ASSERT_TRUE(servo.waitForCount(1, 5.0));
  EXPECT_EQ(servo.last().mode, "position");
  // At start the servo holds the initial angle (π/6) without any command, past the timeout.
  test::sleepWall(1.0);
  EXPECT_NEAR(state_.last().q[0], M_PI / 6, 0.01);
  send(setpoint, 1.2);
  ASSERT_TRUE(
      waitForState([](const MechanismState& m) { return std::abs(m.q[0] - 1.2) < 0.002; }, 5.0))
      << state_.last().q[0];
  test::sleepWall(3.0);  // the integral takes the last of the error (ki 100)
  const ServoState held = servo.last();
  EXPECT_EQ(held.setpoint, 1.2);
  EXPECT_NEAR(held.error, 0.0, 0.001);
  EXPECT_FALSE(held.saturated);
  EXPECT_NEAR(held.output, held.p + held.i + held.d + held.feedforward, 1e-9);
  EXPECT_NE(held.feedforward, 0.0);
  EXPECT_EQ(held.command, held.output);
  // The effort in joint_states is the delivered torque, as mechanism_state's applied torque.
  ASSERT_TRUE(
      test::waitFor([&] { return js.last().header.stamp == state_.last().header.stamp; }, 1.0));
  EXPECT_EQ(js.last().effort[0], state_.last().applied_torque);

  // A far step saturates and says so; the drive gets the limit (50 N m).
  send(setpoint, 3.5);
  ASSERT_TRUE(test::waitFor([&] { return servo.last().saturated; }, 2.0));
  EXPECT_EQ(std::abs(servo.last().command), 50.0);
  EXPECT_GT(std::abs(servo.last().output), 50.0);

  // Hostile setpoints and a torque_command: refused, the setpoint kept, every number finite.
  for (double bad : {std::nan(""), std::numeric_limits<double>::infinity(), -1e308})
    send(setpoint, bad);
  test::sleepWall(1.1);  // one warning per second per kind: the next refusal is heard too
  send(torque_, 20.0);
  test::sleepWall(0.5);
  const auto logged = [&rosout](const std::string& text) {
    for (const auto& log : rosout.messages())
      if (log.msg.find(text) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(logged("servo_setpoint nan rad is not finite; the last setpoint is kept"));
  EXPECT_TRUE(logged("command.mode is position: torque_command 20 N m is ignored"));
  EXPECT_EQ(servo.last().setpoint, 3.5);
  for (const ServoState& s : servo.messages())
    ASSERT_TRUE(std::isfinite(s.output) && std::isfinite(s.i) && std::isfinite(s.error));
  EXPECT_TRUE(test::allFinite(state_.last()));
}

}  // namespace
}  // namespace kane_sim
