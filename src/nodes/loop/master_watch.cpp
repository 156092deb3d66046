#include "loop/master_watch.h"

#include <ros/master.h>
#include <ros/this_node.h>

namespace kane_sim {

MasterWatch::MasterWatch(PidQuery query, std::chrono::milliseconds period)
    : query_(std::move(query)), period_(period), thread_(&MasterWatch::watch, this) {}

MasterWatch::~MasterWatch() {
  stop_ = true;
  thread_.join();
}

void MasterWatch::observe(bool answered, int pid) {
  if (!answered) return;
  if (last_pid_ != -1 && pid != last_pid_) restarted_ = true;
  last_pid_ = pid;
}

bool MasterWatch::askMaster(int* pid) {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  if (!ros::master::execute("getPid", args, result, payload, false)) return false;
  *pid = payload;
  return true;
}

void MasterWatch::watch() {
  // Beside the physics loop: an XML-RPC call per second must not delay a tick. Sleeps in short
  // slices so that destruction (node shutdown) is prompt.
  constexpr auto kSlice = std::chrono::milliseconds(20);
  while (!stop_) {
    int pid = -1;
    const bool answered = query_(&pid);
    observe(answered, pid);
    for (auto slept = std::chrono::milliseconds(0); slept < period_ && !stop_; slept += kSlice)
      std::this_thread::sleep_for(std::min<std::chrono::milliseconds>(kSlice, period_ - slept));
  }
}

}  // namespace kane_sim
