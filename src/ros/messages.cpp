#include "kane_sim/ros/messages.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include <Eigen/Geometry>
#include <string>

#include "kane_sim/ros/markers.h"

namespace kane_sim {
namespace {

geometry_msgs::TransformStamped transformMessage(const JointPose& pose, const ros::Time& stamp) {
  geometry_msgs::TransformStamped t;
  t.header.stamp = stamp;
  t.header.frame_id = pose.joint->parent;
  t.child_frame_id = pose.joint->child;
  const Eigen::Vector3d& p = pose.parent_to_child.translation();
  t.transform.translation.x = p.x();
  t.transform.translation.y = p.y();
  t.transform.translation.z = p.z();
  const Eigen::Quaterniond q(pose.parent_to_child.linear());
  t.transform.rotation.x = q.x();
  t.transform.rotation.y = q.y();
  t.transform.rotation.z = q.z();
  t.transform.rotation.w = q.w();
  return t;
}

std::vector<geometry_msgs::TransformStamped> transformMessages(const std::vector<JointPose>& poses,
                                                               const ros::Time& stamp) {
  std::vector<geometry_msgs::TransformStamped> out;
  out.reserve(poses.size());
  for (const JointPose& pose : poses) out.push_back(transformMessage(pose, stamp));
  return out;
}

}  // namespace

sensor_msgs::JointState jointStateMessage(const JointValues& j, const ros::Time& stamp) {
  sensor_msgs::JointState msg;
  msg.header.stamp = stamp;
  msg.name.assign(kJointNames.begin(), kJointNames.end());
  msg.position.assign(j.position.begin(), j.position.end());
  msg.velocity.assign(j.velocity.begin(), j.velocity.end());
  msg.effort.assign(j.effort.begin(), j.effort.end());
  return msg;
}

std::vector<geometry_msgs::TransformStamped> staticTransforms(const RobotDescription& robot,
                                                              const ros::Time& stamp) {
  return transformMessages(fixedJointPoses(robot), stamp);
}

std::vector<geometry_msgs::TransformStamped> jointTransforms(const RobotDescription& robot,
                                                             const JointValues& joints,
                                                             const ros::Time& stamp) {
  return transformMessages(movingJointPoses(robot, joints), stamp);
}

const std::vector<std::string>& loadNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (const LoadInfo& load : kLoadInfo) out.push_back(load.name);
    return out;
  }();
  return names;
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
  msg.gravitational_energy = s.energy.gravitational();
  msg.spring_energy = s.energy.spring();
  msg.total_energy = s.energy.total();
  msg.motor_work = s.motor_work;
  msg.dissipated_energy = s.dissipated_energy;
  msg.parameter_energy = s.parameter_energy;
  msg.energy_balance = s.energyBalance();
  msg.contact_impacts = static_cast<std::uint32_t>(s.contact_impacts);
  msg.resting_contact = s.resting_contact;
  msg.contact_force = s.contact_force;
  msg.parameter_changes = static_cast<std::uint32_t>(s.parameter_changes);
  msg.spring_elongation = s.spring_elongation;
  msg.slider_separation = s.slider_separation;
  msg.slider_crossings = static_cast<std::uint32_t>(s.slider_crossings);
  msg.real_time_factor = real_time_factor;
  const ConstraintForces& f = s.constraint_forces;
  msg.pin_o_force = {f.pin_o.x(), f.pin_o.y()};
  msg.pin_a_force = {f.pin_a.x(), f.pin_a.y()};
  msg.pin_b_force = {f.pin_b.x(), f.pin_b.y()};
  msg.rail_force_slider3 = f.rail_slider3;
  msg.rail_force_slider4 = f.rail_slider4;
  msg.spring_force = f.spring;
  msg.reactions_determinate = f.determinate;
  msg.load_names = loadNames();
  msg.load_powers.assign(s.load_powers.by_name.begin(), s.load_powers.by_name.end());
  msg.load_energies.assign(s.energy.potential.begin(), s.energy.potential.end());
  std::copy(s.body_kinetic_energy.begin(), s.body_kinetic_energy.end(),
            msg.body_kinetic_energy.begin());
  msg.impact_energy = s.impact_energy;
  return msg;
}

kane_sim::ResetEvent resetEventMessage(const std::string& cause, double sim_time, const State& x,
                                       const ros::Time& stamp) {
  kane_sim::ResetEvent event;
  event.header.stamp = stamp;
  event.cause = cause;
  event.sim_time = sim_time;
  event.q = {x.q1, x.q2};
  event.u = {x.u1, x.u2};
  return event;
}

kane_sim::ServoState servoStateMessage(const Snapshot& s, CommandMode mode,
                                       const ros::Time& stamp) {
  kane_sim::ServoState msg;
  msg.header.stamp = stamp;
  msg.mode = commandModeName(mode);
  msg.setpoint = s.servo.setpoint;
  msg.measured = s.servo.measured;
  msg.error = s.servo.error;
  msg.p = s.servo.proportional;
  msg.i = s.servo.integral;
  msg.d = s.servo.derivative;
  msg.feedforward = s.servo.feedforward;
  msg.output = s.servo.output;
  msg.command = s.servo.command;
  msg.delivered = s.torque;
  msg.saturated = s.servo.saturated;
  return msg;
}

kane_sim::InputLog inputLogMessage(const DriverInput& input, const ros::Time& stamp,
                                   std::uint64_t seq) {
  kane_sim::InputLog msg;
  msg.header.stamp = stamp;
  msg.seq = seq;
  msg.tick = input.tick;
  msg.kind = static_cast<std::uint8_t>(input.kind);
  msg.value = input.value;
  if (input.kind == DriverInput::Kind::kSetState)
    msg.state = {input.state.q1, input.state.q2, input.state.u1, input.state.u2};
  return msg;
}

std::optional<DriverInput> driverInput(const kane_sim::InputLog& msg) {
  if (msg.kind > kane_sim::InputLog::SET_STATE) return std::nullopt;
  DriverInput input;
  input.kind = static_cast<DriverInput::Kind>(msg.kind);
  input.tick = msg.tick;
  input.value = msg.value;
  if (input.kind == DriverInput::Kind::kSetState) {
    if (msg.state.size() != 4) return std::nullopt;
    input.state = State{msg.state[0], msg.state[1], msg.state[2], msg.state[3]};
  }
  return input;
}

PublishedMessages buildMessages(const Snapshot& snapshot, const RobotDescription& robot,
                                double real_time_factor, const ros::Time& stamp) {
  PublishedMessages out;
  out.joint_state = jointStateMessage(snapshot, stamp);
  out.tf.transforms = jointTransforms(robot, snapshot.joints, stamp);
  out.mechanism_state =
      mechanismStateMessage(snapshot, real_time_factor, stamp, robot.frames.mechanism);
  out.markers = mechanismMarkers(snapshot, robot.frames, stamp);
  return out;
}

}  // namespace kane_sim
