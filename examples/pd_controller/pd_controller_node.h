// Example of commanding the virtual robot from another node: a PD position controller for the
// crank. Reads joint_states, publishes torque_command on every crank reading.
#ifndef KANE_SIM_EXAMPLES_PD_CONTROLLER_NODE_H
#define KANE_SIM_EXAMPLES_PD_CONTROLLER_NODE_H

#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Float64.h>

#include "pd_law.h"

namespace kane_sim {

class PdControllerNode {
 public:
  // Throws std::invalid_argument naming a bad parameter (kp, kd, torque_limit, setpoint).
  PdControllerNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh);

 private:
  void onJointState(const sensor_msgs::JointState::ConstPtr& msg);
  void onSetpoint(const std_msgs::Float64::ConstPtr& msg);

  ros::NodeHandle nh_;
  PdGains gains_;
  double setpoint_ = 0.0;  // [rad] q1 to hold
  ros::Subscriber joint_state_sub_;
  ros::Subscriber setpoint_sub_;
  ros::Publisher torque_pub_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_EXAMPLES_PD_CONTROLLER_NODE_H
