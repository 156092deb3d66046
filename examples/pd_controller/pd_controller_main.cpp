// pd_controller: example crank position controller for kane_sim_node.
#include <sstream>
#include <stdexcept>
#include <string>

#include <ros/ros.h>

#include "kane_sim/ros/node_main.h"

#include "kane_sim/ros/shutdown_signals.h"
#include "pd_controller_node.h"
#include "pd_law.h"

namespace {
constexpr const char* kDescription =
    "Example crank position controller for kane_sim_node: answers every joint_states reading\n"
    "with torque_command = kp (setpoint - q1) - kd u1 + ki * integral of the error, clamped;\n"
    "the setpoint also on the `setpoint` topic (std_msgs/Float64). The integral is cleared on\n"
    "the simulator's kane_sim/reset_event (reset, set_state). _stamped:=true answers on\n"
    "torque_command_stamped with each reading's stamp (what lockstep waits for). Gains in\n"
    "config/controller.yaml. _law:=FILE runs the state-feedback law a file of `rosrun kane_sim\n"
    "design lqr --out FILE` holds instead (M_m = torque - K (x - state) on crank_joint and\n"
    "slider4_joint, clamped to torque_limit). _setpoint_table:=CSV plays a table of t,setpoint\n"
    "rows [s, rad] (identify --excite --controller writes one) as the setpoint, t from the first\n"
    "reading, each row held until the next, the last after the end; the topic is then ignored.\n";

// The defaults shown are the law's own (PdGains), so the usage cannot drift from them.
std::string usage() {
  const kane_sim::PdGains d;
  std::ostringstream out;
  out << "Usage: rosrun kane_sim pd_controller [_kp:=" << d.kp << "] [_kd:=" << d.kd
      << "] [_ki:=" << d.ki << "] [_setpoint:=0] [_torque_limit:=" << d.torque_limit
      << "] [_stamped:=false] [_law:=FILE | _setpoint_table:=CSV]\n\n"
      << kDescription;
  return out.str();
}
}  // namespace

int main(int argc, char** argv) {
  kane_sim::exitOnHelp(argc, argv, usage().c_str());
  kane_sim::initNode(argc, argv, "pd_controller", ros::init_options::NoSigintHandler);
  kane_sim::installShutdownSignalHandlers();
  // Held outside the try: destroying the last NodeHandle shuts ROS (and its logging) down, and
  // the fatal message below must still reach the console.
  const ros::NodeHandle nh;
  const ros::NodeHandle private_nh("~");
  try {
    kane_sim::PdControllerNode node{nh, private_nh};
    ros::spin();
  } catch (const std::invalid_argument& e) {
    ROS_FATAL("pd_controller: %s", e.what());
    return 1;
  }
  return 0;
}
