// crank_marker: an rviz interactive marker on the crank. Dragging its ring about the crank
// axis (the mechanism frame's z) publishes the angle as `setpoint` (std_msgs/Float64) for
// pd_controller; a setpoint published by anyone else (teleop_key, a script) moves the marker,
// so rviz always shows the setpoint in force. It starts at the controller's `setpoint`
// parameter (the controller named by ~controller_node, default pd_controller) or, when there is
// none, grabs the crank where it is: the first joint_states' crank angle is its first setpoint.
#ifndef KANE_SIM_NODES_CRANK_MARKER_NODE_H
#define KANE_SIM_NODES_CRANK_MARKER_NODE_H

#include <string>

#include <interactive_markers/interactive_marker_server.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Float64.h>
#include <visualization_msgs/InteractiveMarkerFeedback.h>

namespace kane_sim {

class CrankMarkerNode {
 public:
  // Reads ~frame_prefix (default: the sim node's frames/prefix, the sim node named by
  // ~sim_node, default kane_sim), ~controller_node and ~scale [m]; a bad one throws
  // std::invalid_argument.
  CrankMarkerNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh);

  static constexpr const char* kMarkerName = "crank";

 private:
  void onFeedback(const visualization_msgs::InteractiveMarkerFeedbackConstPtr& feedback);
  void onSetpoint(const ros::MessageEvent<const std_msgs::Float64>& event);
  void onJointState(const sensor_msgs::JointState::ConstPtr& msg);
  void moveMarker();
  void publishSetpoint(double setpoint);

  ros::NodeHandle nh_;
  std::string frame_;  // the mechanism frame: the crank turns about its z axis at its origin
  interactive_markers::InteractiveMarkerServer server_;
  ros::Publisher setpoint_pub_;
  ros::Subscriber setpoint_sub_;
  ros::Subscriber joint_state_sub_;
  double setpoint_ = 0.0;  // [rad] what the marker shows
  bool placed_ = false;    // set from joint_states, a setpoint or a drag
};

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_CRANK_MARKER_NODE_H
