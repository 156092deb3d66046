#include "kane_sim/ros/messages.h"

#include <cmath>
#include <string>

#include "kane_sim/ros/markers.h"

namespace kane_sim {
namespace {

geometry_msgs::TransformStamped planarTransform(const std::string& parent, const std::string& child,
                                                const Eigen::Vector3d& origin, double angle,
                                                const ros::Time& stamp) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.transform.translation.x = origin.x();
  t.transform.translation.y = origin.y();
  t.transform.translation.z = origin.z();
  t.transform.rotation.z = std::sin(angle / 2);  // rotation by `angle` about the plane normal k
  t.transform.rotation.w = std::cos(angle / 2);
  return t;
}

}  // namespace

sensor_msgs::JointState jointStateMessage(const Snapshot& snapshot, const ros::Time& stamp) {
  const JointValues& j = snapshot.joints;
  sensor_msgs::JointState msg;
  msg.header.stamp = stamp;
  msg.name.assign(kJointNames.begin(), kJointNames.end());
  msg.position.assign(j.position.begin(), j.position.end());
  msg.velocity.assign(j.velocity.begin(), j.velocity.end());
  msg.effort.assign(j.effort.begin(), j.effort.end());
  return msg;
}

geometry_msgs::TransformStamped worldToMechanism(const FrameNames& frames,
                                                 const FrameSettings& settings,
                                                 const ros::Time& stamp) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = frames.world;
  t.child_frame_id = frames.mechanism;
  t.transform.translation.z = settings.pivot_height;
  // +90° about world y: mechanism x -> world -z (down), y -> world y, z -> world x.
  t.transform.rotation.y = std::sqrt(0.5);
  t.transform.rotation.w = std::sqrt(0.5);
  return t;
}

std::vector<geometry_msgs::TransformStamped> bodyTransforms(const Snapshot& snapshot,
                                                            const FrameNames& frames,
                                                            const ros::Time& stamp) {
  const MechanismGeometry& g = snapshot.geometry;
  return {
      planarTransform(frames.mechanism, frames.bodies[kRod1], g.rod1_center, g.rod1_angle, stamp),
      planarTransform(frames.mechanism, frames.bodies[kRod2], g.rod2_center, g.rod2_angle, stamp),
      planarTransform(frames.mechanism, frames.bodies[kSlider3], g.pin_b, 0.0, stamp),
      planarTransform(frames.mechanism, frames.bodies[kSlider4], g.point_c, 0.0, stamp)};
}

kane_sim::MechanismState mechanismStateMessage(const Snapshot& s, double real_time_factor,
                                               const ros::Time& stamp,
                                               const std::string& frame_id) {
  kane_sim::MechanismState msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = frame_id;
  msg.sim_time = s.time;
  msg.q = {s.state.q1, s.state.q2};
  msg.u = {s.state.u1, s.state.u2};
  msg.u_dot = {s.u_dot[0], s.u_dot[1]};
  msg.commanded_torque = s.command.commanded;
  msg.applied_torque = s.torque;
  msg.active_forces = {s.active_forces[0], s.active_forces[1]};
  msg.inertia_forces = {s.inertia_forces[0], s.inertia_forces[1]};
  msg.kinetic_energy = s.energy.kinetic;
  msg.gravitational_energy = s.energy.gravitational;
  msg.spring_energy = s.energy.spring;
  msg.total_energy = s.energy.total();
  msg.motor_work = s.motor_work;
  msg.spring_elongation = s.spring_elongation;
  msg.slider_separation = s.slider_separation;
  msg.slider_crossings = static_cast<std::uint32_t>(s.slider_crossings);
  msg.real_time_factor = real_time_factor;
  return msg;
}

PublishedMessages buildMessages(const Snapshot& snapshot, const FrameNames& frames,
                                double real_time_factor, const ros::Time& stamp) {
  PublishedMessages out;
  out.joint_state = jointStateMessage(snapshot, stamp);
  out.tf.transforms = bodyTransforms(snapshot, frames, stamp);
  out.mechanism_state = mechanismStateMessage(snapshot, real_time_factor, stamp, frames.mechanism);
  out.markers = mechanismMarkers(snapshot, frames, stamp);
  return out;
}

}  // namespace kane_sim
