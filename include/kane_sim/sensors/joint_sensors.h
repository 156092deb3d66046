// The joints as sensors report them (config sensors:): the truth plus a walking bias plus white
// noise, rounded to encoder counts, sampled on a grid of physics ticks and delivered whole after
// a latency with jitter, never overtaking one another. Seeded: a seed and a config give one
// sequence of readings, whatever the machine's load. ROS-free; SimDriver owns one.
#ifndef KANE_SIM_SENSORS_JOINT_SENSORS_H
#define KANE_SIM_SENSORS_JOINT_SENSORS_H

#include <array>
#include <cstdint>
#include <deque>
#include <random>
#include <string>

#include "kane_sim/config/config.h"
#include "kane_sim/description/joint_values.h"

namespace kane_sim {

struct SensorReading {
  std::uint64_t sample_tick = 0;    // the physics tick the joints were sampled at
  std::uint64_t delivery_tick = 0;  // the tick it reaches joint_states (>= sample_tick)
  double sample_time = 0.0;         // [s] sim time of sample_tick
  JointValues joints;               // as measured; effort is the delivered torque, exact
};

class JointSensors {
 public:
  // physics_rate and publish_rate: the simulation's (a sensors.rate of 0 means publish_rate).
  JointSensors(const SensorSettings& settings, double physics_rate, double publish_rate);

  bool enabled() const { return settings_.enabled; }
  // At every physics tick the mechanism reaches (after each step, and at start): takes a reading
  // when the tick is on the sensor grid. `truth` is only evaluated then.
  template <typename TruthFn>
  void onTick(std::uint64_t tick, double time, TruthFn truth) {
    if (enabled() && tick % ticks_per_sample_ == 0) sample(tick, time, truth());
  }
  // The oldest reading whose delivery tick has come, removed from the queue; false when none.
  bool takeDue(std::uint64_t tick, SensorReading* reading);
  // The mechanism was moved (reset, set_state): readings of the old state still in flight are
  // dropped. The biases stay: they belong to the sensors, not to the state.
  void dropPending();

  std::uint64_t ticksPerSample() const { return ticks_per_sample_; }
  std::uint64_t latencyTicks() const { return latency_ticks_; }
  std::uint64_t jitterTicks() const { return jitter_ticks_; }
  const std::array<double, kNumJoints>& biases() const { return bias_; }
  std::size_t pending() const { return queue_.size(); }

  // What the sensors remember (sim/checkpoint.h): the random engine and normal distribution as
  // their standard text, the biases, the readings in flight. Restored into sensors of the same
  // settings, they give the same readings from there on.
  struct Memory {
    std::string random;
    std::array<double, kNumJoints> bias{};
    std::deque<SensorReading> queue;
    std::uint64_t last_delivery_tick = 0;
  };
  Memory memory() const;
  void restore(const Memory& memory);  // std::invalid_argument when `random` does not parse

 private:
  void sample(std::uint64_t tick, double time, const JointValues& truth);
  double measurePosition(int joint, double truth);

  SensorSettings settings_;
  std::uint64_t ticks_per_sample_;
  std::uint64_t latency_ticks_;
  std::uint64_t jitter_ticks_;
  double sample_period_;  // [s]
  std::mt19937_64 random_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  std::array<double, kNumJoints> bias_{};  // [rad | m] each joint's position bias now
  std::deque<SensorReading> queue_;        // in delivery order
  std::uint64_t last_delivery_tick_ = 0;
};

// Whole physics steps in `seconds` at `physics_rate` (a latency's, rounded to the nearest).
std::uint64_t physicsTicks(double seconds, double physics_rate);

}  // namespace kane_sim

#endif  // KANE_SIM_SENSORS_JOINT_SENSORS_H
