// tracking_controller: follows a plan of `rosrun kane_sim design plan` on the readings of
// joint_states (tracking_controller_node.h).
#include <stdexcept>

#include <ros/ros.h>

#include "kane_sim/ros/node_main.h"
#include "kane_sim/ros/shutdown_signals.h"
#include "tracking_controller_node.h"

namespace {
constexpr const char* kUsage =
    "Usage: rosrun kane_sim tracking_controller _plan:=PLAN.csv [_config:=MECHANISM.yaml]\n"
    "         [_torque_limit:=NM] [_stamped:=false]\n\n"
    "Follows a plan of `rosrun kane_sim design plan ... --out PLAN.csv` on joint_states:\n"
    "torque_command = M_m(t) - K(t) (x - x(t)), x = (q1, q2, u1, u2) read from crank_joint and\n"
    "slider4_joint, t from the first reading (again after kane_sim/reset_event); past the plan's\n"
    "end, the goal's LQR. _config: the mechanism the plan must be for (refused if not), its\n"
    "command.torque_limit the clamp unless _torque_limit is given. _stamped:=true answers on\n"
    "torque_command_stamped with each reading's stamp (lockstep). The reference is published on\n"
    "~reference.\n";
}  // namespace

int main(int argc, char** argv) {
  kane_sim::exitOnHelp(argc, argv, kUsage);
  kane_sim::initNode(argc, argv, "tracking_controller", ros::init_options::NoSigintHandler);
  kane_sim::installShutdownSignalHandlers();
  const ros::NodeHandle nh;
  const ros::NodeHandle private_nh("~");
  try {
    kane_sim::TrackingControllerNode node{nh, private_nh};
    ros::spin();
  } catch (const std::invalid_argument& e) {
    ROS_FATAL("tracking_controller: %s", e.what());
    return 1;
  }
  return 0;
}
