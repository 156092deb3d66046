// The lockstep protocol's bookkeeping, ROS-free but for ros::Time: which joint_states stamp
// awaits its answer, which torque_command_stamped answers it (the first; a second one from
// another controller, or with another torque, is said once), and what an answer that matches
// no published state is (late: a state already stepped past; unknown: a stamp this node never
// published, e.g. a controller that stamps with now()).
#ifndef KANE_SIM_NODES_LOOP_LOCKSTEP_GATE_H
#define KANE_SIM_NODES_LOOP_LOCKSTEP_GATE_H

#include <cstdint>
#include <deque>
#include <string>

#include <ros/time.h>

namespace kane_sim {

class LockstepGate {
 public:
  enum class Verdict {
    kApply,      // the first answer to the state awaiting one: apply it
    kDuplicate,  // a further answer to that state: dropped (warning() may say why)
    kLate,       // answers a state already stepped past: dropped
    kUnknown,    // answers no state this node published: dropped, warning() says so
  };

  // A state went out on joint_states with `stamp`: a new stamp awaits its answer (the same
  // stamp again, a repeat, changes nothing).
  void published(const ros::Time& stamp);

  // An answer from `caller` for the state stamped `stamp`, commanding `torque` [N m].
  Verdict answer(const ros::Time& stamp, const std::string& caller, double torque);

  // The state awaiting an answer got one (or the timeout released it); true before any state
  // went out (with sensors on, the first reading comes only after its latency).
  bool answered() const { return !has_state_ || answered_; }
  bool hasState() const { return has_state_; }
  void release() { answered_ = true; }

  const ros::Time& awaiting() const { return current_; }

  // What the last answer() has to say (a second controller, an unknown stamp), once per kind of
  // problem for a second controller and every time for an unknown stamp (the caller throttles);
  // "" when nothing.
  const std::string& warning() const { return warning_; }

  // Answers with an unknown stamp since the state awaiting one was published, and the last
  // such stamp: the timeout's message says that commands came but matched nothing.
  std::uint64_t unknownSinceState() const { return unknown_since_state_; }
  const ros::Time& lastUnknownStamp() const { return last_unknown_; }

  // What to say when no answer came within `timeout` [s] for the state at sim time `sim_time`:
  // that commands came but matched no published state (when they did), else that none came;
  // `zero` names the fallback (commanding 0 N m, else holding the last command).
  std::string timeoutReport(double sim_time, double timeout, bool zero) const;
  // How many recent stamps tell a late answer from an unknown one.
  static constexpr size_t kRecentStamps = 256;

 private:
  ros::Time current_;
  bool has_state_ = false;
  bool answered_ = false;
  std::string first_caller_;
  double first_torque_ = 0.0;
  bool warned_twice_ = false;
  std::deque<ros::Time> recent_;  // stamps published before current_, newest last
  std::string warning_;
  std::uint64_t unknown_since_state_ = 0;
  ros::Time last_unknown_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_LOOP_LOCKSTEP_GATE_H
