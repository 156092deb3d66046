// pd_controller: example crank position controller for kane_sim_node.
#include <stdexcept>

#include <ros/ros.h>

#include "kane_sim/ros/shutdown_signals.h"
#include "pd_controller_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "pd_controller", ros::init_options::NoSigintHandler);
  kane_sim::installShutdownSignalHandlers();
  // Held outside the try: destroying the last NodeHandle shuts ROS (and its logging) down, and
  // the fatal message below must still reach the console.
  const ros::NodeHandle nh;
  const ros::NodeHandle private_nh("~");
  try {
    kane_sim::PdControllerNode node{nh, private_nh};
    ros::spin();
  } catch (const std::invalid_argument& e) {
    ROS_FATAL("pd_controller: %s", e.what());
    return 1;
  }
  return 0;
}
