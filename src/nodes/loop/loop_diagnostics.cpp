#include "loop/loop_diagnostics.h"

#include <sstream>

#include <diagnostic_msgs/KeyValue.h>

namespace kane_sim {

diagnostic_msgs::DiagnosticStatus LoopDiagnostics::close(const LoopStats::Summary& s,
                                                         double wall_window,
                                                         const LoopState& loop) {
  diagnostic_msgs::DiagnosticStatus status;
  status.name = "kane_sim: physics loop (" + loop.node_name + ")";
  status.hardware_id = "kane_sim" + loop.node_namespace;
  const bool on_time = !health_.update(s);
  status.level = (loop.paused || on_time) ? diagnostic_msgs::DiagnosticStatus::OK
                                          : diagnostic_msgs::DiagnosticStatus::WARN;
  std::ostringstream msg;
  if (steps_refused_ > 0) {
    status.level = diagnostic_msgs::DiagnosticStatus::ERROR;
    msg << "physics stalled: " << steps_refused_
        << " steps refused (the last good state is published); lower the torque or call reset. "
        << last_refusal_;
  } else if (loop.stopped_at_time_limit) {
    msg << "stopped: sim time reached the largest stampable value; restart the node";
  } else if (loop.paused) {
    msg << "paused";
  } else if (on_time) {
    msg << "on schedule" << (health_.consecutiveLateWindows() > 0 ? " (some ticks late)" : "");
  } else {
    msg << "behind schedule for " << health_.consecutiveLateWindows() << " s: " << s.overruns
        << " of " << s.ticks << " ticks overran, " << s.skipped << " s lag dropped";
  }
  status.message = msg.str();
  auto add = [&status](const std::string& key, double value) {
    diagnostic_msgs::KeyValue kv;
    kv.key = key;
    std::ostringstream v;
    v << value;
    kv.value = v.str();
    status.values.push_back(kv);
  };
  add("physics rate achieved [Hz]", s.physics_rate);
  add("physics rate target [Hz]", loop.paused ? 0.0 : loop.physics_rate * loop.real_time_factor);
  add("real-time factor achieved", s.real_time_factor);
  add("real-time factor target", loop.real_time_factor);
  add("tick lateness p50 [us]", s.lateness_p50 * 1e6);
  add("tick lateness p99 [us]", s.lateness_p99 * 1e6);
  add("tick lateness max [us]", s.lateness_max * 1e6);
  add("overruns", static_cast<double>(s.overruns));
  add("ticks", static_cast<double>(s.ticks));
  add("lag dropped [s]", s.skipped);
  add("sim time [s]", loop.sim_time);
  add("torque commands received [1/s]", wall_window > 0 ? commands_ / wall_window : 0.0);
  add("torque commands rejected or clamped", static_cast<double>(commands_refused_));
  add("physics steps refused", static_cast<double>(steps_refused_));
  add("lockstep timeouts", static_cast<double>(lockstep_timeouts_));
  if (lockstep_timeouts_ > 0 && status.level == diagnostic_msgs::DiagnosticStatus::OK) {
    status.level = diagnostic_msgs::DiagnosticStatus::WARN;
    status.message += "; lockstep: " + std::to_string(lockstep_timeouts_) +
                      " states got no torque_command_stamped in time (fallback applied)";
  }
  commands_ = commands_refused_ = steps_refused_ = lockstep_timeouts_ = 0;
  return status;
}

}  // namespace kane_sim
