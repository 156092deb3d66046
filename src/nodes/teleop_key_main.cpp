// teleop_key: drive the crank from the keyboard, in the spirit of turtle_teleop_key.
//   rosrun kane_sim teleop_key [_mode:=setpoint] [_torque_step:=0.5] [_setpoint_step:=0.1]
#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <stdexcept>

#include <ros/ros.h>

#include "kane_sim/ros/node_main.h"

#include "keyboard_input.h"
#include "teleop_key_node.h"

namespace {

// SIGINT (Ctrl-C), SIGTERM and SIGHUP (terminal closed) end the key loop, not ROS: the node
// still commands torque 0 before it goes.
std::atomic<bool> g_stop{false};
void stopOnSignal(int) { g_stop = true; }

}  // namespace

namespace {
constexpr const char* kUsage =
    "Usage: rosrun kane_sim teleop_key [_mode:=torque|setpoint] [_torque_step:=0.5]\n"
    "                                  [_torque_limit:=20] [_setpoint_step:=0.1] "
    "[_repeat_rate:=20]\n\n"
    "Drives the crank from the keyboard of this terminal: arrows (or a/d, w/s) step the torque\n"
    "(torque_command) or pd_controller's setpoint, space zeroes it, t/p switch modes, h help,\n"
    "q quits (torque 0 first).\n";
}  // namespace

int main(int argc, char** argv) {
  kane_sim::exitOnHelp(argc, argv, kUsage);
  // A closed stdin (`teleop_key <&-`) must be seen before ros::init opens sockets: the first of
  // them would get fd 0 and be read as the keyboard, forever.
  if (fcntl(STDIN_FILENO, F_GETFD) == -1) {
    std::fprintf(stderr,
                 "teleop_key: stdin is closed: run it in a terminal (or pipe keys into it, e.g. "
                 "printf 'ddq' | rosrun kane_sim teleop_key)\n");
    return 1;
  }
  kane_sim::initNode(argc, argv, "teleop_key", ros::init_options::NoSigintHandler);
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
