// A torque profile fed to the driver as the command stream a node would send, for the offline
// tools (`simulate`, sweeps): a command whenever the profile's value changes, and at least every
// half command timeout so the timeout never lapses. The applied torque is the same as with a
// command at every step (a lapse needs a gap longer than the timeout: with dt > timeout/2 this
// still commands every step), without a command's bookkeeping at every step.
#ifndef KANE_SIM_SIM_PROFILE_COMMANDS_H
#define KANE_SIM_SIM_PROFILE_COMMANDS_H

#include <atomic>
#include <cstdint>
#include <optional>

#include "kane_sim/sim/output_grid.h"
#include "kane_sim/sim/sim_driver.h"
#include "kane_sim/sim/torque_profile.h"

namespace kane_sim {

// A servo's setpoint (command.mode velocity | position), else a torque command: what a value
// of an offline run's command stream is.
inline TorqueCommand::Verdict sendCommand(SimDriver& driver, double value) {
  return driver.servoMode() ? driver.setpoint(value) : driver.command(value);
}

// The command stream of an offline run (`simulate`, every sweep case): the profile given, else
// the start held: 0 N m in effort mode, a servo's initial setpoint (the starting angle, or
// standing still) in command.mode velocity | position. A table whose header named a setpoint is
// refused in effort mode and one that named a torque in a servo mode (std::invalid_argument).
inline TorqueProfile profileOrHold(const SimDriver& driver,
                                   const std::optional<TorqueProfile>& given) {
  if (given) {
    given->checkPlaysAs(driver.servoMode());  // a table's header against the mode
    return *given;
  }
  return TorqueProfile::constant(driver.servoMode() ? driver.snapshot().servo.setpoint : 0.0);
}

class ProfileCommands {
 public:
  // timeout: command.timeout [s] of the driver's config (0 = none).
  ProfileCommands(const TorqueProfile& profile, double timeout)
      : profile_(profile), refresh_(timeout > 0 ? 0.5 * timeout : -1.0) {}
  ProfileCommands(const TorqueProfile&&, double) = delete;  // keeps a reference: no temporaries

  // Commands the profile's value at driver.time() when due (always on the first call).
  void update(SimDriver& driver) {
    const double now = driver.time();
    const double torque = first_ || !profile_.isConstant() ? profile_.at(now) : last_torque_;
    if (first_ || torque != last_torque_ || (refresh_ >= 0 && now - last_time_ >= refresh_)) {
      sendCommand(driver, torque);
      first_ = false;
      last_torque_ = torque;
      last_time_ = now;
    }
  }

 private:
  const TorqueProfile& profile_;
  double refresh_;  // [s] re-send at least this often; < 0: only on change
  bool first_ = true;
  double last_torque_ = 0.0;
  double last_time_ = 0.0;
};

// One value per physics step from an array (Python's Simulator.run(torque=array), a recorded
// command series): value i is commanded over step i from first_tick on, the last held after it.
class SampledCommands {
 public:
  SampledCommands(const double* values, long count, std::uint64_t first_tick)
      : values_(values), count_(count), first_tick_(first_tick) {}
  void update(SimDriver& driver) {
    const long i = static_cast<long>(driver.ticks() - first_tick_);
    if (i < count_) last_ = values_[i];
    sendCommand(driver, last_);
  }
  double last() const { return last_; }

 private:
  const double* values_;  // the caller's, alive for the run
  long count_;
  std::uint64_t first_tick_;
  double last_ = 0.0;
};

enum class RunEnd { kFinished, kStepRefused, kStopped };

// The offline run, one loop for `simulate`, every sweep case and the Python module's
// Simulator.run: `steps` physics steps of `driver` under `commands` (anything with
// update(SimDriver&): ProfileCommands, SampledCommands, or the Python module's callables; the
// caller updates them once at the start, before its first output; then after each step, as the
// node's tick does), on_step(driver) after every step and on_sample(driver) after every
// `steps_per_sample`-th and the last. Ends early when a step is refused or `stop` is set (checked
// before each step). A template, so the callbacks inline into the loop (simulate's speed bar is
// measured on it).
template <typename Commands, typename OnStep, typename OnSample>
RunEnd runProfile(SimDriver& driver, Commands& commands, long steps, long steps_per_sample,
                  const std::atomic<bool>* stop, OnStep on_step, OnSample on_sample) {
  long until_sample = steps_per_sample;  // a countdown: a division per step shows in a profile
  for (long i = 1; i <= steps; ++i) {
    if (stop && stop->load(std::memory_order_relaxed)) return RunEnd::kStopped;
    if (!driver.step()) return RunEnd::kStepRefused;
    commands.update(driver);
    on_step(driver);
    if (--until_sample == 0 || i == steps) {
      on_sample(driver);
      until_sample = steps_per_sample;
    }
  }
  return RunEnd::kFinished;
}

// simulate's run, for every door that makes simulate's rows (`simulate`, the browser's
// kaneSim.run): `profile` as the command stream, on_sample(driver) for the row at the start, then
// on_step(driver) (the start's sensor readings), then runProfile over `grid`.
template <typename OnStep, typename OnSample>
RunEnd runOnGrid(SimDriver& driver, const TorqueProfile& profile, const OutputGrid& grid,
                 const std::atomic<bool>* stop, OnStep on_step, OnSample on_sample) {
  ProfileCommands commands(profile, driver.config().command.timeout);
  commands.update(driver);
  on_sample(driver);
  on_step(driver);
  return runProfile(driver, commands, grid.steps(), grid.steps_per_row, stop, on_step, on_sample);
}

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_PROFILE_COMMANDS_H
