// Everything kane_sim_node shows to ROS: its subscribers, publishers and services, made together
// by the node's connect() and dropped together by shutdown() (a restarted master knows none of
// them). Also the one rule for /tf that needs the publisher at hand.
#ifndef KANE_SIM_NODES_NODE_INTERFACES_H
#define KANE_SIM_NODES_NODE_INTERFACES_H

#include <memory>
#include <vector>

#include <ros/ros.h>
#include <tf2_msgs/TFMessage.h>
#include <tf2_ros/static_transform_broadcaster.h>

namespace kane_sim {

struct NodeInterfaces {
  ros::Subscriber torque_command;
  ros::Subscriber torque_command_stamped;
  ros::Subscriber servo_setpoint;
  ros::Publisher joint_states;
  ros::Publisher joint_states_true;  // sensors on: the truth beside the sensor view
  ros::Publisher mechanism_state;
  ros::Publisher servo_state;  // command.mode velocity | position
  ros::Publisher markers;
  ros::Publisher clock;  // simulation.publish_clock
  ros::Publisher diagnostics;
  ros::Publisher reset_event;
  ros::Publisher input_log;   // every driver input, for simulate --replay
  ros::Publisher checkpoint;  // latched
  ros::Publisher tf;          // frames.publish_tf
  std::unique_ptr<tf2_ros::StaticTransformBroadcaster> static_tf;
  std::vector<ros::ServiceServer> services;

  // Unregisters everything (quietly, when the master that knew them is gone).
  void shutdown();

  // /tf at `stamp`, never two transforms of one frame with one stamp for a listener that has
  // them (it would warn TF_REPEATED_DATA); a listener that joined since (paused in /clock mode,
  // a late rviz) gets them again. Nothing without frames.publish_tf.
  void publishTf(const tf2_msgs::TFMessage& transforms, const ros::Time& stamp);

 private:
  ros::Time last_tf_stamp_;
  uint32_t tf_subscribers_ = 0;  // /tf's subscribers when the transforms were last sent
};

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_NODE_INTERFACES_H
