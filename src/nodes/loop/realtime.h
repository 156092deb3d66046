// Real-time scheduling for the physics loop's thread: SCHED_FIFO at a priority, memory locked
// (mlockall) so no page fault stalls a tick. Needs privileges (root, CAP_SYS_NICE, or an
// rtprio limit: /etc/security/limits.conf `@realtime - rtprio 99`, `@realtime - memlock
// unlimited`); without them the loop runs as before and the caller says why.
#ifndef KANE_SIM_NODES_LOOP_REALTIME_H
#define KANE_SIM_NODES_LOOP_REALTIME_H

#include <string>

namespace kane_sim {

struct RealtimeResult {
  bool scheduled = false;  // the calling thread now runs SCHED_FIFO at the priority
  bool memory_locked = false;
  std::string problem;  // "" when both succeeded; else what was refused and how to allow it
};

// For the calling thread (the other threads keep their policy). priority in [1, 99].
RealtimeResult makeRealtime(int priority);

// simulation.realtime_priority as the node applies it to its physics loop: nothing at 0; not
// with real_time_factor 0 (a loop that never sleeps would hold a core at real-time priority).
// `report` is the line to log ("" for none), `warn` its level.
struct RealtimePolicy {
  bool scheduled = false;
  bool warn = false;
  std::string report;
};
RealtimePolicy applyRealtimePolicy(int priority, double real_time_factor);

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_LOOP_REALTIME_H
