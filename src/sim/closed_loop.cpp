#include "kane_sim/sim/closed_loop.h"

#include <cmath>
#include <cstdint>

namespace kane_sim {

std::int64_t stampNanoseconds(double t) {
  // ros::Duration::fromSec: whole seconds by floor, the rest rounded to nanoseconds.
  const double seconds = std::floor(t);
  return static_cast<std::int64_t>(seconds) * 1000000000 +
         static_cast<std::int64_t>(std::round((t - seconds) * 1e9));
}

bool runClosedLoop(SimDriver& driver, double until, const ReadingController& controller,
                   const std::function<bool(const SimDriver&)>& after_step) {
  const Config& config = driver.config();
  const std::uint64_t ticks_per_publish = static_cast<std::uint64_t>(
      wholeStepsPerPeriod(config.simulation.physics_rate, config.simulation.publish_rate));
  const double dt = 1.0 / config.simulation.physics_rate;
  const auto answer = [&](double time, const JointValues& joints) {
    if (const std::optional<double> torque = controller(stampNanoseconds(time), joints))
      driver.command(*torque);
  };
  while (driver.time() < until - dt / 2) {
    if (!driver.sensorsEnabled() && driver.ticks() % ticks_per_publish == 0)
      answer(driver.time(), driver.simulator().joints());
    if (!driver.step()) return false;
    SensorReading reading;
    while (driver.takeSensorReading(&reading)) answer(driver.time(), reading.joints);
    if (after_step && !after_step(driver)) return false;
  }
  return true;
}

}  // namespace kane_sim
