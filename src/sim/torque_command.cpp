#include "kane_sim/sim/torque_command.h"
#include "kane_sim/format_number.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace kane_sim {

TorqueCommand::Verdict TorqueCommand::receive(double torque, double now, std::string* message) {
  // Messages are formatted only for refused or clamped commands: accepted ones, the normal
  // case at up to kHz rates, cost no string work.
  if (!std::isfinite(torque)) {
    // What is applied now: the last command, or 0 once its timeout has lapsed.
    const double applying = timed_out_ || lapsesAt(now) ? 0.0 : clamped_;
    *message = "torque_command " + formatNumber(torque) + " N m is not finite: ignored, applying " +
               formatNumber(applying) + " N m" +
               (applying != clamped_ ? " (the last command timed out)" : "");
    return Verdict::kRejected;
  }
  commanded_ = torque;
  clamped_ = std::clamp(torque, -settings_.torque_limit, settings_.torque_limit);
  last_command_time_ = now;
  have_command_ = true;
  timed_out_ = false;
  if (clamped_ != torque) {
    *message = "torque_command " + formatNumber(torque) + " N m exceeds command.torque_limit " +
               formatNumber(settings_.torque_limit) + " N m: clamped to " + formatNumber(clamped_) +
               " N m";
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
