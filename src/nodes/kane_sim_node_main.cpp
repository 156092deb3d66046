// kane_sim_node: the virtual robot. Parameters: see config/mechanism.yaml and
// doc/reference/parameters.md.
#include <algorithm>
#include <stdexcept>
#include <string>

#include <ros/ros.h>

#include "kane_sim/ros/node_main.h"

#include "kane_sim/config/load_config.h"
#include "kane_sim/ros/shutdown_signals.h"
#include "kane_sim_node.h"

namespace {
constexpr const char* kUsage =
    "Usage: rosrun kane_sim kane_sim_node [ROS remappings, e.g. __ns:=robot_a]\n"
    "       roslaunch kane_sim sim.launch [config:=FILE] [ns:=NAME] ... (the usual way)\n\n"
    "The virtual robot of the textbook example (Kane equations - Example 1): integrates the\n"
    "mechanism at simulation/physics_rate. Its parameters are config/mechanism.yaml loaded into\n"
    "its private namespace (sim.launch does that).\n\n"
    "Subscribes: torque_command (std_msgs/Float64), torque_command_stamped\n"
    "  (kane_sim/TorqueCommandStamped, lockstep), servo_setpoint (std_msgs/Float64,\n"
    "  command.mode velocity | position)\n"
    "Publishes:  joint_states, joint_states_true (sensors on), tf, mechanism_state,\n"
    "  visualization_markers, servo_state (servo modes), /clock (publish_clock), /diagnostics,\n"
    "  ~reset_event, ~input_log and ~checkpoint (for simulate --replay), robot_description\n"
    "Services:   ~reset, ~pause, ~unpause, ~step, ~step_with_command, ~set_state;\n"
    "  dynamic_reconfigure on ~set_parameters\n\n"
    "See doc/guide/node.md.\n";
}  // namespace

int main(int argc, char** argv) {
  kane_sim::exitOnHelp(argc, argv, kUsage);
  kane_sim::initNode(argc, argv, "kane_sim", ros::init_options::NoSigintHandler);
  kane_sim::installShutdownSignalHandlers();
  // Held outside the try: destroying the last NodeHandle shuts ROS (and its logging) down, and
  // the fatal message below must still reach the console.
  const ros::NodeHandle nh;
  const ros::NodeHandle private_nh("~");
  try {
    kane_sim::KaneSimNode node{nh, private_nh};
    node.run();
  } catch (const kane_sim::ConfigError& e) {
    std::string param = e.key();
    std::replace(param.begin(), param.end(), '.', '/');
    ROS_FATAL(
        "kane_sim: bad parameter %s/%s: %s. Fix it in the config file (or on the parameter "
        "server) and start again.",
        ros::this_node::getName().c_str(), param.c_str(), e.what());
    return 1;
  } catch (const std::invalid_argument& e) {
    ROS_FATAL("kane_sim: %s", e.what());
    return 1;
  }
  return 0;
}
