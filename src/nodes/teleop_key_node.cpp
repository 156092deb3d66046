#include "teleop_key_node.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <stdexcept>

#include <std_msgs/Float64.h>

#include "kane_sim/format_number.h"
#include "kane_sim/ros/node_params.h"

namespace kane_sim {

TeleopKeyParams readTeleopKeyParams(const ros::NodeHandle& pnh) {
  TeleopKeyParams params;
  TeleopSettings& settings = params.teleop;
  // Read as numbers here; their ranges are the key map's (validate) and the repeat rate's.
  settings.torque_step = numberParam(pnh, "torque_step", settings.torque_step);
  settings.torque_limit = numberParam(pnh, "torque_limit", settings.torque_limit);
  settings.setpoint_step = numberParam(pnh, "setpoint_step", settings.setpoint_step);
  params.repeat_rate = numberParam(pnh, "repeat_rate", params.repeat_rate);
  std::string mode = "torque";
  if (pnh.hasParam("mode") && !pnh.getParam("mode", mode))
    throw std::invalid_argument("parameter " + pnh.resolveName("mode") +
                                " must be the string torque or setpoint");
  if (mode != "torque" && mode != "setpoint")
    throw std::invalid_argument("parameter " + pnh.resolveName("mode") +
                                " must be torque or setpoint, got '" + mode + "'");
  settings.mode = mode == "torque" ? TeleopMode::kTorque : TeleopMode::kSetpoint;
  try {
    validate(settings);
    // More than a kHz of repeats is a flood (1e9 sent 648 000 messages in 6 s), not a keyboard.
    if (!(params.repeat_rate > 0 && params.repeat_rate <= kMaxRepeatRate))
      throw std::invalid_argument("repeat_rate must be in (0, 1000] Hz, got " +
                                  formatNumber(params.repeat_rate));
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("parameter " + pnh.getNamespace() + "/" + e.what());
  }
  return params;
}

TeleopKeyNode::TeleopKeyNode(const ros::NodeHandle& nh, const TeleopKeyParams& params)
    : nh_(nh), teleop_(params.teleop), repeat_period_(1.0 / params.repeat_rate) {
  torque_pub_ = nh_.advertise<std_msgs::Float64>("torque_command", 10);
  setpoint_pub_ = nh_.advertise<std_msgs::Float64>("setpoint", 10, /*latch=*/true);
  joint_state_sub_ = nh_.subscribe("joint_states", 10, &TeleopKeyNode::onJointState, this);
}

void TeleopKeyNode::onJointState(const sensor_msgs::JointState::ConstPtr& msg) {
  // joint_states' name of the crank (model/joint_names.h; teleop_key links no model library).
  const auto it = std::find(msg->name.begin(), msg->name.end(), "crank_joint");
  const size_t i = static_cast<size_t>(it - msg->name.begin());
  if (it != msg->name.end() && i < msg->position.size() && std::isfinite(msg->position[i]))
    teleop_.setCrankAngle(msg->position[i]);
}

void TeleopKeyNode::publishTorque() {
  std_msgs::Float64 msg;
  msg.data = teleop_.torque();
  torque_pub_.publish(msg);
  torque_sent_ = msg.data != 0.0;
  last_torque_ = std::chrono::steady_clock::now();
}

void TeleopKeyNode::publishSetpoint() {
  std_msgs::Float64 msg;
  msg.data = teleop_.setpoint();
  setpoint_pub_.publish(msg);
}

// On a terminal the status line is rewritten in place (carriage return, erase line); into a
// pipe or a file every line ends.
void TeleopKeyNode::show(const std::string& text, bool keep_line) {
  static const bool terminal = isatty(STDOUT_FILENO);
  if (terminal)
    std::cout << "\r\033[K" << text << (keep_line ? "" : "\n") << std::flush;
  else
    std::cout << text << (text.back() == '\n' ? "" : "\n") << std::flush;
}

void TeleopKeyNode::handle(TeleopEvent event) {
  switch (event) {
    case TeleopEvent::kTorqueChanged:
      publishTorque();
      break;
    case TeleopEvent::kSetpointChanged:
      publishSetpoint();
      break;
    case TeleopEvent::kModeChanged:
      show(teleop_.mode() == TeleopMode::kTorque
               ? "torque mode: publishing torque_command (stop pd_controller, or it fights back)"
               : "setpoint mode: publishing setpoint for pd_controller",
           false);
      teleop_.mode() == TeleopMode::kTorque ? publishTorque() : publishSetpoint();
      break;
    case TeleopEvent::kHelp:
      show(KeyTeleop::help(), false);
      break;
    case TeleopEvent::kStepChanged:
    case TeleopEvent::kQuit:
    case TeleopEvent::kNone:
      break;
  }
  show(teleop_.status(), true);
}

void TeleopKeyNode::run(KeyboardInput& keyboard, const std::atomic<bool>& stop) {
  show(KeyTeleop::help(), false);
  if (!keyboard.isTerminal())
    ROS_WARN(
        "teleop_key: stdin is not a terminal; reading keys from it as they come (end of "
        "input quits). Run it with rosrun in a terminal to drive by hand.");
  show(teleop_.status(), true);
  if (teleop_.mode() == TeleopMode::kSetpoint) publishSetpoint();
  KeyDecoder decoder;
  bool quit = false;
  while (!quit && !stop && ros::ok()) {
    const std::optional<std::string> bytes = keyboard.read(std::min(repeat_period_, 0.05));
    if (!bytes) break;
    for (const char byte : *bytes) {
      const std::optional<Key> key = decoder.feed(byte);
      if (!key) continue;
      const TeleopEvent event = teleop_.press(*key);
      if (event == TeleopEvent::kQuit) {
        quit = true;
        break;
      }
      handle(event);
    }
    // Hold the torque: the sim drops a command older than its timeout.
    const auto now = std::chrono::steady_clock::now();
    if (teleop_.mode() == TeleopMode::kTorque && torque_sent_ &&
        std::chrono::duration<double>(now - last_torque_).count() >= repeat_period_)
      publishTorque();
    ros::spinOnce();
  }
  std::cout << "\n";
  if (teleop_.mode() == TeleopMode::kTorque && torque_sent_ && ros::ok()) {
    std_msgs::Float64 zero;
    torque_pub_.publish(zero);
    ros::WallDuration(0.2).sleep();  // let it go out before the node shuts down
  }
}

}  // namespace kane_sim
