// observer: the estimator beside a rig (observer_node.h), or, with --bag, a recording replayed
// through it offline (tools/observer/observer_bag.h).
#include <stdexcept>

#include <ros/ros.h>

#include "kane_sim/ros/node_main.h"
#include "kane_sim/ros/shutdown_signals.h"
#include "observer/observer_bag.h"
#include "observer_node.h"

namespace {
constexpr const char* kUsage =
    "Usage: rosrun kane_sim observer [_config:=MECHANISM.yaml | _config_from:=/kane_sim]\n"
    "       rosrun kane_sim observer --bag BAG [--topic T] [--config FILE] [--csv FILE]\n\n"
    "The rig's state from its joint_states (crank_joint and slider4_joint positions, the\n"
    "crank's effort, velocities when present) by an extended Kalman filter on the Kane\n"
    "equations of _config's mechanism, its sensors: section the measurement model and its\n"
    "estimator: section the trust in the model. Publishes ~estimate (kane_sim/StateEstimate,\n"
    "with covariance), ~joint_states and ~mechanism_state (the virtual sensors) of the estimate\n"
    "at each reading's stamp, and the model-mismatch alarm on /diagnostics. --bag replays a\n"
    "recording offline into a CSV (observer --bag x --help for its options). _config_from\n"
    "takes the config of a running kane_sim_node from its parameters (at start).\n";
}  // namespace

int main(int argc, char** argv) {
  if (kane_sim::wantsBagReplay(argc, argv)) return kane_sim::runBagReplay(argc, argv);
  kane_sim::exitOnHelp(argc, argv, kUsage);
  kane_sim::initNode(argc, argv, "observer", ros::init_options::NoSigintHandler);
  kane_sim::installShutdownSignalHandlers();
  const ros::NodeHandle nh;
  const ros::NodeHandle private_nh("~");
  try {
    kane_sim::ObserverNode node{nh, private_nh};
    ros::spin();
  } catch (const std::invalid_argument& e) {
    ROS_FATAL("observer: %s", e.what());
    return 1;
  }
  return 0;
}
