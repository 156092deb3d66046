// The observer node: the estimator (estimate/) beside a rig. Reads the rig's joint_states (a
// real rig's, or kane_sim_node's with its sensors on), and for each reading publishes the
// estimate carried to the reading's stamp on ~estimate (kane_sim/StateEstimate, with its
// covariance), ~joint_states (all four joints: what a controller can read instead of the
// rig's, lockstep stamps kept) and ~mechanism_state (the virtual sensors); the model-mismatch
// alarm on /diagnostics (every second and when its level changes). kane_sim/reset_event
// restarts the filter. ROS plumbing only: the filter is ROS-free.
#ifndef KANE_SIM_NODES_OBSERVER_NODE_H
#define KANE_SIM_NODES_OBSERVER_NODE_H

#include <memory>
#include <string>

#include <ros/ros.h>
#include <sensor_msgs/JointState.h>

#include "kane_sim/ResetEvent.h"
#include "kane_sim/config/frame_names.h"
#include "kane_sim/estimate/estimate_table.h"
#include "kane_sim/estimate/mechanism_estimator.h"
#include "kane_sim/ros/inline_callback_queue.h"

namespace kane_sim {

class ObserverNode {
 public:
  // Throws std::invalid_argument naming a bad ~config.
  ObserverNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh);

 private:
  void onJointState(const sensor_msgs::JointState::ConstPtr& msg);
  void onResetEvent(const ResetEvent::ConstPtr& msg);
  void publishDiagnostics();  // with inline_queue_ held

  ros::NodeHandle nh_;
  // The readings and reset events are taken in roscpp's network thread, one at a time; the
  // diagnostics timer, on ros::spin's thread, holds this queue while it reads the alarm.
  InlineCallbackQueue inline_queue_;
  Config config_;
  std::unique_ptr<MechanismEstimator> estimator_;
  std::unique_ptr<VirtualSensors> sensors_;
  std::unique_ptr<const FrameNames> frames_;  // the config's, built once
  double first_stamp_ = 0.0;
  ros::SteadyTime last_reading_;  // when the last usable reading arrived
  AlarmLevel published_level_ = AlarmLevel::kOk;
  ros::Subscriber joint_state_sub_, reset_event_sub_;
  ros::Publisher estimate_pub_, joint_state_pub_, mechanism_state_pub_, diagnostics_pub_;
  ros::SteadyTimer diagnostics_timer_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_OBSERVER_NODE_H
