#include "loop/lockstep_gate.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include "kane_sim/format_number.h"

namespace kane_sim {
namespace {

std::string stampText(const ros::Time& t) {
  std::ostringstream out;
  out << t.sec << "." << std::string(9 - std::to_string(t.nsec).size(), '0') << t.nsec;
  return out.str();
}

}  // namespace

void LockstepGate::published(const ros::Time& stamp) {
  if (has_state_ && stamp == current_) return;
  if (has_state_) {
    recent_.push_back(current_);
    if (recent_.size() > kRecentStamps) recent_.pop_front();
  }
  current_ = stamp;
  has_state_ = true;
  answered_ = false;
  first_caller_.clear();
  unknown_since_state_ = 0;
}

LockstepGate::Verdict LockstepGate::answer(const ros::Time& stamp, const std::string& caller,
                                           double torque) {
  warning_.clear();
  if (has_state_ && stamp == current_) {
    if (!answered_ || first_caller_.empty()) {
      if (answered_) return Verdict::kDuplicate;  // released by the timeout: too late for it
      answered_ = true;
      first_caller_ = caller;
      first_torque_ = torque;
      return Verdict::kApply;
    }
    // The same controller answering a repeat of the state with the same torque is no news.
    const bool same = caller == first_caller_ && torque == first_torque_;
    if (!same && !warned_twice_) {
      warned_twice_ = true;
      warning_ = "lockstep: " + caller + " answered the state stamped " + stampText(stamp) +
                 " with " + formatNumber(torque) + " N m after " + first_caller_ +
                 " answered it with " + formatNumber(first_torque_) +
                 " N m; the first answer is applied (said once: two controllers answer "
                 "torque_command_stamped)";
    }
    return Verdict::kDuplicate;
  }
  if (std::find(recent_.begin(), recent_.end(), stamp) != recent_.end()) return Verdict::kLate;
  ++unknown_since_state_;
  last_unknown_ = stamp;
  warning_ = "lockstep: torque_command_stamped from " + caller + " stamped " + stampText(stamp) +
             " matches no joint_states this node published (the state awaiting an answer is "
             "stamped " +
             stampText(current_) +
             "): copy the header.stamp of the joint_states message you answer, do not stamp "
             "with now()";
  return Verdict::kUnknown;
}

std::string LockstepGate::timeoutReport(double sim_time, double timeout, bool zero) const {
  const char* fallback = zero ? "commanding 0 N m" : "holding the last command";
  char text[512];
  if (unknown_since_state_ > 0)
    std::snprintf(text, sizeof text,
                  "lockstep: %llu torque_command_stamped arrived for the state at t = %.6f s "
                  "(stamped %.9f) but matched no published state (the last stamped %.9f): "
                  "controllers must copy the joint_states stamp; %s and stepping on",
                  static_cast<unsigned long long>(unknown_since_state_), sim_time, current_.toSec(),
                  last_unknown_.toSec(), fallback);
  else
    std::snprintf(text, sizeof text,
                  "lockstep: no torque_command_stamped for the state at t = %.6f s within %g s; "
                  "%s and stepping on",
                  sim_time, timeout, fallback);
  return text;
}

}  // namespace kane_sim
