// The tracking controller: follows a plan of `design plan` (design/plan_follower.h) against the
// readings on joint_states — feedforward from the plan, its time-varying LQR feedback on the
// crank's and slider 4's readings, the goal's LQR from the plan's end on — and answers each
// reading on torque_command (or, ~stamped, torque_command_stamped with the reading's stamp:
// what lockstep waits for). The plan's clock starts at the first reading and again at the first
// after the simulator announces a reset or set_state (kane_sim/reset_event). Publishes the
// reference it compares with on ~reference (JointState: crank_joint, slider4_joint; effort the
// feedforward). ROS plumbing only: the law is ROS-free.
#ifndef KANE_SIM_NODES_TRACKING_CONTROLLER_NODE_H
#define KANE_SIM_NODES_TRACKING_CONTROLLER_NODE_H

#include <cstdint>
#include <optional>

#include <ros/ros.h>
#include <sensor_msgs/JointState.h>

#include "kane_sim/ResetEvent.h"
#include "kane_sim/design/plan_follower.h"
#include "kane_sim/ros/inline_callback_queue.h"

namespace kane_sim {

class TrackingControllerNode {
 public:
  // Throws std::invalid_argument naming a bad parameter or plan (~plan, ~config, ~torque_limit).
  TrackingControllerNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh);

 private:
  void onJointState(const sensor_msgs::JointState::ConstPtr& msg);
  void onResetEvent(const ResetEvent::ConstPtr& msg);
  void answer(const ros::Time& stamp, double torque);

  ros::NodeHandle nh_;
  // Readings and reset events answered in roscpp's network thread, one at a time: at 1 kHz a
  // spinner's wake-up per reading costs more than the law.
  InlineCallbackQueue inline_queue_;
  std::optional<PlanFollower> follower_;
  double last_torque_ = 0.0;                // answered again for a reading it cannot use
  std::optional<std::int64_t> last_stamp_;  // [ns] a reading before it restarts the plan
  bool stamped_ = false;
  ros::Subscriber joint_state_sub_;
  ros::Subscriber reset_event_sub_;
  ros::Publisher torque_pub_;
  ros::Publisher reference_pub_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_TRACKING_CONTROLLER_NODE_H
