// teleop_key: drives the crank from the keyboard (the key map is KeyTeleop's). Torque mode
// publishes torque_command, repeated at ~repeat_rate so the sim's command timeout never lapses
// while a key's torque is meant to hold; setpoint mode publishes setpoint (latched) for
// pd_controller. joint_states gives the crank angle setpoint mode starts from.
#ifndef KANE_SIM_NODES_TELEOP_KEY_NODE_H
#define KANE_SIM_NODES_TELEOP_KEY_NODE_H

#include <atomic>
#include <chrono>
#include <string>

#include <ros/ros.h>
#include <sensor_msgs/JointState.h>

#include "kane_sim/teleop/key_teleop.h"
#include "keyboard_input.h"

namespace kane_sim {

struct TeleopKeyParams {
  TeleopSettings teleop;
  double repeat_rate = 20.0;  // [Hz] torque repeats; well above 1 / command.timeout (0.5 s)
};
constexpr double kMaxRepeatRate = 1000.0;  // [Hz]

// Reads ~mode (torque|setpoint), ~torque_step, ~torque_limit, ~setpoint_step, ~repeat_rate; a
// bad one throws std::invalid_argument naming the parameter and its value.
TeleopKeyParams readTeleopKeyParams(const ros::NodeHandle& private_nh);

class TeleopKeyNode {
 public:
  TeleopKeyNode(const ros::NodeHandle& nh, const TeleopKeyParams& params);

  // Reads keys until q, end of input or `stop`; commands torque 0 before returning when it was
  // commanding torque.
  void run(KeyboardInput& keyboard, const std::atomic<bool>& stop);

 private:
  void handle(TeleopEvent event);
  void publishTorque();
  void publishSetpoint();
  void show(const std::string& text, bool keep_line);
  void onJointState(const sensor_msgs::JointState::ConstPtr& msg);

  ros::NodeHandle nh_;
  KeyTeleop teleop_;
  double repeat_period_;  // [s]
  ros::Publisher torque_pub_;
  ros::Publisher setpoint_pub_;
  ros::Subscriber joint_state_sub_;
  bool torque_sent_ = false;  // a torque went out since the last torque 0
  std::chrono::steady_clock::time_point last_torque_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_TELEOP_KEY_NODE_H
