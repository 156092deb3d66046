// reset, pause, unpause and step of a running sim (test/node/services.test).
#include <cmath>

#include <gtest/gtest.h>
#include <std_msgs/Float64.h>
#include <std_srvs/Empty.h>
#include <std_srvs/Trigger.h>

#include "kane_sim/MechanismState.h"
#include "node_test_utils.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

class Services : public test::SimNodeTest {};

using test::Recorder;

template <class S>
bool call(const std::string& name, S& srv) {
  if (!ros::service::waitForService(name, ros::Duration(10.0))) return false;
  return ros::service::call(name, srv);
}

TEST_F(Services, PauseFreezesSimTimeAndStepAdvancesOnePublishPeriod) {
  Recorder<MechanismState>& state = state_;
  ASSERT_TRUE(state.waitForCount(10, 15.0));
  std_srvs::Empty empty;
  ASSERT_TRUE(call("pause", empty));
  test::sleepWall(0.1);
  const double frozen = state.last().sim_time;
  state.clear();
  test::sleepWall(0.3);
  for (const auto& m : state.messages()) EXPECT_EQ(m.sim_time, frozen);
  EXPECT_GT(state.count(), 10u) << "wall-clock mode keeps publishing while paused";

  std_srvs::Trigger step;
  ASSERT_TRUE(call("step", step));
  EXPECT_TRUE(step.response.success) << step.response.message;
  ASSERT_TRUE(test::waitFor([&] { return state.last().sim_time > frozen; }, 2.0));
  EXPECT_NEAR(state.last().sim_time - frozen, 0.01, 1e-9);  // 10 steps of 1 ms

  ASSERT_TRUE(call("unpause", empty));
  test::sleepWall(0.3);
  EXPECT_GT(state.last().sim_time, frozen + 0.2);
  ASSERT_TRUE(call("step", step));
  EXPECT_FALSE(step.response.success);
  EXPECT_NE(step.response.message.find("not paused"), std::string::npos) << step.response.message;
}

TEST_F(Services, ResetRestoresTheInitialStateAndZeroesWork) {
  Recorder<MechanismState>& state = state_;
  test::send(torque_, 5.0);
  ASSERT_TRUE(
      test::waitFor([&] { return state.count() > 0 && state.last().motor_work != 0.0; }, 5.0));
  const double before = state.last().sim_time;
  std_srvs::Empty empty;
  ASSERT_TRUE(call("pause", empty));
  ASSERT_TRUE(call("reset", empty));
  test::sleepWall(0.1);
  const MechanismState m = state.last();
  const Config c = test::defaultConfig();
  EXPECT_EQ(m.q[0], c.initial_state.q1);
  EXPECT_EQ(m.q[1], c.initial_state.q2);
  EXPECT_EQ(m.u[0], c.initial_state.u1);
  EXPECT_EQ(m.u[1], c.initial_state.u2);
  EXPECT_EQ(m.motor_work, 0.0);
  EXPECT_EQ(m.applied_torque, 0.0);
  EXPECT_GE(m.sim_time, before) << "sim time never runs backwards";
  ASSERT_TRUE(call("unpause", empty));
}

}  // namespace
}  // namespace kane_sim
