// The one message-filling path: the node and the offline bag writer turn snapshots into ROS
// messages only through these functions. Pure translation (snapshot + frame names + stamp ->
// message): nothing here evaluates the model. Needs ROS message headers, not a running master.
#ifndef KANE_SIM_ROS_MESSAGES_H
#define KANE_SIM_ROS_MESSAGES_H

#include <cstdint>
#include <optional>
#include <vector>

#include <geometry_msgs/TransformStamped.h>
#include <ros/time.h>
#include <sensor_msgs/JointState.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/MarkerArray.h>

#include "kane_sim/InputLog.h"
#include "kane_sim/MechanismState.h"
#include "kane_sim/ResetEvent.h"
#include "kane_sim/ServoState.h"
#include "kane_sim/config/config.h"
#include "kane_sim/description/robot_description.h"
#include "kane_sim/sim/sim_driver.h"
#include "kane_sim/sim/snapshot.h"

namespace kane_sim {

// In /clock mode and in bags written offline, stamps are this fixed epoch plus sim time, so that
// no stamp is 0 (which tf reads as "latest") and runs of one config share their stamps.
constexpr std::uint32_t kSimEpochSeconds = 1000000000;  // 2001-09-09T01:46:40Z
// ros::Duration holds at most 2^31 s: sim time past this cannot be stamped. The node stops
// there (and `simulate` limits --duration far below it).
constexpr double kMaxStampableSimTime = 2.0e9;  // [s], about 63 years
inline bool isStampable(double sim_time) {
  return sim_time >= 0.0 && sim_time <= kMaxStampableSimTime;
}
// Precondition: isStampable(sim_time); outside the range the nearest end is used.
inline ros::Time simStamp(double sim_time) {
  const double t = isStampable(sim_time) ? sim_time : (sim_time > 0 ? kMaxStampableSimTime : 0.0);
  return ros::Time(kSimEpochSeconds, 0) + ros::Duration(t);
}

// joint_states carries the joints as the sensors report them when sensors are on; the truth then
// goes to joint_states_true (node and bags alike).
constexpr const char* kJointStatesTopic = "joint_states";
inline const char* truthJointStatesTopic(bool sensors_enabled) {
  return sensors_enabled ? "joint_states_true" : kJointStatesTopic;
}

sensor_msgs::JointState jointStateMessage(const JointValues& joints, const ros::Time& stamp);
inline sensor_msgs::JointState jointStateMessage(const Snapshot& snapshot, const ros::Time& stamp) {
  return jointStateMessage(snapshot.joints, stamp);
}

// The tf tree of the robot description (description/robot_description.h), the same tree
// robot_state_publisher computes from the URDF and joint_states.
// Fixed joints (world -> mechanism), for /tf_static.
std::vector<geometry_msgs::TransformStamped> staticTransforms(const RobotDescription& robot,
                                                              const ros::Time& stamp);
// Moving joints at these joint values (mechanism -> rod1 -> rod2, mechanism -> slider3, slider4).
std::vector<geometry_msgs::TransformStamped> jointTransforms(const RobotDescription& robot,
                                                             const JointValues& joints,
                                                             const ros::Time& stamp);

// MechanismState's load_names: the model's load names, indexed by LoadName (load_powers' order).
const std::vector<std::string>& loadNames();

// real_time_factor: sim time per wall time achieved by whoever produced the snapshot (0 offline).
kane_sim::MechanismState mechanismStateMessage(const Snapshot& snapshot, double real_time_factor,
                                               const ros::Time& stamp, const std::string& frame_id);

// ~reset_event: the state moved (cause "reset" or "set_state") to x at sim time t, stamped with
// the moved state's stamp (tf at it is the new pose).
kane_sim::ResetEvent resetEventMessage(const std::string& cause, double sim_time, const State& x,
                                       const ros::Time& stamp);

// The servo's update in the snapshot (command.mode velocity | position).
kane_sim::ServoState servoStateMessage(const Snapshot& snapshot, CommandMode mode,
                                       const ros::Time& stamp);

// ~input_log: a driver input and back (simulate --replay). The message's kind is checked: an
// unknown one gives std::nullopt. seq: the input's number in the order the node received them.
kane_sim::InputLog inputLogMessage(const DriverInput& input, const ros::Time& stamp,
                                   std::uint64_t seq);
std::optional<DriverInput> driverInput(const kane_sim::InputLog& msg);

// Everything published at one publish instant, by the node or into a bag offline.
struct PublishedMessages {
  sensor_msgs::JointState joint_state;
  tf2_msgs::TFMessage tf;  // the moving joints' transforms
  kane_sim::MechanismState mechanism_state;
  visualization_msgs::MarkerArray markers;
};

PublishedMessages buildMessages(const Snapshot& snapshot, const RobotDescription& robot,
                                double real_time_factor, const ros::Time& stamp);

}  // namespace kane_sim

#endif  // KANE_SIM_ROS_MESSAGES_H
