// Sensors (sensors/joint_sensors.h, driven by SimDriver): the measured noise, bias walk,
// quantisation and delays are what the config says, within statistical tolerances stated at each
// test; one seed gives one sequence; the physics never sees the sensors.
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "kane_sim/config/load_config.h"
#include "kane_sim/sensors/joint_sensors.h"
#include "kane_sim/sim/sim_driver.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

constexpr double kPhysicsRate = 1000.0;
constexpr double kPublishRate = 100.0;

SensorSettings enabledSensors() {
  SensorSettings s;
  s.enabled = true;
  return s;
}

// Every reading of `n` samples of constant truth `truth`, delivered in order.
std::vector<SensorReading> readConstant(const SensorSettings& settings, const JointValues& truth,
                                        int n) {
  JointSensors sensors(settings, kPhysicsRate, kPublishRate);
  std::vector<SensorReading> out;
  SensorReading r;
  for (std::uint64_t tick = 0; out.size() < static_cast<std::size_t>(n); ++tick) {
    sensors.onTick(tick, tick / kPhysicsRate, [&] { return truth; });
    while (sensors.takeDue(tick, &r)) out.push_back(r);
  }
  return out;
}

double mean(const std::vector<double>& v) {
  return std::accumulate(v.begin(), v.end(), 0.0) / v.size();
}
double standardDeviation(const std::vector<double>& v) {
  const double m = mean(v);
  double sum = 0.0;
  for (double x : v) sum += (x - m) * (x - m);
  return std::sqrt(sum / (v.size() - 1));
}

// N = 20000 samples: the sample σ has a relative standard error 1/√(2N) = 0.5 %, so 3 % is six
// standard errors; the mean's standard error is σ/√N = 0.7 % of σ, 5 % of σ is seven.
constexpr int kSamples = 20000;

TEST(JointSensors, WhiteNoiseHasTheConfiguredSigmaAndNoMean) {
  SensorSettings s = enabledSensors();
  s.joints[kCrankJoint].position_noise = 0.01;
  s.joints[kSlider4Joint].velocity_noise = 0.2;
  JointValues truth;
  truth.position = {1.0, -2.0, 0.5, 0.8};
  truth.velocity = {0.3, -0.6, 0.1, -0.2};
  truth.effort = {7.0, 0, 0, 0};
  const std::vector<SensorReading> readings = readConstant(s, truth, kSamples);
  std::vector<double> crank, slider4_speed;
  for (const SensorReading& r : readings) {
    crank.push_back(r.joints.position[kCrankJoint] - 1.0);
    slider4_speed.push_back(r.joints.velocity[kSlider4Joint] + 0.2);
    // What has no noise configured is the truth, exactly; effort is the delivered torque.
    EXPECT_EQ(r.joints.position[kSlider4Joint], 0.8);
    EXPECT_EQ(r.joints.velocity[kCrankJoint], 0.3);
    EXPECT_EQ(r.joints.effort[kCrankJoint], 7.0);
  }
  EXPECT_NEAR(standardDeviation(crank), 0.01, 0.03 * 0.01);
  EXPECT_NEAR(mean(crank), 0.0, 0.05 * 0.01);
  EXPECT_NEAR(standardDeviation(slider4_speed), 0.2, 0.03 * 0.2);
  EXPECT_NEAR(mean(slider4_speed), 0.0, 0.05 * 0.2);
}

// The bias is a random walk: its increments between readings are independent, N(0, b² Δt).
// Without white noise, a reading minus the truth is the bias, so the increments are measured
// directly (same tolerance as above: 20000 increments).
TEST(JointSensors, BiasWalksWithTheConfiguredIntensity) {
  SensorSettings s = enabledSensors();
  s.joints[kSlider3Joint].bias_walk = 0.004;  // [m/√s]
  const std::vector<SensorReading> readings = readConstant(s, JointValues{}, kSamples + 1);
  std::vector<double> increments;
  for (std::size_t i = 1; i < readings.size(); ++i)
    increments.push_back(readings[i].joints.position[kSlider3Joint] -
                         readings[i - 1].joints.position[kSlider3Joint]);
  const double dt = 1.0 / kPublishRate;
  EXPECT_NEAR(standardDeviation(increments), 0.004 * std::sqrt(dt), 0.03 * 0.004 * std::sqrt(dt));
  // The bias wanders: after 200 s its σ is 0.004 √200 = 0.057 m; it is not reset per reading.
  EXPECT_NE(readings.back().joints.position[kSlider3Joint], 0.0);
}

// Encoder counts: every position is a whole number of counts (2π/counts per turn, 1/counts per
// metre), the nearest one to the truth (error at most half a count), and ramps through every
// level in between.
TEST(JointSensors, EncodersRoundToWholeCounts) {
  SensorSettings s = enabledSensors();
  s.joints[kCrankJoint].encoder_counts = 4096;
  s.joints[kSlider4Joint].encoder_counts = 10000;
  JointSensors sensors(s, kPhysicsRate, kPublishRate);
  const double crank_step = 2.0 * M_PI / 4096, slider_step = 1e-4;
  std::set<long> crank_levels;
  SensorReading r;
  for (std::uint64_t tick = 0; tick < 100000; tick += 10) {
    JointValues truth;
    truth.position[kCrankJoint] = 0.3 + 1e-5 * tick;  // a slow ramp: 0.1 rad
    truth.position[kSlider4Joint] = -0.7 - 3e-7 * tick;
    sensors.onTick(tick, tick / kPhysicsRate, [&] { return truth; });
    ASSERT_TRUE(sensors.takeDue(tick, &r));
    const double crank_counts = r.joints.position[kCrankJoint] / crank_step;
    EXPECT_NEAR(crank_counts, std::round(crank_counts), 1e-9);
    EXPECT_LE(std::abs(r.joints.position[kCrankJoint] - truth.position[kCrankJoint]),
              0.5 * crank_step * (1 + 1e-9));
    const double slider_counts = r.joints.position[kSlider4Joint] / slider_step;
    EXPECT_NEAR(slider_counts, std::round(slider_counts), 1e-9);
    EXPECT_LE(std::abs(r.joints.position[kSlider4Joint] - truth.position[kSlider4Joint]),
              0.5 * slider_step * (1 + 1e-9));
    crank_levels.insert(std::lround(crank_counts));
  }
  // 1 rad of ramp covers 0.99999 / step = 652 counts: every level is seen, none skipped.
  EXPECT_EQ(static_cast<long>(crank_levels.size()),
            *crank_levels.rbegin() - *crank_levels.begin() + 1);
  EXPECT_GT(crank_levels.size(), 600u);
}

// Latency 20 ms + jitter up to 5 ms at 1 kHz: every reading arrives 20..25 ticks after its
// sample, never before the one sampled before it, and every delay in the range occurs.
TEST(JointSensors, ReadingsArriveAfterTheLatencyWithJitterInOrder) {
  SensorSettings s = enabledSensors();
  s.latency = 0.02;
  s.latency_jitter = 0.005;
  s.rate = 1000.0;  // a reading every tick: jitter larger than the period, so order matters
  const std::vector<SensorReading> readings = readConstant(s, JointValues{}, 5000);
  std::map<std::uint64_t, int> delays;
  for (std::size_t i = 0; i < readings.size(); ++i) {
    const SensorReading& r = readings[i];
    ASSERT_GE(r.delivery_tick, r.sample_tick + 20);
    ASSERT_LE(r.delivery_tick, r.sample_tick + 25);
    if (i > 0) {
      ASSERT_GE(r.delivery_tick, readings[i - 1].delivery_tick);
      ASSERT_GT(r.sample_tick, readings[i - 1].sample_tick);
    }
    ++delays[r.delivery_tick - r.sample_tick];
  }
  EXPECT_EQ(delays.size(), 6u);  // 20, 21, ..., 25
  // Without the in-order rule each of the 6 jitters would be 1/6; holding a reading behind a
  // later one only shifts mass to longer delays, so the 20-tick delay is rarer than 1/6 but the
  // mean delay stays within the jitter range.
  double sum = 0.0;
  for (const auto& d : delays) sum += static_cast<double>(d.first) * d.second;
  const double mean_delay = sum / readings.size();
  EXPECT_GT(mean_delay, 22.4);  // 22.5 is the unordered mean; ordering only adds
  EXPECT_LT(mean_delay, 25.0);
}

TEST(JointSensors, OneSeedOneSequence) {
  SensorSettings s = enabledSensors();
  s.joints[kCrankJoint].position_noise = 0.01;
  s.joints[kCouplerJoint].bias_walk = 0.01;
  s.latency_jitter = 0.003;
  const auto a = readConstant(s, JointValues{}, 500);
  const auto b = readConstant(s, JointValues{}, 500);
  s.seed = 2;
  const auto c = readConstant(s, JointValues{}, 500);
  int differing = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].joints.position, b[i].joints.position);
    EXPECT_EQ(a[i].delivery_tick, b[i].delivery_tick);
    differing += a[i].joints.position[kCrankJoint] != c[i].joints.position[kCrankJoint];
  }
  EXPECT_EQ(differing, 500);
}

// Switching on noise on one joint does not change another joint's noise: the draws are made
// in one fixed order whatever is configured.
TEST(JointSensors, OneJointsSettingLeavesTheOthersNoiseAlone) {
  SensorSettings s = enabledSensors();
  s.joints[kCrankJoint].position_noise = 0.01;
  const auto a = readConstant(s, JointValues{}, 200);
  s.joints[kSlider3Joint].position_noise = 0.5;
  s.joints[kSlider3Joint].encoder_counts = 100;
  const auto b = readConstant(s, JointValues{}, 200);
  for (std::size_t i = 0; i < a.size(); ++i)
    EXPECT_EQ(a[i].joints.position[kCrankJoint], b[i].joints.position[kCrankJoint]);
}

// Through the driver: a reading delivered at tick k + L holds the truth of tick k (noise off),
// the physics is that of a driver without sensors bit for bit, and a reset drops the readings
// in flight (none shows the state before it).
TEST(JointSensors, TheDriverDeliversTheTruthOfTheSampleTickLate) {
  Config with = test::defaultConfig();
  with.sensors.enabled = true;
  with.sensors.latency = 0.03;  // 30 ticks, three sample periods
  Config without = test::defaultConfig();
  SimDriver sensed(with, {});
  SimDriver plain(without, {});
  std::map<std::uint64_t, JointValues> truth{{0, plain.simulator().joints()}};
  sensed.command(20.0);
  plain.command(20.0);
  int delivered = 0;
  for (int i = 0; i < 500; ++i) {
    ASSERT_TRUE(sensed.step());
    ASSERT_TRUE(plain.step());
    ASSERT_EQ(sensed.simulator().state().q1, plain.simulator().state().q1);
    truth[plain.ticks()] = plain.simulator().joints();
    SensorReading r;
    while (sensed.takeSensorReading(&r)) {
      EXPECT_EQ(r.delivery_tick, sensed.ticks());
      EXPECT_EQ(r.delivery_tick, r.sample_tick + 30);
      EXPECT_EQ(r.sample_tick % 10, 0u);
      EXPECT_EQ(r.joints.position, truth.at(r.sample_tick).position);
      EXPECT_EQ(r.joints.velocity, truth.at(r.sample_tick).velocity);
      ++delivered;
    }
  }
  EXPECT_EQ(delivered, (500 - 30) / 10 + 1);  // samples at ticks 0, 10, ..., 470
  EXPECT_EQ(sensed.sensors().pending(), 3u);
  // A reset: what was in flight is dropped; what comes next was sampled after it.
  const std::uint64_t reset_tick = sensed.ticks();
  sensed.reset();
  EXPECT_EQ(sensed.sensors().pending(), 1u);  // tick 500 is on the grid: sampled anew
  for (int i = 0; i < 100; ++i) {
    ASSERT_TRUE(sensed.step());
    SensorReading r;
    while (sensed.takeSensorReading(&r)) EXPECT_GE(r.sample_tick, reset_tick);
  }
}

// command_latency: a command is in force that many steps after it arrived, through the same
// clamp and timeout; a non-finite one is refused at once; a reset drops one in flight.
TEST(JointSensors, CommandLatencyDelaysTheTorquePath) {
  Config config = test::defaultConfig();
  config.sensors.enabled = true;
  config.sensors.command_latency = 0.01;  // 10 steps
  std::vector<SimEvent> events;
  SimDriver driver(config, [&events](const SimEvent& e) { events.push_back(e); });
  EXPECT_EQ(driver.command(5.0), TorqueCommand::Verdict::kAccepted);
  for (int i = 0; i < 9; ++i) {
    ASSERT_TRUE(driver.step());
    EXPECT_EQ(driver.snapshot().command.commanded, 0.0) << "step " << i + 1;
  }
  ASSERT_TRUE(driver.step());
  EXPECT_EQ(driver.snapshot().command.commanded, 5.0);
  EXPECT_EQ(driver.simulator().torque(), 5.0);
  EXPECT_EQ(driver.command(std::nan("")), TorqueCommand::Verdict::kRejected);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, SimEvent::Kind::kCommandRejected);
  EXPECT_EQ(driver.command(500.0), TorqueCommand::Verdict::kClamped);
  EXPECT_EQ(events.size(), 1u);  // the clamp is reported when it takes effect
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(driver.step());
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[1].kind, SimEvent::Kind::kCommandClamped);
  EXPECT_EQ(driver.simulator().torque(), config.command.torque_limit);
  driver.command(-3.0);
  driver.reset();
  for (int i = 0; i < 20; ++i) ASSERT_TRUE(driver.step());
  EXPECT_EQ(driver.simulator().torque(), 0.0);  // the command in flight went with the reset
  // Off (the default), command_latency is not applied: the sensors section is one switch.
  Config off = config;
  off.sensors.enabled = false;
  SimDriver immediate(off, {});
  immediate.command(5.0);
  EXPECT_EQ(immediate.simulator().torque(), 5.0);
}

TEST(JointSensors, OffTheDriverHasNoReadings) {
  SimDriver driver(test::defaultConfig(), {});
  SensorReading r;
  for (int i = 0; i < 50; ++i) {
    ASSERT_TRUE(driver.step());
    EXPECT_FALSE(driver.takeSensorReading(&r));
  }
}

// The loader's cross rule and the hostile values of the section's own rules (every number of
// the schema also goes through ParameterSchema.HostileNumbersAreRefusedNamingTheKey).
TEST(JointSensors, BadSettingsStopTheLoadNamingTheKey) {
  const auto refused = [](const std::string& key, const std::string& value) {
    YAML::Node root = YAML::LoadFile(test::configPath("mechanism.yaml"));
    root["sensors"][key] = YAML::Load(value);
    try {
      loadConfig(root);
    } catch (const ConfigError& e) {
      EXPECT_EQ(e.key(), "sensors." + key) << e.what();
      EXPECT_NE(std::string(e.what()).find(value == "333" ? "whole number" : ""), std::string::npos)
          << e.what();
      return true;
    }
    return false;
  };
  EXPECT_TRUE(refused("rate", "333"));  // 1000/333 steps is not whole
  EXPECT_TRUE(refused("rate", "-100"));
  EXPECT_TRUE(refused("rate", "2000"));  // faster than the physics
  EXPECT_TRUE(refused("latency", "-0.001"));
  EXPECT_TRUE(refused("latency", "11"));
  EXPECT_TRUE(refused("latency_jitter", "1e308"));
  EXPECT_TRUE(refused("command_latency", "-1"));
  EXPECT_TRUE(refused("seed", "-1"));
  EXPECT_TRUE(refused("seed", "1.5"));
  EXPECT_TRUE(refused("seed", "1e10"));
  EXPECT_TRUE(refused("crank_position_noise", "-0.1"));
  EXPECT_TRUE(refused("crank_position_noise", "1e308"));  // would overflow to inf readings
  EXPECT_TRUE(refused("slider4_encoder_counts", "0.5"));
  EXPECT_TRUE(refused("enabled", "yes please"));
  EXPECT_FALSE(refused("rate", "250"));
  EXPECT_FALSE(refused("crank_encoder_counts", "0"));
  // A typo is named, not silently ignored.
  YAML::Node root = YAML::LoadFile(test::configPath("mechanism.yaml"));
  root["sensors"]["crank_noise"] = 0.1;
  const LoadedConfig loaded = loadConfig(root);
  ASSERT_EQ(loaded.warnings.size(), 1u);
  EXPECT_NE(loaded.warnings[0].find("sensors.crank_noise"), std::string::npos);
  // The shipped example overlay loads over the default and turns the sensors on.
  YAML::Node overlay = YAML::LoadFile(test::configPath("sensors.yaml"));
  YAML::Node merged = YAML::LoadFile(test::configPath("mechanism.yaml"));
  for (const auto& entry : overlay["sensors"])
    merged["sensors"][entry.first.Scalar()] = entry.second;
  const LoadedConfig example = loadConfig(merged);
  EXPECT_TRUE(example.warnings.empty());
  EXPECT_TRUE(example.config.sensors.enabled);
}

}  // namespace
}  // namespace kane_sim
