// pd_controller: example crank position controller for kane_sim_node.
#include <stdexcept>

#include <ros/ros.h>

#include "kane_sim/pd_controller_node.h"
#include "kane_sim/shutdown_signals.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "pd_controller", ros::init_options::NoSigintHandler);
  kane_sim::installShutdownSignalHandlers();
  try {
    kane_sim::PdControllerNode node{ros::NodeHandle(), ros::NodeHandle("~")};
    ros::spin();
  } catch (const std::invalid_argument& e) {
    ROS_FATAL("pd_controller: %s", e.what());
    return 1;
  }
  return 0;
}
