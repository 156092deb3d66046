// The swing-up through the node (test/node/tracking.test): config/swing_up.yaml (its sensors,
// lockstep), the tracking controller following config/swing_up_plan.csv. The node's true joints
// must be, bit for bit, those of the offline closed loop (sim/closed_loop.h) running the same
// plan follower on the same seeded readings; and the crank, swung up from hanging by a drive of
// less than half the torque gravity needs, stays within 0.05 rad of upright for 60 s.
#include <cmath>
#include <iterator>
#include <limits>
#include <vector>

#include <gtest/gtest.h>
#include <sensor_msgs/JointState.h>

#include "controlled_run.h"
#include "kane_sim/TorqueCommandStamped.h"
#include "kane_sim/design/plan_file.h"
#include "kane_sim/design/plan_follower.h"
#include "kane_sim/ros/messages.h"
#include "kane_sim/sim/closed_loop.h"
#include "node_test_utils.h"

namespace kane_sim {
namespace {

using test::Recorder;

TEST(Tracking, TheNodeSwingsTheCrankUpAndHoldsItAsTheOfflineLoopDoes) {
  ros::NodeHandle nh;
  Recorder<sensor_msgs::JointState> truth(nh, "joint_states_true");
  ASSERT_TRUE(truth.waitForCount(1, 20.0));  // the paused initial state
  test::sleepWall(1.0);
  truth.clear();
  std::string plan_path, config_path;
  ASSERT_TRUE(ros::param::get("/tracking_controller/plan", plan_path));
  ASSERT_TRUE(ros::param::get("/tracking_controller/config", config_path));
  const Plan plan = readPlanCsv(plan_path).plan;
  constexpr double kHold = 60.0;
  const double until = plan.duration() + kHold;
  const size_t publishes = static_cast<size_t>(std::floor(until * 100.0));  // publish_rate 100
  // A bound, not an expectation: ~10 s here, longer on a busy machine.
  ASSERT_TRUE(test::runUnpausedFor(truth, publishes + 2, 800.0));

  XmlRpc::XmlRpcValue params;
  ASSERT_TRUE(ros::param::get("/kane_sim", params));
  const Config config = loadSimulationConfig(yamlFromXmlRpc(params)).config;
  ASSERT_TRUE(config.sensors.enabled);
  ASSERT_TRUE(config.simulation.lockstep);
  std::vector<sensor_msgs::JointState> got;
  for (const auto& m : truth.messages())  // the paused state may be repeated (once a second)
    if (m.header.stamp != simStamp(0.0)) got.push_back(m);
  ASSERT_GE(got.size(), publishes);

  SimDriver driver(config, {});
  PlanFollower follower(plan, loadConfigFile(config_path).config.command.torque_limit);
  const std::uint64_t ticks_per_publish = static_cast<std::uint64_t>(
      wholeStepsPerPeriod(config.simulation.physics_rate, config.simulation.publish_rate));
  size_t k = 0;
  double worst_hold = 0.0;
  ASSERT_TRUE(runClosedLoop(
      driver, until,
      [&](std::int64_t stamp, const JointValues& reading) {
        return follower.command(stamp, stateFromJoints(reading));
      },
      [&](const SimDriver& d) {
        if (d.ticks() % ticks_per_publish != 0 || k >= publishes) return true;
        const sensor_msgs::JointState& m = got[k++];
        const JointValues j = d.simulator().joints();
        EXPECT_EQ(m.header.stamp, simStamp(d.time())) << "publish " << k;
        for (int i = 0; i < kNumJoints; ++i) {
          EXPECT_EQ(m.position[i], j.position[i]) << "publish " << k << " joint " << i;
          EXPECT_EQ(m.velocity[i], j.velocity[i]) << "publish " << k << " joint " << i;
        }
        if (d.time() >= plan.duration())
          worst_hold =
              std::max(worst_hold, std::abs(std::remainder(m.position[0] - M_PI, 2 * M_PI)));
        return !::testing::Test::HasFailure();
      }));
  EXPECT_EQ(k, publishes);
  std::printf(
      "tracking: %zu publishes equal to the offline loop; worst |q1 - pi| over the %g s "
      "hold %.4f rad\n",
      k, kHold, worst_hold);
  EXPECT_LE(worst_hold, 0.05);
}

// Readings a rig might send: not finite, a joint missing, a stamp gone back. Each is answered (a
// lockstep node waits for every answer), never with a number that is not finite.
TEST(Tracking, HostileReadingsAreAnsweredWithAFiniteTorque) {
  ros::NodeHandle nh;
  Recorder<TorqueCommandStamped> answers(nh, "torque_command_stamped");
  ros::Publisher readings = nh.advertise<sensor_msgs::JointState>("joint_states", 10);
  ASSERT_TRUE(test::waitFor([&] { return readings.getNumSubscribers() > 0; }, 20.0));
  test::sleepWall(0.5);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  struct Reading {
    double q1, u1;
    bool slider4;
    double stamp;
  };
  const Reading cases[] = {{nan, 0, true, 1e5},           {inf, 0, true, 1e5 + 1},
                           {3.1, -inf, true, 1e5 + 2},    {3.1, 0.0, false, 1e5 + 3},
                           {1e308, 1e308, true, 1e5 + 4}, {3.1, 0.0, true, 1.0}};
  for (const Reading& r : cases) {
    sensor_msgs::JointState m;
    m.header.stamp = ros::Time(r.stamp);
    m.name = {"crank_joint"};
    m.position = {r.q1};
    m.velocity = {r.u1};
    if (r.slider4) {
      m.name.push_back("slider4_joint");
      m.position.push_back(-0.66);
      m.velocity.push_back(0.0);
    }
    readings.publish(m);
  }
  ASSERT_TRUE(answers.waitForCount(std::size(cases), 20.0)) << answers.count();
  for (const auto& a : answers.messages()) {
    if (a.header.stamp.toSec() < 10.0 && a.header.stamp != ros::Time(1.0)) continue;  // the sim's
    EXPECT_TRUE(std::isfinite(a.torque)) << a.header.stamp;
    EXPECT_LE(std::abs(a.torque), 10.0) << a.header.stamp;
  }
}

}  // namespace
}  // namespace kane_sim
