// What the node does with torque commands, kept free of ROS so it can be unit-tested:
// non-finite values are rejected, out-of-range ones clamped, and a silent commander times out.
#ifndef KANE_SIM_SIM_TORQUE_COMMAND_H
#define KANE_SIM_SIM_TORQUE_COMMAND_H

#include <string>

#include "kane_sim/config/config.h"

namespace kane_sim {

class TorqueCommand {
 public:
  enum class Verdict { kAccepted, kClamped, kRejected };

  explicit TorqueCommand(const CommandSettings& settings) : settings_(settings) {}

  // A new command at sim time `now` [s]. `message` explains a clamp or a rejection.
  Verdict receive(double torque, double now, std::string* message);

  // The torque to apply from sim time `now`: the clamped command, or 0 after a timeout.
  // `timed_out_now` is set true only on the call at which the timeout first takes effect.
  double applied(double now, bool* timed_out_now);
  // True when applied(now) would take the timeout into effect (its own test, inline: the
  // driver asks this at every step and calls applied() only then).
  bool lapsesAt(double now) const {
    return have_command_ && !timed_out_ && settings_.timeout > 0 &&
           now - last_command_time_ > settings_.timeout;
  }

  double commanded() const { return commanded_; }  // last accepted value, before clamping
  double torqueLimit() const { return settings_.torque_limit; }
  bool timedOut() const { return timed_out_; }
  void reset();  // back to no command, torque 0

  // What it remembers (sim/checkpoint.h): restored into one of the same settings, it goes on
  // as the original would.
  struct Memory {
    double commanded = 0.0, clamped = 0.0, last_command_time = 0.0;
    bool have_command = false, timed_out = false;
  };
  Memory memory() const {
    return {commanded_, clamped_, last_command_time_, have_command_, timed_out_};
  }
  void restore(const Memory& m) {
    commanded_ = m.commanded, clamped_ = m.clamped, last_command_time_ = m.last_command_time;
    have_command_ = m.have_command, timed_out_ = m.timed_out;
  }
  // New limit and timeout (runtime reconfiguration): the last command is clamped anew.
  void setSettings(const CommandSettings& settings);

 private:
  CommandSettings settings_;
  double commanded_ = 0.0;
  double clamped_ = 0.0;
  double last_command_time_ = 0.0;
  bool have_command_ = false;
  bool timed_out_ = false;
};

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_TORQUE_COMMAND_H
