// Sensors through the node (test/node/sensors.test): lockstep on the sim clock, the example
// controller answering every reading. joint_states must carry exactly the readings the ROS-free
// driver gives with the same seed (noise, bias walk, encoder counts, latency with jitter), stamped
// when they arrive; joint_states_true the truth; and the controller's torques, through the
// command latency, the same trajectory — so a seed gives one run, whatever the machine does.
#include <cmath>
#include <map>
#include <vector>

#include <gtest/gtest.h>
#include <sensor_msgs/JointState.h>

#include "controlled_run.h"
#include "kane_sim/MechanismState.h"
#include "kane_sim/ros/messages.h"
#include "kane_sim/sim/sim_driver.h"
#include "node_test_utils.h"

namespace kane_sim {
namespace {

using test::Recorder;

TEST(Sensors, ReadingsTruthAndTheControlledRunAreTheSeededOfflineOnes) {
  ros::NodeHandle nh;
  Recorder<sensor_msgs::JointState> readings(nh, "joint_states");
  Recorder<sensor_msgs::JointState> truth(nh, "joint_states_true");
  ASSERT_TRUE(truth.waitForCount(1, 20.0));  // the paused initial state (latency: no reading yet)
  test::sleepWall(1.0);
  EXPECT_EQ(readings.count(), 0u);
  truth.clear();
  constexpr size_t kReadings = 300;  // 3 s of sim time at 100 Hz
  ASSERT_TRUE(test::runUnpausedFor(readings, kReadings + 2));

  test::ControlledRun run;
  ASSERT_TRUE(test::readControlledRun(&run));
  const Config& config = run.config;
  ASSERT_TRUE(config.sensors.enabled);
  const PdGains& gains = run.gains;
  const double setpoint = run.setpoint;

  // Offline: the node's loop without ROS. After each step the due readings are answered by the
  // law at once (lockstep holds the next step until the answer is in).
  SimDriver driver(config, {});
  const std::vector<sensor_msgs::JointState> got = readings.messages();
  std::vector<sensor_msgs::JointState> got_truth = truth.messages();
  // Paused in /clock mode the node repeats its initial state every second of wall time, and the
  // test slept a second before the clear: a repeat may land just after it. Not part of the run.
  while (!got_truth.empty() && got_truth.front().header.stamp == simStamp(0.0))
    got_truth.erase(got_truth.begin());
  const std::uint64_t ticks_per_publish = static_cast<std::uint64_t>(
      wholeStepsPerPeriod(config.simulation.physics_rate, config.simulation.publish_rate));
  size_t k = 0, t = 0, truth_compared = 0;
  double largest_noise = 0.0;
  std::map<std::uint64_t, JointValues> true_at{{0, driver.simulator().joints()}};
  while (k < kReadings) {
    ASSERT_TRUE(driver.step());
    true_at[driver.ticks()] = driver.simulator().joints();
    if (driver.ticks() % ticks_per_publish == 0 && t < got_truth.size()) {
      const Snapshot s = driver.snapshot();
      const sensor_msgs::JointState& m = got_truth[t++];
      ASSERT_EQ(m.header.stamp, simStamp(s.time)) << "truth " << t;
      for (int j = 0; j < kNumJoints; ++j) EXPECT_EQ(m.position[j], s.joints.position[j]);
      ++truth_compared;
    }
    SensorReading r;
    while (driver.takeSensorReading(&r)) {
      const sensor_msgs::JointState& m = got[k];
      ASSERT_EQ(m.header.stamp, simStamp(driver.time())) << "reading " << k;
      const JointValues& j = r.joints;
      for (int i = 0; i < kNumJoints; ++i) {
        ASSERT_EQ(m.position[i], j.position[i]) << "reading " << k << " joint " << i;
        ASSERT_EQ(m.velocity[i], j.velocity[i]) << "reading " << k << " joint " << i;
      }
      ASSERT_EQ(m.effort[0], j.effort[0]) << "reading " << k;
      // Arrived 4..9 ms after it was sampled (latency 4 ms + jitter up to 5 ms).
      const double delay = driver.time() - r.sample_time;
      EXPECT_GE(delay, 0.004 - 1e-9);
      EXPECT_LE(delay, 0.009 + 1e-9);
      // The encoder: a whole number of 4096ths of a turn.
      const double counts = j.position[0] / (2 * M_PI / 4096);
      EXPECT_NEAR(counts, std::round(counts), 1e-6);
      // What the controller saw is not the truth of the sample's instant, but near it: noise
      // σ 0.002 rad, a bias walk of 0.001 rad/√s over 3 s, half a count (0.00077 rad).
      const double error = j.position[0] - true_at.at(r.sample_tick).position[0];
      EXPECT_LT(std::abs(error), 6 * 0.002 + 6 * 0.001 * std::sqrt(3.0) + 0.0008);
      largest_noise = std::max(largest_noise, std::abs(error));
      driver.command(pdTorque(gains, setpoint, j.position[0], j.velocity[0]));
      ++k;
    }
  }
  EXPECT_GT(truth_compared, 250u);
  // The controller moved the crank, and what it saw was not the truth.
  EXPECT_GT(std::abs(got[kReadings - 1].position[0] - config.initial_state.q1), 0.2);
  EXPECT_GT(largest_noise, 1e-3);
}

}  // namespace
}  // namespace kane_sim
