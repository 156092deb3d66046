// Notices a restarted ROS master: roscpp registers topics and services once, and a new master
// knows nothing of them. A background thread asks the master's pid once a second; a different
// pid means a restart, which `restarted()` reports once. The question is injected, so the
// logic is unit-tested without a master.
#ifndef KANE_SIM_NODES_LOOP_MASTER_WATCH_H
#define KANE_SIM_NODES_LOOP_MASTER_WATCH_H

#include <atomic>
#include <chrono>
#include <functional>
#include <thread>

namespace kane_sim {

class MasterWatch {
 public:
  // Writes the master's pid and returns true when it answered.
  using PidQuery = std::function<bool(int* pid)>;

  // Watches until destroyed; `period` between questions.
  explicit MasterWatch(PidQuery query = askMaster,
                       std::chrono::milliseconds period = std::chrono::milliseconds(1000));
  ~MasterWatch();
  MasterWatch(const MasterWatch&) = delete;
  MasterWatch& operator=(const MasterWatch&) = delete;

  // True once after each restart seen.
  bool restarted() { return restarted_.exchange(false); }

  // getPid over XML-RPC (ros::master::execute).
  static bool askMaster(int* pid);

 private:
  void watch();
  // One answer. An unanswered question changes nothing (a master that is down is not a new one
  // yet).
  void observe(bool answered, int pid);

  PidQuery query_;
  std::chrono::milliseconds period_;
  int last_pid_ = -1;
  std::atomic<bool> restarted_{false};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_LOOP_MASTER_WATCH_H
