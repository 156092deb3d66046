#include "kane_sim/sensors/joint_sensors.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace kane_sim {
namespace {

bool isRevolute(int joint) { return joint == kCrankJoint || joint == kCouplerJoint; }

}  // namespace

std::uint64_t physicsTicks(double seconds, double physics_rate) {
  return static_cast<std::uint64_t>(std::llround(seconds * physics_rate));
}

JointSensors::JointSensors(const SensorSettings& settings, double physics_rate, double publish_rate)
    : settings_(settings),
      ticks_per_sample_(std::max<std::uint64_t>(
          1, static_cast<std::uint64_t>(wholeStepsPerPeriod(
                 physics_rate, settings.rate > 0 ? settings.rate : publish_rate)))),
      latency_ticks_(physicsTicks(settings.latency, physics_rate)),
      jitter_ticks_(physicsTicks(settings.latency_jitter, physics_rate)),
      sample_period_(static_cast<double>(ticks_per_sample_) / physics_rate),
      random_(static_cast<std::uint64_t>(settings.seed)) {}

double JointSensors::measurePosition(int joint, double truth) {
  const JointSensorSettings& s = settings_.joints[joint];
  // Bias first (a random walk: its variance grows by bias_walk² per second), then white noise.
  bias_[joint] += s.bias_walk * std::sqrt(sample_period_) * normal_(random_);
  double measured = truth + bias_[joint] + s.position_noise * normal_(random_);
  if (s.encoder_counts > 0) {
    // To the nearest count: the quantisation error is uniform in ±step/2, unbiased.
    const double step = (isRevolute(joint) ? 2.0 * M_PI : 1.0) / s.encoder_counts;
    measured = step * std::round(measured / step);
  }
  return measured;
}

void JointSensors::sample(std::uint64_t tick, double time, const JointValues& truth) {
  SensorReading r;
  r.sample_tick = tick;
  r.sample_time = time;
  r.joints.effort = truth.effort;
  // The draws in one fixed order per reading (bias, position, velocity per joint, then the
  // jitter), whatever is switched on: a setting of one joint never changes another's noise.
  for (int j = 0; j < kNumJoints; ++j) {
    r.joints.position[j] = measurePosition(j, truth.position[j]);
    r.joints.velocity[j] =
        truth.velocity[j] + settings_.joints[j].velocity_noise * normal_(random_);
  }
  std::uint64_t delay = latency_ticks_;
  if (jitter_ticks_ > 0)
    delay += std::uniform_int_distribution<std::uint64_t>(0, jitter_ticks_)(random_);
  // One connection: a reading never overtakes the one before it.
  r.delivery_tick = std::max(tick + delay, last_delivery_tick_);
  last_delivery_tick_ = r.delivery_tick;
  queue_.push_back(r);
}

bool JointSensors::takeDue(std::uint64_t tick, SensorReading* reading) {
  if (queue_.empty() || queue_.front().delivery_tick > tick) return false;
  *reading = queue_.front();
  queue_.pop_front();
  return true;
}

JointSensors::Memory JointSensors::memory() const {
  std::ostringstream random;
  random << random_ << ' ' << normal_;
  return {random.str(), bias_, queue_, last_delivery_tick_};
}

void JointSensors::restore(const Memory& memory) {
  std::istringstream random(memory.random);
  std::mt19937_64 engine;
  std::normal_distribution<double> normal;
  random >> engine >> normal;
  if (!random) throw std::invalid_argument("the sensors' random state does not parse");
  random_ = engine;
  normal_ = normal;
  bias_ = memory.bias;
  queue_ = memory.queue;
  last_delivery_tick_ = memory.last_delivery_tick;
}

void JointSensors::dropPending() {
  queue_.clear();
  last_delivery_tick_ = 0;
}

}  // namespace kane_sim
