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

}  // namespace kane_sim
