// The one message-filling path: the node and the offline bag writer turn snapshots into ROS
// messages only through these functions. Pure translation (snapshot + frame names + stamp ->
// message): nothing here evaluates the model. Needs ROS message headers, not a running master.
#ifndef KANE_SIM_ROS_MESSAGES_H
#define KANE_SIM_ROS_MESSAGES_H

#include <cstdint>
#include <vector>

#include <geometry_msgs/TransformStamped.h>
#include <ros/time.h>
#include <sensor_msgs/JointState.h>
#include <tf2_msgs/TFMessage.h>
#include <visualization_msgs/MarkerArray.h>

#include "kane_sim/MechanismState.h"
#include "kane_sim/config/config.h"
#include "kane_sim/ros/frame_names.h"
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

sensor_msgs::JointState jointStateMessage(const Snapshot& snapshot, const ros::Time& stamp);

// world -> mechanism: the textbook's x axis (i) along world -z (gravity), O at pivot_height.
geometry_msgs::TransformStamped worldToMechanism(const FrameNames& frames,
                                                 const FrameSettings& settings,
                                                 const ros::Time& stamp);

// mechanism -> rod1, rod2, slider3, slider4 at the mass centers, x along each rod.
std::vector<geometry_msgs::TransformStamped> bodyTransforms(const Snapshot& snapshot,
                                                            const FrameNames& frames,
                                                            const ros::Time& stamp);

// real_time_factor: sim time per wall time achieved by whoever produced the snapshot (0 offline).
kane_sim::MechanismState mechanismStateMessage(const Snapshot& snapshot, double real_time_factor,
                                               const ros::Time& stamp, const std::string& frame_id);

// Everything published at one publish instant, by the node or into a bag offline.
struct PublishedMessages {
  sensor_msgs::JointState joint_state;
  tf2_msgs::TFMessage tf;  // mechanism -> bodies
  kane_sim::MechanismState mechanism_state;
  visualization_msgs::MarkerArray markers;
};

PublishedMessages buildMessages(const Snapshot& snapshot, const FrameNames& frames,
                                double real_time_factor, const ros::Time& stamp);

}  // namespace kane_sim

#endif  // KANE_SIM_ROS_MESSAGES_H
