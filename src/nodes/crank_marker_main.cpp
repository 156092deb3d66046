// crank_marker: set pd_controller's setpoint by dragging the crank in rviz.
//   rosrun kane_sim crank_marker [_frame_prefix:=P] [_scale:=0.6]
#include <stdexcept>

#include <ros/ros.h>

#include "kane_sim/ros/node_main.h"

#include "crank_marker_node.h"
#include "kane_sim/ros/shutdown_signals.h"

namespace {
constexpr const char* kUsage =
    "Usage: rosrun kane_sim crank_marker [_frame_prefix:=P] [_scale:=0.6] [_sim_node:=kane_sim]\n"
    "                                    [_controller_node:=pd_controller]\n\n"
    "An rviz interactive marker on the crank: dragging its ring publishes the angle as\n"
    "`setpoint` for pd_controller (update topic crank_marker/update).\n";
}  // namespace

int main(int argc, char** argv) {
  kane_sim::exitOnHelp(argc, argv, kUsage);
  kane_sim::initNode(argc, argv, "crank_marker", ros::init_options::NoSigintHandler);
  kane_sim::installShutdownSignalHandlers();
  // Held outside the try: the fatal message below must still reach the console.
  const ros::NodeHandle nh;
  const ros::NodeHandle private_nh("~");
  try {
    kane_sim::CrankMarkerNode node{nh, private_nh};
    ros::spin();
  } catch (const std::invalid_argument& e) {
    ROS_FATAL("crank_marker: %s", e.what());
    return 1;
  }
  return 0;
}
