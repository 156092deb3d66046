// The example PD controller driving the sim (test/node/controller.test).
#include <cmath>

#include <gtest/gtest.h>
#include <std_msgs/Float64.h>

#include "kane_sim/MechanismState.h"
#include "node_test_utils.h"

namespace kane_sim {
namespace {

using test::Recorder;

// Tolerance 0.05 rad: a PD's steady error is the holding moment over kp, here at most
// ~(14.7 N m gravity + spring) / 500 N m/rad ≈ 0.03 rad (test_pd_law checks it offline).
TEST(Controller, HoldsTheCrankAtItsSetpointAndFollowsTheSetpointTopic) {
  ros::NodeHandle nh;
  Recorder<MechanismState> state(nh, "mechanism_state");
  ASSERT_TRUE(state.waitForCount(1, 15.0));
  test::sleepWall(3.0);
  EXPECT_NEAR(state.last().q[0], 1.0, 0.05);

  ros::Publisher setpoint = test::connectedPublisher<std_msgs::Float64>(nh, "setpoint");
  test::send(setpoint, -0.5);
  test::sleepWall(3.0);
  EXPECT_NEAR(state.last().q[0], -0.5, 0.05);
  EXPECT_NEAR(state.last().u[0], 0.0, 0.5);
}

}  // namespace
}  // namespace kane_sim
