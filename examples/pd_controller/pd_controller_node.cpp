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
  gains_.ki = boundedParam(private_nh, "ki", defaults.ki, ParamBound::kNonNegative);
  setpoint_ = boundedParam(private_nh, "setpoint", 0.0, ParamBound::kAnyFinite);
  // ~stamped: answer each reading on torque_command_stamped with its stamp, which lockstep
  // (simulation.lockstep) waits for; else the plain torque_command.
  stamped_ = flagParam(private_nh, "stamped", false);
  torque_pub_ = stamped_ ? nh_.advertise<TorqueCommandStamped>("torque_command_stamped", 10)
                         : nh_.advertise<std_msgs::Float64>("torque_command", 10);
  joint_state_sub_ = nh_.subscribe("joint_states", 10, &PdControllerNode::onJointState, this,
                                   ros::TransportHints().tcpNoDelay());
  setpoint_sub_ = nh_.subscribe("setpoint", 10, &PdControllerNode::onSetpoint, this);
  // The simulator's private topic, beside it in this namespace (/kane_sim/reset_event, or
  // /robot_a/kane_sim/reset_event under ns robot_a); remap `kane_sim/reset_event` for another.
  reset_event_sub_ =
      nh_.subscribe("kane_sim/reset_event", 10, &PdControllerNode::onResetEvent, this);
  ROS_INFO(
      "pd_controller: holding crank_joint at %g rad (kp %g N m/rad, kd %g N m s/rad, ki %g N "
      "m/(rad s))",
      setpoint_, gains_.kp, gains_.kd, gains_.ki);
}

void PdControllerNode::onJointState(const sensor_msgs::JointState::ConstPtr& msg) {
  const auto it = std::find(msg->name.begin(), msg->name.end(), "crank_joint");
  const size_t i = static_cast<size_t>(it - msg->name.begin());
  if (it == msg->name.end() || i >= msg->position.size() || i >= msg->velocity.size()) {
    ROS_WARN_THROTTLE(5.0, "pd_controller: joint_states without crank_joint position and velocity");
    return;
  }
  const double q1 = msg->position[i];
  if (!last_sample_.isZero())
    integral_.add(gains_, setpoint_ - q1, (msg->header.stamp - last_sample_).toSec());
  last_sample_ = msg->header.stamp;
  const double torque = pdTorque(gains_, setpoint_, q1, msg->velocity[i], integral_.value());
  if (!std::isfinite(torque)) return;
  if (stamped_) {
    TorqueCommandStamped answer;
    answer.header.stamp = msg->header.stamp;  // the state this answers
    answer.torque = torque;
    torque_pub_.publish(answer);
  } else {
    std_msgs::Float64 plain;
    plain.data = torque;
    torque_pub_.publish(plain);
  }
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

void PdControllerNode::onResetEvent(const ResetEvent::ConstPtr& msg) {
  // The motion the integral summed is gone: start it afresh from the moved state.
  integral_.clear();
  last_sample_ = msg->header.stamp;
  ROS_INFO("pd_controller: the mechanism was moved (%s at t = %.3f s): integral cleared",
           msg->cause.c_str(), msg->sim_time);
}

}  // namespace kane_sim
