// kane_sim_node: the virtual robot. Parameters: see config/mechanism.yaml and the README.
#include <algorithm>
#include <string>

#include <ros/ros.h>

#include "kane_sim/config/load_config.h"
#include "kane_sim/ros/shutdown_signals.h"
#include "kane_sim_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "kane_sim", ros::init_options::NoSigintHandler);
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
  }
  return 0;
}
