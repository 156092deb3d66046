// The example PD controller driving the sim (test/node/controller.test).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Float64.h>

#include "controlled_run.h"
#include "kane_sim/MechanismState.h"
#include "kane_sim/design/lqr_file.h"
#include "kane_sim/sim/sim_driver.h"
#include "kane_sim/sim/torque_profile.h"
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

// The LQR law of config/upright_lqr.yaml (design lqr --q1 pi, sampled at the 100 Hz readings)
// brings the crank from 0.05 rad off back upright: within 1e-3 rad of pi after 10 s of sim time
// (its closed-loop poles, -13.9 and -10.6 1/s, leave e^-100 of the start). Lockstep: the node's
// trajectory is the ROS-free driver's under the same law (the file's, sampled at every publish,
// clamped to the controller's torque_limit), bit for bit: one truth for the law's doors.
TEST(ControllerLaw, HoldsTheCrankUprightAsTheOfflineDriverDoes) {
  ros::NodeHandle nh;
  Recorder<sensor_msgs::JointState> js(nh, "joint_states");
  ros::Time paused_stamp;
  ASSERT_TRUE(test::awaitPausedStart(&js, &paused_stamp));
  constexpr size_t kPublishes = 1000;  // 10 s of sim time at 100 Hz
  // A bound, not an expectation: ~1 s here, longer on one core beside a CPU hog.
  ASSERT_TRUE(test::runUnpausedFor(js, kPublishes + 2, 500.0));

  XmlRpc::XmlRpcValue params;
  ASSERT_TRUE(ros::param::get("/kane_sim", params));
  const Config config = loadSimulationConfig(yamlFromXmlRpc(params)).config;
  std::string law_file;
  double torque_limit = 0.0;
  ASSERT_TRUE(ros::param::get("/pd_controller/law", law_file));
  ASSERT_TRUE(ros::param::get("/pd_controller/torque_limit", torque_limit));
  const StateFeedback law = readStateFeedbackFile(law_file);
  SimDriver driver(config, {});
  const std::vector<sensor_msgs::JointState> recorded = test::steppedMessages(js, paused_stamp);
  ASSERT_GE(recorded.size(), kPublishes);
  const int ticks_per_publish = static_cast<int>(
      wholeStepsPerPeriod(config.simulation.physics_rate, config.simulation.publish_rate));
  for (size_t k = 0; k < kPublishes; ++k) {
    driver.command(
        std::clamp(law.command(driver.simulator().state()), -torque_limit, torque_limit));
    ASSERT_TRUE(test::stepsAsPublished(&driver, ticks_per_publish, recorded[k], k));
  }
  const sensor_msgs::JointState& last = recorded[kPublishes - 1];
  EXPECT_NEAR(std::remainder(last.position[0] - M_PI, 2 * M_PI), 0.0, 1e-3);
  EXPECT_NEAR(last.velocity[0], 0.0, 1e-2);
}

// ~setpoint_table (test/node/controller_table.csv) in lockstep: the table's t is measured from
// the controller's first reading (the paused initial state, answered with ~setpoint 0.2 before
// the table's first row at 0.255 s), each row held until the next. The node's trajectory is the
// ROS-free driver's under the PD law with the table's setpoint at each publish, bit for bit, and
// the crank reaches each row's setpoint in turn.
TEST(ControllerTable, ThePdFollowsItsSetpointTableAsTheOfflineDriverDoes) {
  ros::NodeHandle nh;
  Recorder<sensor_msgs::JointState> js(nh, "joint_states");
  ros::Time paused_stamp;
  ASSERT_TRUE(test::awaitPausedStart(&js, &paused_stamp));
  constexpr size_t kPublishes = 400;  // 4 s of sim time at 100 Hz: every row and past the last
  // A bound, not an expectation: ~1 s here, longer on one core beside a CPU hog.
  ASSERT_TRUE(test::runUnpausedFor(js, kPublishes + 2, 500.0));

  test::ControlledRun run;
  ASSERT_TRUE(test::readControlledRun(&run));
  std::string table_file;
  ASSERT_TRUE(ros::param::get("/pd_controller/setpoint_table", table_file));
  const TorqueProfile table = TorqueProfile::fromCsvFile(table_file);
  const double first_row = table.parts().points.front().first;
  SimDriver driver(run.config, {});
  const std::vector<sensor_msgs::JointState> recorded = test::steppedMessages(js, paused_stamp);
  ASSERT_GE(recorded.size(), kPublishes);
  const int ticks_per_publish = static_cast<int>(
      wholeStepsPerPeriod(run.config.simulation.physics_rate, run.config.simulation.publish_rate));
  double setpoint = run.setpoint;
  for (size_t k = 0; k < kPublishes; ++k) {
    // The state answered: the paused one, then the k-th stepped one, at its stamp.
    const ros::Time stamp = k == 0 ? paused_stamp : recorded[k - 1].header.stamp;
    const double t = (stamp - paused_stamp).toSec();
    if (t >= first_row) setpoint = table.at(t);
    const Snapshot before = driver.snapshot();
    driver.command(
        pdTorque(run.gains, setpoint, before.joints.position[0], before.joints.velocity[0]));
    ASSERT_TRUE(test::stepsAsPublished(&driver, ticks_per_publish, recorded[k], k));
  }
  // Each row reached in turn before the next: within 0.1 rad, the PD's steady error (the holding
  // moment over kp: 0.055 rad at -0.4 rad, where the spring is stretched furthest) and then some;
  // the rows are 0.4 rad or more apart.
  const auto q1_at = [&](double t) { return recorded[std::lround(t * 100.0) - 1].position[0]; };
  EXPECT_NEAR(q1_at(1.5), 1.2, 0.1);
  EXPECT_NEAR(q1_at(2.7), -0.4, 0.1);
  EXPECT_NEAR(q1_at(4.0), 0.8, 0.1);
}

}  // namespace
}  // namespace kane_sim
