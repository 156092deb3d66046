#include "pd_controller_node.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "kane_sim/ros/node_params.h"

namespace kane_sim {

PdControllerNode::PdControllerNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh)
    : nh_(nh) {
  const PdGains defaults;
  gains_.kp = boundedParam(private_nh, "kp", defaults.kp, ParamBound::kNonNegative);
  gains_.kd = boundedParam(private_nh, "kd", defaults.kd, ParamBound::kNonNegative);
  gains_.torque_limit =
      boundedParam(private_nh, "torque_limit", defaults.torque_limit, ParamBound::kNonNegative);
  setpoint_ = boundedParam(private_nh, "setpoint", 0.0, ParamBound::kAnyFinite);
  torque_pub_ = nh_.advertise<std_msgs::Float64>("torque_command", 10);
  joint_state_sub_ = nh_.subscribe("joint_states", 10, &PdControllerNode::onJointState, this,
                                   ros::TransportHints().tcpNoDelay());
  setpoint_sub_ = nh_.subscribe("setpoint", 10, &PdControllerNode::onSetpoint, this);
  ROS_INFO("pd_controller: holding crank_joint at %g rad (kp %g N m/rad, kd %g N m s/rad)",
           setpoint_, gains_.kp, gains_.kd);
}

void PdControllerNode::onJointState(const sensor_msgs::JointState::ConstPtr& msg) {
  const auto it = std::find(msg->name.begin(), msg->name.end(), "crank_joint");
  const size_t i = static_cast<size_t>(it - msg->name.begin());
  if (it == msg->name.end() || i >= msg->position.size() || i >= msg->velocity.size()) {
    ROS_WARN_THROTTLE(5.0, "pd_controller: joint_states without crank_joint position and velocity");
    return;
  }
  std_msgs::Float64 torque;
  torque.data = pdTorque(gains_, setpoint_, msg->position[i], msg->velocity[i]);
  if (std::isfinite(torque.data)) torque_pub_.publish(torque);
}

void PdControllerNode::onSetpoint(const std_msgs::Float64::ConstPtr& msg) {
  if (!std::isfinite(msg->data)) {
    ROS_WARN("pd_controller: setpoint %g is not finite: keeping %g rad", msg->data, setpoint_);
    return;
  }
  setpoint_ = msg->data;
  // Debug level: an interactive marker being dragged sends tens of setpoints a second.
  ROS_DEBUG("pd_controller: new setpoint %g rad", setpoint_);
}

}  // namespace kane_sim
