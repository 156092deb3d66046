#include "tracking_controller_node.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <std_msgs/Float64.h>

#include "kane_sim/TorqueCommandStamped.h"
#include "kane_sim/config/load_config.h"
#include "kane_sim/design/plan_file.h"
#include "kane_sim/model/joint_names.h"
#include "kane_sim/ros/joint_reading.h"
#include "kane_sim/ros/node_params.h"

namespace kane_sim {

TrackingControllerNode::TrackingControllerNode(const ros::NodeHandle& nh,
                                               const ros::NodeHandle& private_nh)
    : nh_(nh) {
  std::string plan_path;
  if (!private_nh.getParam("plan", plan_path) || plan_path.empty())
    throw std::invalid_argument(
        "parameter " + private_nh.resolveName("plan") +
        " must name a plan CSV (rosrun kane_sim design plan ... --out FILE)");
  PlanFile plan;
  try {
    plan = readPlanCsv(plan_path);
  } catch (const PlanError& e) {
    throw std::invalid_argument(std::string("~plan: ") + e.what());
  }
  // ~config: the mechanism the controller runs (the simulator's config): the plan must have
  // been designed for it, and its command.torque_limit is the default clamp.
  double torque_limit = std::numeric_limits<double>::infinity();
  std::string config_path;
  if (private_nh.getParam("config", config_path) && !config_path.empty()) {
    Config config;
    try {
      config = loadConfigFile(config_path).config;
    } catch (const ConfigError& e) {
      throw std::invalid_argument(std::string("~config: ") + e.what());
    }
    const std::string mismatch = planMismatch(plan, config);
    if (!mismatch.empty())
      throw std::invalid_argument("~plan " + plan_path + " is not for ~config " + config_path +
                                  ": " + mismatch);
    torque_limit = config.command.torque_limit;
  } else {
    ROS_WARN(
        "tracking_controller: no ~config: the plan is not checked against the mechanism "
        "it drives, and the torque is clamped only where ~torque_limit says");
  }
  if (private_nh.hasParam("torque_limit"))
    torque_limit = boundedParam(private_nh, "torque_limit", 0.0, ParamBound::kPositive);
  follower_.emplace(plan.plan, torque_limit);
  bool sim_time = false;
  ros::param::get("/use_sim_time", sim_time);
  if (!sim_time)
    ROS_WARN(
        "tracking_controller: /use_sim_time is false: the plan's clock is the readings' wall "
        "stamps. A simulator that waits (lockstep, paused, slower than real time) falls "
        "behind it: run it on /clock (simulation.publish_clock: true; sim.launch plan:= "
        "does)");
  stamped_ = flagParam(private_nh, "stamped", false);
  torque_pub_ = stamped_ ? nh_.advertise<TorqueCommandStamped>("torque_command_stamped", 10)
                         : nh_.advertise<std_msgs::Float64>("torque_command", 10);
  ros::NodeHandle pnh(private_nh);
  reference_pub_ = pnh.advertise<sensor_msgs::JointState>("reference", 10);
  joint_state_sub_ = inline_queue_.subscribe<sensor_msgs::JointState>(
      nh_, "joint_states", 10, [this](const auto& msg) { onJointState(msg); },
      ros::TransportHints().tcpNoDelay());
  reset_event_sub_ = inline_queue_.subscribe<ResetEvent>(
      nh_, "kane_sim/reset_event", 10, [this](const auto& msg) { onResetEvent(msg); });
  ROS_INFO(
      "tracking_controller: following %s (%.3f s, %zu rows every %g s), then the goal's "
      "LQR; |M_m| <= %g N m",
      plan_path.c_str(), plan.plan.duration(), plan.plan.points.size(), plan.plan.step,
      torque_limit);
}

void TrackingControllerNode::onJointState(const sensor_msgs::JointState::ConstPtr& msg) {
  State x;
  // Whole nanoseconds (the plan's clock is their difference: exact).
  const std::int64_t stamp = static_cast<std::int64_t>(msg->header.stamp.toNSec());
  std::optional<double> torque;
  if (last_stamp_ && stamp < *last_stamp_)
    ROS_WARN(
        "tracking_controller: a reading stamped %.6f s before the last one: the plan "
        "starts again from it",
        static_cast<double>(*last_stamp_ - stamp) * 1e-9);
  last_stamp_ = stamp;
  if (jointReading(*msg, kJointNames[kCrankJoint], &x.q1, &x.u1) &&
      jointReading(*msg, kJointNames[kSlider4Joint], &x.q2, &x.u2))
    torque = follower_->command(stamp, x);
  if (!torque) {
    // Still answered (lockstep waits for every answer): the last command, kept.
    ROS_WARN_THROTTLE(5.0,
                      "tracking_controller: joint_states without finite crank_joint and "
                      "slider4_joint positions and velocities: keeping %g N m",
                      last_torque_);
    answer(msg->header.stamp, last_torque_);
    return;
  }
  last_torque_ = *torque;
  answer(msg->header.stamp, *torque);
  if (reference_pub_.getNumSubscribers() == 0) return;  // a message a reading, only when heard
  const PlanPoint reference = follower_->plan().at(follower_->planTime(stamp));
  sensor_msgs::JointState ref;
  ref.header.stamp = msg->header.stamp;
  ref.name = {kJointNames[kCrankJoint], kJointNames[kSlider4Joint]};
  ref.position = {reference.x[0], reference.x[1]};
  ref.velocity = {reference.x[2], reference.x[3]};
  ref.effort = {reference.torque, 0.0};
  reference_pub_.publish(ref);
}

void TrackingControllerNode::answer(const ros::Time& stamp, double torque) {
  if (stamped_) {
    TorqueCommandStamped out;
    out.header.stamp = stamp;  // the reading this answers
    out.torque = torque;
    torque_pub_.publish(out);
  } else {
    std_msgs::Float64 out;
    out.data = torque;
    torque_pub_.publish(out);
  }
}

void TrackingControllerNode::onResetEvent(const ResetEvent::ConstPtr& msg) {
  follower_->restart();
  last_torque_ = 0.0;
  last_stamp_.reset();
  ROS_INFO(
      "tracking_controller: the mechanism was moved (%s at t = %.3f s): the plan starts "
      "again at the next reading",
      msg->cause.c_str(), msg->sim_time);
}

}  // namespace kane_sim
