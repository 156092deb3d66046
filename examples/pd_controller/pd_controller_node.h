// Example of commanding the virtual robot from another node: a PD (PID with ~ki) position
// controller for the crank, or (~law: a file `design lqr --out` wrote) the state-feedback law
// M_m = torque - K (x - state) on the crank's and slider 4's readings. The PD's setpoint comes
// from ~setpoint, the `setpoint` topic, or a table (~setpoint_table: t,setpoint rows, as
// `identify --excite --controller` writes them) played from the first reading. Reads joint_states,
// publishes torque_command on every reading; clears its integral when the simulator announces a
// reset or set_state (reset_event).
#ifndef KANE_SIM_EXAMPLES_PD_CONTROLLER_NODE_H
#define KANE_SIM_EXAMPLES_PD_CONTROLLER_NODE_H

#include <optional>
#include <string>

#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Float64.h>

#include "kane_sim/ResetEvent.h"
#include "kane_sim/TorqueCommandStamped.h"

#include "kane_sim/design/state_feedback.h"
#include "kane_sim/sim/torque_profile.h"
#include "pd_law.h"

namespace kane_sim {

class PdControllerNode {
 public:
  // Throws std::invalid_argument naming a bad parameter (kp, kd, torque_limit, setpoint,
  // setpoint_table).
  PdControllerNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh);

 private:
  void onJointState(const sensor_msgs::JointState::ConstPtr& msg);
  void onSetpoint(const std_msgs::Float64::ConstPtr& msg);
  void onResetEvent(const ResetEvent::ConstPtr& msg);
  // ~setpoint_table's value at a reading's stamp (t from the first reading), or the setpoint
  // held so far before the table's first row.
  void followTable(const ros::Time& stamp);

  ros::NodeHandle nh_;
  PdGains gains_;
  double setpoint_ = 0.0;  // [rad] q1 to hold
  IntegralTerm integral_;
  ros::Time last_sample_;  // stamp of the last joint_states used (the integral's dt)
  ros::Subscriber joint_state_sub_;
  ros::Subscriber setpoint_sub_;
  ros::Subscriber reset_event_sub_;
  ros::Publisher torque_pub_;  // torque_command, or torque_command_stamped with ~stamped
  bool stamped_ = false;
  std::optional<StateFeedback> law_;       // ~law: the state feedback instead of the PD
  std::optional<TorqueProfile> table_;     // ~setpoint_table: [s] -> [rad], held from each row
  double table_first_time_ = 0.0;          // [s] its first row's t
  std::optional<ros::Time> table_origin_;  // the first reading's stamp: the table's t = 0
};

}  // namespace kane_sim

#endif  // KANE_SIM_EXAMPLES_PD_CONTROLLER_NODE_H
