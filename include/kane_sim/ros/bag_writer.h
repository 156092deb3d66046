// Writes what the node would publish into a bag, with no master running: the offline tool's
// way to make bags that replay in rviz like recorded ones.
#ifndef KANE_SIM_ROS_BAG_WRITER_H
#define KANE_SIM_ROS_BAG_WRITER_H

#include <memory>
#include <string>
#include <vector>

#include <rosbag/bag.h>

#include "kane_sim/InputLog.h"
#include "kane_sim/ros/messages.h"

namespace kane_sim {

class BagWriter {
 public:
  // Opens `path` for writing; throws rosbag::BagException when it cannot.
  explicit BagWriter(const std::string& path);
  ~BagWriter();

  // /tf_static (latched, like tf2_ros' static broadcaster) with the fixed joints' transforms.
  void writeStatic(const std::vector<geometry_msgs::TransformStamped>& transforms);
  // /clock, /joint_states (/joint_states_true with sensors on), /tf, /mechanism_state,
  // /visualization_markers at `stamp`.
  void write(const PublishedMessages& messages, const ros::Time& stamp, bool sensors_enabled);
  // /servo_state (command.mode velocity | position), as the node publishes it.
  void writeServoState(const kane_sim::ServoState& state);
  // A sensor reading on /joint_states, stamped when it is delivered.
  void writeSensorReading(const sensor_msgs::JointState& reading);
  // A driver input on /kane_sim/input_log (the node's ~input_log under its default name), so that
  // identify drives its replays with the commands as they were applied.
  void writeInputLog(const kane_sim::InputLog& input);
  void close();

 private:
  template <typename Operation>
  void guarded(Operation operation);

  std::unique_ptr<rosbag::Bag> bag_;  // null once abandoned after a failure
};

}  // namespace kane_sim

#endif  // KANE_SIM_ROS_BAG_WRITER_H
