#include "loop/realtime.h"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstring>

namespace kane_sim {

RealtimeResult makeRealtime(int priority) {
  RealtimeResult r;
  sched_param param{};
  param.sched_priority = priority;
  const int sched_error = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  r.scheduled = sched_error == 0;
  if (!r.scheduled)
    r.problem = "SCHED_FIFO priority " + std::to_string(priority) + " refused (" +
                std::strerror(sched_error) +
                "): run as root, or give the user an rtprio limit (/etc/security/limits.conf: "
                "'@realtime - rtprio 99') or CAP_SYS_NICE";
  if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) {
    r.memory_locked = true;
  } else {
    const int lock_error = errno;
    r.problem += std::string(r.problem.empty() ? "" : "; ") + "mlockall refused (" +
                 std::strerror(lock_error) +
                 "): raise the memlock limit ('@realtime - memlock unlimited') or run as root";
  }
  return r;
}

RealtimePolicy applyRealtimePolicy(int priority, double real_time_factor) {
  RealtimePolicy policy;
  const std::string setting = "simulation.realtime_priority " + std::to_string(priority);
  if (priority <= 0) return policy;
  policy.warn = true;
  if (real_time_factor == 0.0) {
    policy.report = setting +
                    " ignored: with real_time_factor 0 the loop never sleeps, and at real-time "
                    "priority it would hold a core from everything else";
    return policy;
  }
  const RealtimeResult r = makeRealtime(priority);
  policy.scheduled = r.scheduled;
  policy.warn = !r.problem.empty();
  policy.report = policy.warn ? setting + ": " + r.problem + "; " +
                                    (r.scheduled ? "the loop runs SCHED_FIFO without locked memory"
                                                 : "the loop runs at normal priority")
                              : "physics loop at SCHED_FIFO priority " + std::to_string(priority) +
                                    ", memory locked";
  return policy;
}

}  // namespace kane_sim
