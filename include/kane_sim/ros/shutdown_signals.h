// SIGINT and SIGTERM both end a node cleanly (roscpp handles only SIGINT by itself): the loop
// sees ros::ok() turn false, returns, and the process exits 0.
#ifndef KANE_SIM_ROS_SHUTDOWN_SIGNALS_H
#define KANE_SIM_ROS_SHUTDOWN_SIGNALS_H

#include <csignal>

#include <ros/ros.h>

namespace kane_sim {

inline void requestShutdownOnSignal(int) { ros::requestShutdown(); }

// Call right after ros::init(..., ros::init_options::NoSigintHandler).
inline void installShutdownSignalHandlers() {
  std::signal(SIGINT, requestShutdownOnSignal);
  std::signal(SIGTERM, requestShutdownOnSignal);
}

}  // namespace kane_sim

#endif  // KANE_SIM_ROS_SHUTDOWN_SIGNALS_H
