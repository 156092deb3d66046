// rviz markers of what the robot description does not draw: pins, rail, spring zigzag and
// torque arrow (rviz's RobotModel display draws the rods and sliders from robot_description),
// all in the `mechanism` frame with stable namespaces and ids (rviz updates, never piles up).
#ifndef KANE_SIM_ROS_MARKERS_H
#define KANE_SIM_ROS_MARKERS_H

#include <ros/time.h>
#include <visualization_msgs/MarkerArray.h>

#include "kane_sim/description/body_shapes.h"
#include "kane_sim/config/frame_names.h"
#include "kane_sim/sim/snapshot.h"

namespace kane_sim {


// The torque arrow is full length (0.3 m) at snapshot.command.torque_limit.
visualization_msgs::MarkerArray mechanismMarkers(const Snapshot& snapshot, const FrameNames& frames,
                                                 const ros::Time& stamp);

}  // namespace kane_sim

#endif  // KANE_SIM_ROS_MARKERS_H
