// The one message-filling path: the node and the offline bag writer turn snapshots into ROS
// messages only through these functions. Needs ROS message headers, not a running master.
#ifndef KANE_SIM_ROS_MESSAGES_H
#define KANE_SIM_ROS_MESSAGES_H

#include <cstdint>
#include <vector>

#include <geometry_msgs/TransformStamped.h>
#include <ros/time.h>
#include <sensor_msgs/JointState.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/MarkerArray.h>
#include <xmlrpcpp/XmlRpcValue.h>
#include <yaml-cpp/yaml.h>

#include "kane_sim/MechanismState.h"
#include "kane_sim/frame_names.h"
#include "kane_sim/simulator.h"

namespace kane_sim {

// In /clock mode and in bags written offline, stamps are this fixed epoch plus sim time, so that
// no stamp is 0 (which tf reads as "latest") and runs of one config share their stamps.
constexpr std::uint32_t kSimEpochSeconds = 1000000000;  // 2001-09-09T01:46:40Z
inline ros::Time simStamp(double sim_time) {
  return ros::Time(kSimEpochSeconds, 0) + ros::Duration(sim_time);
}

// rosparam's view of the private namespace -> the YAML the config loader reads.
YAML::Node yamlFromXmlRpc(XmlRpc::XmlRpcValue& value);

sensor_msgs::JointState jointStateMessage(const MechanismModel& model,
                                          const MechanismSnapshot& snapshot,
                                          const ros::Time& stamp);

// world -> mechanism: the seed's x axis along world -z (gravity), O at pivot_height.
geometry_msgs::TransformStamped worldToMechanism(const FrameNames& frames,
                                                 const FrameSettings& settings,
                                                 const ros::Time& stamp);

// mechanism -> rod1, rod2, slider3, slider4 at the mass centers, x along each rod.
std::vector<geometry_msgs::TransformStamped> bodyTransforms(const MechanismModel& model,
                                                            const State& state,
                                                            const FrameNames& frames,
                                                            const ros::Time& stamp);

kane_sim::MechanismState mechanismStateMessage(const MechanismSnapshot& snapshot,
                                               double commanded_torque, double real_time_factor,
                                               const ros::Time& stamp, const std::string& frame_id);

// Everything published at one publish instant, by the node or into a bag offline.
struct PublishedMessages {
  sensor_msgs::JointState joint_state;
  tf2_msgs::TFMessage tf;  // mechanism -> bodies
  kane_sim::MechanismState mechanism_state;
  visualization_msgs::MarkerArray markers;
};

struct PublishContext {
  const MechanismModel* model;
  const FrameNames* frames;
  double torque_limit;  // [N m] scales the torque arrow
};

PublishedMessages buildMessages(const PublishContext& context, const MechanismSnapshot& snapshot,
                                double commanded_torque, double real_time_factor,
                                const ros::Time& stamp);

}  // namespace kane_sim

#endif  // KANE_SIM_ROS_MESSAGES_H
