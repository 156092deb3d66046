#include "kane_sim/sim/torque_command.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace kane_sim {

TorqueCommand::Verdict TorqueCommand::receive(double torque, double now, std::string* message) {
  // Messages are formatted only for refused or clamped commands: accepted ones, the normal
  // case at up to kHz rates, cost no string work.
  if (!std::isfinite(torque)) {
    std::ostringstream msg;
    msg << "torque_command " << torque << " N m is not finite: ignored, still applying " << clamped_
        << " N m";
    *message = msg.str();
    return Verdict::kRejected;
  }
  commanded_ = torque;
  clamped_ = std::clamp(torque, -settings_.torque_limit, settings_.torque_limit);
  last_command_time_ = now;
  have_command_ = true;
  timed_out_ = false;
  if (clamped_ != torque) {
    std::ostringstream msg;
    msg << "torque_command " << torque << " N m exceeds command.torque_limit "
        << settings_.torque_limit << " N m: clamped to " << clamped_ << " N m";
    *message = msg.str();
    return Verdict::kClamped;
  }
  message->clear();
  return Verdict::kAccepted;
}

double TorqueCommand::applied(double now, bool* timed_out_now) {
  *timed_out_now = false;
  if (!have_command_) return 0.0;
  if (lapsesAt(now)) {
    timed_out_ = true;
    *timed_out_now = true;
  }
  return timed_out_ ? 0.0 : clamped_;
}

void TorqueCommand::reset() {
  commanded_ = clamped_ = last_command_time_ = 0.0;
  have_command_ = timed_out_ = false;
}

void TorqueCommand::setSettings(const CommandSettings& settings) {
  settings_ = settings;
  clamped_ = std::clamp(commanded_, -settings_.torque_limit, settings_.torque_limit);
}

}  // namespace kane_sim
