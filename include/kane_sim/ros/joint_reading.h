// One joint's position and velocity out of a JointState, as the controllers read joint_states
// (pd_controller, tracking_controller): false when the joint is missing, its arrays too short,
// or a value is not finite.
#ifndef KANE_SIM_ROS_JOINT_READING_H
#define KANE_SIM_ROS_JOINT_READING_H

#include <algorithm>
#include <cmath>

#include <sensor_msgs/JointState.h>

namespace kane_sim {

inline bool jointReading(const sensor_msgs::JointState& msg, const char* joint, double* position,
                         double* velocity) {
  const auto it = std::find(msg.name.begin(), msg.name.end(), joint);
  const size_t i = static_cast<size_t>(it - msg.name.begin());
  if (it == msg.name.end() || i >= msg.position.size() || i >= msg.velocity.size()) return false;
  *position = msg.position[i];
  *velocity = msg.velocity[i];
  return std::isfinite(*position) && std::isfinite(*velocity);
}

}  // namespace kane_sim

#endif  // KANE_SIM_ROS_JOINT_READING_H
