// reset, pause, unpause and step of a running sim (test/node/services.test).
#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Float64.h>
#include <std_srvs/Empty.h>
#include <std_srvs/Trigger.h>

#include "kane_sim/MechanismState.h"
#include "kane_sim/SetState.h"
#include "kane_sim/StepWithCommand.h"
#include "kane_sim/ros/param_yaml.h"
#include "kane_sim/sim/config_check.h"
#include "kane_sim/sim/sim_driver.h"
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
  ASSERT_TRUE(call("kane_sim/pause", empty));
  test::sleepWall(0.1);
  const double frozen = state.last().sim_time;
  state.clear();
  test::sleepWall(0.3);
  for (const auto& m : state.messages()) EXPECT_EQ(m.sim_time, frozen);
  EXPECT_GT(state.count(), 10u) << "wall-clock mode keeps publishing while paused";

  std_srvs::Trigger step;
  ASSERT_TRUE(call("kane_sim/step", step));
  EXPECT_TRUE(step.response.success) << step.response.message;
  ASSERT_TRUE(test::waitFor([&] { return state.last().sim_time > frozen; }, 2.0));
  EXPECT_NEAR(state.last().sim_time - frozen, 0.01, 1e-9);  // 10 steps of 1 ms

  ASSERT_TRUE(call("kane_sim/unpause", empty));
  test::sleepWall(0.3);
  EXPECT_GT(state.last().sim_time, frozen + 0.2);
  ASSERT_TRUE(call("kane_sim/step", step));
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
  ASSERT_TRUE(call("kane_sim/pause", empty));
  ASSERT_TRUE(call("kane_sim/reset", empty));
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
  ASSERT_TRUE(call("kane_sim/unpause", empty));
}

// set_state puts the mechanism where a controller test wants it: the next published state is
// that state (paused, so nothing moves on), motor work restarts from 0, and stepping on from it
// follows the same physics as the offline driver started there.
TEST_F(Services, SetStatePutsTheMechanismIntoTheGivenState) {
  std_srvs::Empty empty;
  ASSERT_TRUE(call("kane_sim/pause", empty));
  SetState set;
  set.request.q1 = -0.4;
  set.request.q2 = 1.3;
  set.request.u1 = 2.0;
  set.request.u2 = -0.5;
  ASSERT_TRUE(call("kane_sim/set_state", set));
  EXPECT_TRUE(set.response.success) << set.response.message;
  ASSERT_TRUE(test::waitFor([&] { return state_.last().q[0] == -0.4; }, 2.0));
  const MechanismState m = state_.last();
  EXPECT_EQ(m.q[1], 1.3);
  EXPECT_EQ(m.u[0], 2.0);
  EXPECT_EQ(m.u[1], -0.5);
  EXPECT_EQ(m.motor_work, 0.0);
  // The spring keeps its rest length: elongation from the config's initial state.
  const Config c = test::defaultConfig();
  const MechanismModel model = mechanismModel(c);
  EXPECT_NEAR(m.spring_elongation, model.springElongation(model.geometry(-0.4, 1.3)), 1e-15);
  // u' at that state is the model's (no torque commanded in this test).
  const SpeedVector u_dot = model.accelerations(State{-0.4, 1.3, 2.0, -0.5}, m.applied_torque);
  EXPECT_NEAR(m.u_dot[0], u_dot[0], 1e-12 * (1 + std::abs(u_dot[0])));
  EXPECT_NEAR(m.u_dot[1], u_dot[1], 1e-12 * (1 + std::abs(u_dot[1])));
  ASSERT_TRUE(call("kane_sim/unpause", empty));
}

TEST_F(Services, SetStateRefusesNonFiniteValuesAndKeepsTheState) {
  std_srvs::Empty empty;
  ASSERT_TRUE(call("kane_sim/pause", empty));
  test::sleepWall(0.1);
  const MechanismState before = state_.last();
  SetState set;
  set.request.q1 = 0.1;
  set.request.q2 = 1.0;
  set.request.u1 = std::nan("");
  set.request.u2 = 0.0;
  ASSERT_TRUE(call("kane_sim/set_state", set));
  EXPECT_FALSE(set.response.success);
  EXPECT_NE(set.response.message.find("u1"), std::string::npos) << set.response.message;
  EXPECT_NE(set.response.message.find("not finite"), std::string::npos) << set.response.message;
  set.request.u1 = 0.0;
  set.request.q2 = std::numeric_limits<double>::infinity();
  ASSERT_TRUE(call("kane_sim/set_state", set));
  EXPECT_FALSE(set.response.success);
  EXPECT_NE(set.response.message.find("q2"), std::string::npos) << set.response.message;
  test::sleepWall(0.1);
  EXPECT_EQ(state_.last().q[0], before.q[0]);
  EXPECT_EQ(state_.last().q[1], before.q[1]);
  ASSERT_TRUE(call("kane_sim/unpause", empty));
}

// The repros of the first defect of "nothing a user can set makes it lie": u1 = 1e5 rad/s and
// q1 = 1e308 were accepted and put inf/NaN on mechanism_state within 2 ms (joint_states
// velocity 1.4e223). Refused now, naming why; and nothing non-finite is published meanwhile.
TEST_F(Services, SetStateRefusesStatesThatCannotBeSimulated) {
  test::Recorder<sensor_msgs::JointState> joints(nh_, "joint_states");
  const size_t from = state_.count();
  const struct {
    double q1, q2, u1, u2;
    const char* says;
  } refused[] = {{0.0, 1.2, 100000.0, 0.0, "more than 1 rad per rk4 step"},
                 {1e308, 1.2, 0.0, 0.0, "q1 = 1e+308 rad is beyond"},
                 {0.5, 1e5, 0.0, 0.0, "too stiff for rk4"}};
  for (const auto& r : refused) {
    SetState set;
    set.request.q1 = r.q1;
    set.request.q2 = r.q2;
    set.request.u1 = r.u1;
    set.request.u2 = r.u2;
    ASSERT_TRUE(call("kane_sim/set_state", set));
    EXPECT_FALSE(set.response.success) << r.says;
    EXPECT_NE(set.response.message.find(r.says), std::string::npos) << set.response.message;
  }
  ASSERT_TRUE(state_.waitForCount(from + 30, 5.0));
  const auto states = state_.messages();
  for (size_t i = from; i < states.size(); ++i) ASSERT_TRUE(test::allFinite(states[i])) << i;
  for (const auto& j : joints.messages())
    for (size_t k = 0; k < j.position.size(); ++k)
      ASSERT_TRUE(std::isfinite(j.position[k]) && std::isfinite(j.velocity[k]) &&
                  std::isfinite(j.effort[k]));
}

// spring_at_rest: slider 4 placed where the spring is unstretched for the given q1 (the example
// of doc/reference/ros_api.md {q1: 1.0, q2: 1.2} stretched it 0.36 m and crossed the sliders in
// 0.15 s).
TEST_F(Services, SetStateCanPutSlider4AtTheSpringsRestLength) {
  std_srvs::Empty empty;
  ASSERT_TRUE(call("kane_sim/pause", empty));
  SetState set;
  set.request.q1 = 1.0;
  set.request.q2 = 123.0;  // ignored
  set.request.spring_at_rest = true;
  ASSERT_TRUE(call("kane_sim/set_state", set));
  ASSERT_TRUE(set.response.success) << set.response.message;
  ASSERT_TRUE(test::waitFor([&] { return state_.last().q[0] == 1.0; }, 2.0));
  const MechanismState m = state_.last();
  const MechanismModel model = mechanismModel(test::defaultConfig());
  EXPECT_NEAR(m.q[1], 4 * 0.25 * std::cos(1.0) + model.springRestLength(), 1e-15);
  EXPECT_NEAR(m.spring_elongation, 0.0, 1e-15);
  EXPECT_NEAR(model.springRestLength(), 0.3, 1e-12);  // config: slider 4 0.3 m below slider 3
  ASSERT_TRUE(call("kane_sim/unpause", empty));
}

// One round trip: torque and steps in, the state after them out; exactly what the ROS-free
// driver computes from the same state with the same command (one stepping path). Refused while
// running, and for hostile values, with nothing changed.
TEST_F(Services, StepWithCommandAdvancesAPausedSimulationByTheStepsAsked) {
  Recorder<MechanismState>& state = state_;
  ASSERT_TRUE(state.waitForCount(5, 15.0));
  StepWithCommand step;
  step.request.torque = 3.0;
  step.request.steps = 200;
  ASSERT_TRUE(call("kane_sim/step_with_command", step));
  EXPECT_FALSE(step.response.success);
  EXPECT_NE(step.response.message.find("not paused"), std::string::npos) << step.response.message;

  std_srvs::Empty empty;
  ASSERT_TRUE(call("kane_sim/pause", empty));
  SetState set;
  set.request.q1 = 0.5;
  set.request.spring_at_rest = true;
  ASSERT_TRUE(call("kane_sim/set_state", set));
  ASSERT_TRUE(set.response.success) << set.response.message;
  test::sleepWall(0.1);
  const double t0 = state.last().sim_time;
  const MechanismState& last = state.last();
  const State x0{last.q[0], last.q[1], last.u[0], last.u[1]};

  // Hostile requests: refused, nothing moves.
  for (const auto& [torque, steps] :
       std::vector<std::pair<double, std::uint32_t>>{{std::nan(""), 10},
                                                     {std::numeric_limits<double>::infinity(), 10},
                                                     {1.0, 0},
                                                     {1.0, 4000000000u}}) {
    StepWithCommand bad;
    bad.request.torque = torque;
    bad.request.steps = steps;
    ASSERT_TRUE(call("kane_sim/step_with_command", bad));
    EXPECT_FALSE(bad.response.success) << torque << " " << steps;
    EXPECT_NE(bad.response.message.find("nothing changed"), std::string::npos)
        << bad.response.message;
  }
  test::sleepWall(0.1);
  EXPECT_EQ(state.last().sim_time, t0);

  ASSERT_TRUE(call("kane_sim/step_with_command", step));
  ASSERT_TRUE(step.response.success) << step.response.message;
  EXPECT_NEAR(step.response.time - t0, 0.2, 1e-9);  // 200 steps of 1 ms

  // The same from the ROS-free driver: the node's config (its parameter namespace), started at
  // the state set above, the command once, 200 steps.
  XmlRpc::XmlRpcValue params;
  ASSERT_TRUE(ros::param::get("/kane_sim", params));
  const Config config = loadSimulationConfig(yamlFromXmlRpc(params)).config;
  SimDriver driver(config, {});
  ASSERT_TRUE(driver.setState(x0).ok);  // as set_state: the config's spring rest length kept
  driver.command(3.0);
  for (int i = 0; i < 200; ++i) ASSERT_TRUE(driver.step());
  EXPECT_EQ(step.response.q1, driver.simulator().state().q1);
  EXPECT_EQ(step.response.u1, driver.simulator().state().u1);
  EXPECT_EQ(step.response.q2, driver.simulator().state().q2);
  EXPECT_EQ(step.response.applied_torque, 3.0);

  // Beyond the torque limit: clamped, and said.
  step.request.torque = 1e6;
  step.request.steps = 1;
  ASSERT_TRUE(call("kane_sim/step_with_command", step));
  EXPECT_TRUE(step.response.success);
  EXPECT_NE(step.response.message.find("clamped"), std::string::npos) << step.response.message;
  EXPECT_EQ(step.response.applied_torque, 50.0);
  ASSERT_TRUE(call("kane_sim/unpause", empty));
}

}  // namespace
}  // namespace kane_sim
