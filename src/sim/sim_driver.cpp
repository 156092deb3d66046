#include "kane_sim/sim/sim_driver.h"

#include <cmath>
#include <cstdio>
#include <utility>

namespace kane_sim {
namespace {

template <typename... Args>
std::string format(const char* fmt, Args... args) {
  char buffer[512];
  std::snprintf(buffer, sizeof(buffer), fmt, args...);
  return buffer;
}

}  // namespace

SimDriver::SimDriver(const Config& config, EventHandler on_event)
    : config_(config),
      sim_(config),
      command_(config.command),
      on_event_(std::move(on_event)),
      sensors_(config.sensors, config.simulation.physics_rate, config.simulation.publish_rate),
      command_latency_ticks_(config.sensors.enabled ? physicsTicks(config.sensors.command_latency,
                                                                   config.simulation.physics_rate)
                                                    : 0) {
  sampleSensors();
}

void SimDriver::applyCommand() {
  bool timed_out_now = false;
  const double torque = command_.applied(sim_.time(), &timed_out_now);
  if (timed_out_now)
    report(SimEvent::Kind::kCommandTimedOut,
           format("no torque_command for %g s (command.timeout): applying 0 N m until the next "
                  "command",
                  config_.command.timeout));
  sim_.setTorque(torque);  // finite and clamped by TorqueCommand
}

void SimDriver::report(SimEvent::Kind kind, std::string message) const {
  if (on_event_) on_event_(SimEvent{kind, sim_.time(), std::move(message)});
}

TorqueCommand::Verdict SimDriver::command(double torque) {
  if (command_latency_ticks_ == 0 || !std::isfinite(torque)) return receive(torque);
  delayed_commands_.push_back({sim_.ticks() + command_latency_ticks_, torque});
  return std::abs(torque) > command_.torqueLimit() ? TorqueCommand::Verdict::kClamped
                                                   : TorqueCommand::Verdict::kAccepted;
}

void SimDriver::deliverDelayedCommands() {
  while (!delayed_commands_.empty() && delayed_commands_.front().due_tick <= sim_.ticks()) {
    receive(delayed_commands_.front().torque);
    delayed_commands_.pop_front();
  }
}

TorqueCommand::Verdict SimDriver::receive(double torque) {
  std::string message;
  const TorqueCommand::Verdict verdict = command_.receive(torque, sim_.time(), &message);
  if (verdict == TorqueCommand::Verdict::kRejected)
    report(SimEvent::Kind::kCommandRejected, std::move(message));
  else if (verdict == TorqueCommand::Verdict::kClamped)
    report(SimEvent::Kind::kCommandClamped, std::move(message));
  applyCommand();
  return verdict;
}

bool SimDriver::step() {
  const std::uint64_t crossings_before = sim_.sliderCrossings();
  const bool coarse_before = sim_.stepTooCoarse();
  const Status result = sim_.step();
  if (!result.ok) {
    report(SimEvent::Kind::kStepRefused, result.error);
    return false;
  }
  if (crossings_before == 0 && sim_.sliderCrossings() > 0)
    report(SimEvent::Kind::kFirstSliderCrossing,
           format("slider 4 passed through slider 3: the textbook example models no contact "
                  "between the sliders (counted in slider_crossings; reported once per start or "
                  "reset; contact.enabled stops it)"));
  if (!coarse_before && sim_.stepTooCoarse())
    report(SimEvent::Kind::kStepTooCoarse,
           format("the crank turns %.3f rad per physics step (u1 = %.1f rad/s): rk4 at %g Hz no "
                  "longer resolves the motion and energy is not conserved; use "
                  "simulation.integrator dopri5 or a higher simulation.physics_rate (reported "
                  "once per start or reset)",
                  std::abs(sim_.state().u1) * sim_.stepSize(), sim_.state().u1,
                  config_.simulation.physics_rate));
  // The torque in force changes between commands only when the timeout lapses.
  if (command_.lapsesAt(sim_.time())) applyCommand();
  deliverDelayedCommands();
  sampleSensors();
  return true;
}

void SimDriver::reset() {
  sim_.reset();
  command_.reset();
  delayed_commands_.clear();
  applyCommand();
  sensors_.dropPending();
  sampleSensors();
}

Status SimDriver::setState(const State& state) {
  const Status result = sim_.setState(state);
  if (!result.ok) return result;
  applyCommand();
  sensors_.dropPending();
  sampleSensors();
  return result;
}

void SimDriver::reconfigure(const Config& config) {
  const MechanismParameters& next = config.mechanism;
  // Masses, k, g, damping, the motor line (its stall torque is command.torque_limit), contact.
  if (next != config_.mechanism) sim_.setParameters(next);
  config_.mechanism = next;
  config_.command = config.command;
  command_.setSettings(config.command);
  applyCommand();
}

Snapshot SimDriver::snapshot() const {
  Snapshot snap = sim_.snapshot();
  snap.command.commanded = command_.commanded();
  snap.command.torque_limit = command_.torqueLimit();
  snap.command.timed_out = command_.timedOut();
  return snap;
}

}  // namespace kane_sim
