// teleop_key: drive the crank from the keyboard, in the spirit of turtle_teleop_key.
//   rosrun kane_sim teleop_key [_mode:=setpoint] [_torque_step:=0.5] [_setpoint_step:=0.1]
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <stdexcept>

#include <ros/ros.h>

#include "keyboard_input.h"
#include "teleop_key_node.h"

namespace {

// SIGINT (Ctrl-C), SIGTERM and SIGHUP (terminal closed) end the key loop, not ROS: the node
// still commands torque 0 before it goes.
std::atomic<bool> g_stop{false};
void stopOnSignal(int) { g_stop = true; }

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "teleop_key", ros::init_options::NoSigintHandler);
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) std::signal(signal, stopOnSignal);
  // Held outside the try: the fatal message below must still reach the console.
  const ros::NodeHandle nh;
  const ros::NodeHandle private_nh("~");
  try {
    kane_sim::TeleopKeyNode node{nh, kane_sim::readTeleopKeyParams(private_nh)};
    kane_sim::KeyboardInput keyboard{STDIN_FILENO};
    node.run(keyboard, g_stop);
  } catch (const std::invalid_argument& e) {
    ROS_FATAL("teleop_key: %s", e.what());
    return 1;
  }
  return 0;
}
