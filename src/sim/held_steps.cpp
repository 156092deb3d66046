// SimDriver::stepHeld: a held torque over a number of steps, with its refusals and its account.
#include <atomic>
#include <cmath>
#include <sstream>

#include "kane_sim/format_number.h"
#include "kane_sim/sim/profile_commands.h"
#include "kane_sim/sim/sim_driver.h"

namespace kane_sim {

SimDriver::HeldSteps SimDriver::stepHeld(double torque, std::uint64_t steps,
                                         const std::function<std::string()>& stop_reason) {
  HeldSteps result;
  if (servoMode())
    result.message = std::string("command.mode is ") + commandModeName(config_.command.mode) +
                     ": the drive takes servo_setpoint, not a torque (publish it, then call ~step)";
  else if (!std::isfinite(torque))
    result.message = "torque = " + formatNumber(torque) + " is not finite";
  else if (steps < 1 || steps > kMaxHeldSteps)
    result.message = "steps = " + std::to_string(steps) + " must be in [1, " +
                     std::to_string(kMaxHeldSteps) + "]";
  if (!result.message.empty()) {
    result.refused = true;
    result.message += "; nothing changed";
    return result;
  }
  const TorqueProfile held = TorqueProfile::constant(torque);
  ProfileCommands commands(held, config_.command.timeout);
  commands.update(*this);
  const double start = time();
  const std::uint64_t start_tick = ticks();
  std::atomic<bool> stop{false};
  std::string why_stopped;
  const RunEnd end = runProfile(
      *this, commands, static_cast<long>(steps), static_cast<long>(steps), &stop,
      [&](const SimDriver& d) {
        if (d.ticks() % kHeldStepsCheckEvery != 0) return;
        why_stopped = stop_reason();
        if (!why_stopped.empty()) stop = true;
      },
      [](const SimDriver&) {});
  result.finished = end == RunEnd::kFinished;
  std::ostringstream msg;
  if (result.finished)
    msg << "advanced " << steps << " physics steps from t = " << formatNumber(start) << " s to "
        << formatNumber(time()) << " s";
  else if (end == RunEnd::kStopped)
    msg << "stopped after " << ticks() - start_tick << " of " << steps
        << " physics steps at t = " << formatNumber(time()) << " s: " << why_stopped
        << "; the state there is answered";
  else
    msg << "a physics step was refused after t = " << formatNumber(time())
        << " s (see the log); the state there is answered";
  if (std::abs(torque) > config_.command.torque_limit)
    msg << "; torque " << formatNumber(torque) << " N m clamped to the limit "
        << formatNumber(config_.command.torque_limit) << " N m";
  result.message = msg.str();
  return result;
}

}  // namespace kane_sim
