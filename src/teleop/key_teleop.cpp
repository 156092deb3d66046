#include "kane_sim/teleop/key_teleop.h"
#include "kane_sim/format_number.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace kane_sim {
namespace {

void requirePositive(const char* field, double value) {
  if (!std::isfinite(value) || value <= 0)
    throw std::invalid_argument(std::string(field) + " must be finite and > 0, got " +
                                formatNumber(value));
}

// A step can be halved down to 1/64 of its start and doubled up to 64 times it (and, for the
// torque, up to the limit): enough range for fine and coarse driving, never 0 or unbounded.
constexpr double kStepRange = 64.0;

}  // namespace

void validate(const TeleopSettings& settings) {
  requirePositive("torque_step", settings.torque_step);
  requirePositive("torque_limit", settings.torque_limit);
  requirePositive("setpoint_step", settings.setpoint_step);
}

KeyTeleop::KeyTeleop(const TeleopSettings& settings)
    : settings_(settings),
      mode_(settings.mode),
      torque_step_(settings.torque_step),
      setpoint_step_(settings.setpoint_step) {
  validate(settings);
}

double& KeyTeleop::step() { return mode_ == TeleopMode::kTorque ? torque_step_ : setpoint_step_; }

double KeyTeleop::initialStep() const {
  return mode_ == TeleopMode::kTorque ? settings_.torque_step : settings_.setpoint_step;
}

void KeyTeleop::nudge(double direction) {
  if (mode_ == TeleopMode::kTorque)
    torque_ = std::clamp(torque_ + direction * torque_step_, -settings_.torque_limit,
                         settings_.torque_limit);
  else
    setpoint_ += direction * setpoint_step_;
}

TeleopEvent KeyTeleop::press(const Key& key) {
  const bool torque_mode = mode_ == TeleopMode::kTorque;
  const TeleopEvent changed =
      torque_mode ? TeleopEvent::kTorqueChanged : TeleopEvent::kSetpointChanged;
  const char c = key.code == Key::Code::kChar ? key.ch : 0;
  if (key.code == Key::Code::kRight || c == 'd') {
    nudge(+1.0);
    return changed;
  }
  if (key.code == Key::Code::kLeft || c == 'a') {
    nudge(-1.0);
    return changed;
  }
  if (key.code == Key::Code::kUp || c == 'w') {
    double upper = initialStep() * kStepRange;
    if (torque_mode) upper = std::min(upper, settings_.torque_limit);
    step() = std::min(step() * 2.0, upper);
    return TeleopEvent::kStepChanged;
  }
  if (key.code == Key::Code::kDown || c == 's') {
    step() = std::max(step() / 2.0, initialStep() / kStepRange);
    return TeleopEvent::kStepChanged;
  }
  switch (c) {
    case ' ':
      (torque_mode ? torque_ : setpoint_) = 0.0;
      return changed;
    case 't':
      if (torque_mode) return TeleopEvent::kNone;
      mode_ = TeleopMode::kTorque;
      torque_ = 0.0;
      return TeleopEvent::kModeChanged;
    case 'p':
      if (!torque_mode) return TeleopEvent::kNone;
      mode_ = TeleopMode::kSetpoint;
      if (crank_angle_) setpoint_ = *crank_angle_;
      return TeleopEvent::kModeChanged;
    case 'h':
    case '?':
      return TeleopEvent::kHelp;
    case 'q':
      return TeleopEvent::kQuit;
    default:
      return TeleopEvent::kNone;
  }
}

std::string KeyTeleop::status() const {
  char line[96];
  if (mode_ == TeleopMode::kTorque)
    std::snprintf(line, sizeof line, "torque mode: torque %+.3f N m (step %.4g N m)", torque_,
                  torque_step_);
  else
    std::snprintf(line, sizeof line, "setpoint mode: setpoint %+.3f rad (step %.4g rad)", setpoint_,
                  setpoint_step_);
  return line;
}

std::string KeyTeleop::help() {
  return "Drive the crank from the keyboard:\n"
         "  right / d : + step          up / w   : step x 2\n"
         "  left  / a : - step          down / s : step / 2\n"
         "  space     : torque 0 (torque mode) / setpoint 0 (setpoint mode)\n"
         "  t : torque mode (publishes torque_command)\n"
         "  p : setpoint mode (publishes setpoint for pd_controller; starts at the crank angle)\n"
         "  h : this help    q : quit (torque 0 first)\n";
}

}  // namespace kane_sim
