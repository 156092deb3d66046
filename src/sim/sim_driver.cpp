#include "kane_sim/sim/sim_driver.h"

#include <cmath>
#include <cstdio>
#include <utility>

namespace kane_sim {

const char* const kSliderCrossingReport =
    "slider 4 passed through slider 3: the textbook example models no contact between the "
    "sliders (counted in slider_crossings; reported once per start or reset; contact.enabled "
    "stops it)";
namespace {

template <typename... Args>
std::string format(const char* fmt, Args... args) {
  char buffer[512];
  std::snprintf(buffer, sizeof(buffer), fmt, args...);
  return buffer;
}

// A position setpoint beyond a million turns is refused, like such a q1 in set_state.
constexpr double kMaxCrankAngle = Simulator::kMaxCrankAngle;  // [rad]
// A speed setpoint the integrator cannot follow is refused: half of set_state's 1 rad per step.
constexpr double kMaxServoTurnPerStep = 0.5;  // [rad]

}  // namespace

SimDriver::SimDriver(const Config& config, EventHandler on_event)
    : config_(config),
      sim_(config),
      command_(config.command),
      on_event_(std::move(on_event)),
      sensors_(config.sensors, config.simulation.physics_rate, config.simulation.publish_rate),
      servo_(config.command),
      setpoint_(initialSetpoint()),
      command_latency_ticks_(config.sensors.enabled ? physicsTicks(config.sensors.command_latency,
                                                                   config.simulation.physics_rate)
                                                    : 0) {
  applyCommand();
  sampleSensors();
}

double SimDriver::initialSetpoint() const {
  // Position: hold where it starts; velocity: stand still.
  return config_.command.mode == CommandMode::kPosition ? config_.initial_state.q1 : 0.0;
}

void SimDriver::updateServo(double dt) {
  const State& x = sim_.state();
  const double holding =
      config_.command.feedforward == Feedforward::kHolding ? sim_.model().holdingMoment(x) : 0.0;
  sim_.setTorque(servo_.update(setpoint_, x.q1, x.u1, holding, dt).command);
}

TorqueCommand::Verdict SimDriver::setpoint(double value) {
  record(DriverInput::Kind::kSetpoint, value);
  const std::string problem = setpointProblem(value);
  if (!problem.empty()) {
    report(SimEvent::Kind::kCommandRejected, problem + "; the last setpoint is kept");
    return TorqueCommand::Verdict::kRejected;
  }
  setpoint_ = value;
  updateServo(0.0);
  return TorqueCommand::Verdict::kAccepted;
}

std::string SimDriver::setpointProblem(double value) const {
  const char* unit = config_.command.mode == CommandMode::kPosition ? "rad" : "rad/s";
  std::string problem;
  if (!servoMode())
    problem =
        "command.mode is effort: servo_setpoint is not used (send torque_command, or set "
        "command.mode velocity or position)";
  else if (!std::isfinite(value))
    problem = format("servo_setpoint %g %s is not finite", value, unit);
  else if (config_.command.mode == CommandMode::kPosition && std::abs(value) > kMaxCrankAngle)
    problem = format("servo_setpoint %g rad is beyond a million turns", value);
  else if (config_.command.mode == CommandMode::kVelocity &&
           std::abs(value) * sim_.stepSize() > kMaxServoTurnPerStep)
    problem = format(
        "servo_setpoint %g rad/s would turn the crank more than %g rad per physics "
        "step (at most %g rad/s at %g Hz)",
        value, kMaxServoTurnPerStep, kMaxServoTurnPerStep / sim_.stepSize(),
        config_.simulation.physics_rate);
  return problem;
}
void SimDriver::applyCommand() {
  if (servoMode()) {
    updateServo(0.0);
    return;
  }
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
  record(DriverInput::Kind::kTorque, torque);
  if (servoMode()) {
    report(SimEvent::Kind::kCommandRejected,
           format("command.mode is %s: torque_command %g N m is ignored (send servo_setpoint in "
                  "%s)",
                  commandModeName(config_.command.mode), torque,
                  config_.command.mode == CommandMode::kPosition ? "rad" : "rad/s"));
    return TorqueCommand::Verdict::kRejected;
  }
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
    report(SimEvent::Kind::kFirstSliderCrossing, kSliderCrossingReport);
  if (!coarse_before && sim_.stepTooCoarse())
    report(SimEvent::Kind::kStepTooCoarse,
           format("the crank turns %.3f rad per physics step (u1 = %.1f rad/s): rk4 at %g Hz no "
                  "longer resolves the motion and energy is not conserved; use "
                  "simulation.integrator dopri5 or a higher simulation.physics_rate (reported "
                  "once per start or reset)",
                  std::abs(sim_.state().u1) * sim_.stepSize(), sim_.state().u1,
                  config_.simulation.physics_rate));
  if (servoMode()) {
    updateServo(sim_.stepSize());  // the drive's servo, once per physics step
  } else if (command_.lapsesAt(sim_.time())) {
    // The torque in force changes between commands only when the timeout lapses.
    applyCommand();
  }
  deliverDelayedCommands();
  sampleSensors();
  return true;
}

void SimDriver::reset() {
  record(DriverInput::Kind::kReset);
  sim_.reset();
  command_.reset();
  delayed_commands_.clear();
  setpoint_ = initialSetpoint();
  servo_.clearIntegral();
  applyCommand();
  sensors_.dropPending();
  sampleSensors();
}

Status SimDriver::setState(const State& state) {
  record(DriverInput::Kind::kSetState, 0.0, state);
  const Status result = sim_.setState(state);
  if (!result.ok) return result;
  servo_.clearIntegral();  // what it integrated belonged to the motion before
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
  servo_.setSettings(config.command);
  applyCommand();
}

void SimDriver::apply(const DriverInput& input) {
  switch (input.kind) {
    case DriverInput::Kind::kTorque:
      command(input.value);
      break;
    case DriverInput::Kind::kSetpoint:
      setpoint(input.value);
      break;
    case DriverInput::Kind::kReset:
      reset();
      break;
    case DriverInput::Kind::kSetState:
      setState(input.state);
      break;
  }
}

DriverCheckpoint SimDriver::checkpoint() const {
  DriverCheckpoint c;
  c.simulator = sim_.dynamics();
  c.command = command_.memory();
  c.delayed_commands = delayed_commands_;
  c.setpoint = setpoint_;
  c.servo_integral = servo_.integral();
  c.servo_status = servo_.status();
  c.sensors = sensors_.memory();
  return c;
}

void SimDriver::restore(const DriverCheckpoint& c) {
  const State& x = c.simulator.state;
  if (!(std::isfinite(x.q1) && std::isfinite(x.q2) && std::isfinite(x.u1) && std::isfinite(x.u2)))
    throw CheckpointError("the checkpoint's state is not finite (" + Simulator::stateText(x) + ")");
  if (!sensors_.enabled() && !c.sensors.queue.empty())
    throw CheckpointError(
        "the checkpoint has sensor readings in flight but this config's "
        "sensors are off: it is another config's checkpoint");
  if (command_latency_ticks_ == 0 && !c.delayed_commands.empty())
    throw CheckpointError(
        "the checkpoint has delayed commands but this config has no "
        "sensors.command_latency: it is another config's checkpoint");
  try {
    sensors_.restore(c.sensors);  // first: it alone can refuse its part
  } catch (const std::invalid_argument& e) {
    throw CheckpointError(std::string("the checkpoint's sensors: ") + e.what());
  }
  sim_.restore(c.simulator);
  command_.restore(c.command);
  delayed_commands_ = c.delayed_commands;
  setpoint_ = c.setpoint;
  servo_.restore(c.servo_integral, c.servo_status);
}

Snapshot SimDriver::snapshot() const {
  Snapshot snap = sim_.snapshot();
  snap.command.commanded = command_.commanded();
  snap.command.torque_limit = command_.torqueLimit();
  snap.command.timed_out = command_.timedOut();
  if (servoMode()) {
    snap.servo = servo_.status();
    snap.command.commanded = snap.servo.output;  // the servo's, before the limit
  }
  return snap;
}

}  // namespace kane_sim
