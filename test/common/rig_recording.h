// A rig recorded the way users record one, without a master: the simulator with its sensors
// on, under a PD controller that reads the sensors' joint_states and chases random setpoints
// (what sim.launch controller:=true does), each reading as joint_states carries it (stamped when
// it arrives) with the truth at that instant beside it. For the estimator's tests.
#ifndef KANE_SIM_TEST_COMMON_RIG_RECORDING_H
#define KANE_SIM_TEST_COMMON_RIG_RECORDING_H

#include <algorithm>
#include <functional>
#include <random>
#include <vector>

#include "kane_sim/estimate/mechanism_estimator.h"
#include "kane_sim/sim/sim_driver.h"

namespace kane_sim {
namespace test {

struct RecordedReading {
  RigReading reading;  // as joint_states carries it
  Snapshot truth;      // the simulator at the reading's stamp
  State sampled;       // the truth when the reading was sampled (latency earlier)
  double sample_time = 0.0;
};

// The truth at time t (linear between the physics ticks of `history`).
inline State truthAt(const std::vector<State>& history, double t, double physics_rate) {
  const double tick = std::clamp(t * physics_rate, 0.0, static_cast<double>(history.size() - 1));
  const auto a = static_cast<std::size_t>(tick);
  const std::size_t b = std::min(a + 1, history.size() - 1);
  const double w = tick - static_cast<double>(a);
  const State& x = history[a];
  const State& y = history[b];
  return {x.q1 + w * (y.q1 - x.q1), x.q2 + w * (y.q2 - x.q2), x.u1 + w * (y.u1 - x.u1),
          x.u2 + w * (y.u2 - x.u2)};
}

struct RigRecording {
  std::vector<RecordedReading> readings;
  std::vector<State> history;  // the truth at every physics tick
  double physics_rate = 0.0;
  State at(double t) const { return truthAt(history, t, physics_rate); }
};

struct RigDrive {
  double kp = 40.0, kd = 4.0;             // [N m/rad], [N m s/rad] on the readings
  double torque_limit = 30.0;             // [N m]
  double setpoint_range = 1.5;            // [rad] setpoints uniform in +- this
  double hold_min = 0.3, hold_max = 1.5;  // [s] each setpoint held this long
  unsigned seed = 1;
  // While this says true (sim time), the rig's driver is stalled, as a loaded scheduler stalls a
  // node stamping on the wall clock: its readings are held and then published in a burst, 0.1 ms
  // apart, the controller answering each as it comes; no answer lands during the stall.
  std::function<bool(double)> stalled;
};

// Runs `rig` for `duration` s of sim time. `at_tick` (when set) is called before every step with
// the driver (a fault injected at a time, say).
inline RigRecording recordRig(const Config& rig, double duration, const RigDrive& drive,
                              const std::function<void(SimDriver&)>& at_tick = {}) {
  SimDriver driver(rig, {});
  std::mt19937 random(drive.seed);
  std::uniform_real_distribution<double> setpoints(-drive.setpoint_range, drive.setpoint_range);
  std::uniform_real_distribution<double> holds(drive.hold_min, drive.hold_max);
  double setpoint = setpoints(random), next_change = holds(random);
  std::vector<RecordedReading> readings;
  std::vector<State> history = {driver.simulator().state()};  // by tick
  std::vector<RecordedReading> held;                          // a stalled driver's readings
  const auto answer = [&](const RigReading& reading) {
    const double torque = drive.kp * (setpoint - reading.q1) - drive.kd * reading.u1;
    driver.command(std::clamp(torque, -drive.torque_limit, drive.torque_limit));
  };
  const auto steps = static_cast<std::uint64_t>(duration * rig.simulation.physics_rate);
  for (std::uint64_t k = 0; k < steps; ++k) {
    if (at_tick) at_tick(driver);
    driver.step();
    history.push_back(driver.simulator().state());
    if (driver.time() >= next_change) {
      setpoint = setpoints(random);
      next_change = driver.time() + holds(random);
    }
    const bool stalled = drive.stalled && drive.stalled(driver.time());
    if (!stalled && !held.empty()) {
      for (std::size_t i = 0; i < held.size(); ++i) {
        held[i].reading.stamp =
            driver.time() - 1e-4 * static_cast<double>(held.size() - i);  // the burst
        readings.push_back(held[i]);
        answer(held[i].reading);
      }
      held.clear();
    }
    SensorReading r;
    while (driver.takeSensorReading(&r)) {
      RecordedReading rec;
      rec.reading.stamp = driver.time();
      rec.reading.q1 = r.joints.position[kCrankJoint];
      rec.reading.q2 = r.joints.position[kSlider4Joint];
      rec.reading.has_velocity = true;
      rec.reading.u1 = r.joints.velocity[kCrankJoint];
      rec.reading.u2 = r.joints.velocity[kSlider4Joint];
      rec.reading.torque = r.joints.effort[kCrankJoint];
      rec.truth = driver.snapshot();
      rec.sampled = history.at(r.sample_tick);
      rec.sample_time = r.sample_time;
      if (stalled) {
        held.push_back(rec);
        continue;
      }
      readings.push_back(rec);
      answer(rec.reading);
    }
  }
  return {readings, history, rig.simulation.physics_rate};
}

}  // namespace test
}  // namespace kane_sim

#endif  // KANE_SIM_TEST_COMMON_RIG_RECORDING_H
