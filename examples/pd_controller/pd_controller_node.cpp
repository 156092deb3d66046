#include "pd_controller_node.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "kane_sim/design/lqr_file.h"
#include "kane_sim/format_number.h"
#include "kane_sim/ros/joint_reading.h"
#include "kane_sim/ros/node_params.h"
#include "kane_sim/sim/simulator.h"

namespace kane_sim {

PdControllerNode::PdControllerNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh)
    : nh_(nh) {
  const PdGains defaults;
  gains_.kp = boundedParam(private_nh, "kp", defaults.kp, ParamBound::kNonNegative);
  gains_.kd = boundedParam(private_nh, "kd", defaults.kd, ParamBound::kNonNegative);
  gains_.torque_limit =
      boundedParam(private_nh, "torque_limit", defaults.torque_limit, ParamBound::kNonNegative);
  gains_.ki = boundedParam(private_nh, "ki", defaults.ki, ParamBound::kNonNegative);
  setpoint_ = boundedParam(private_nh, "setpoint", 0.0, ParamBound::kAnyFinite);
  if (std::abs(setpoint_) > Simulator::kMaxCrankAngle)
    throw std::invalid_argument("parameter " + private_nh.resolveName("setpoint") + " " +
                                formatNumber(setpoint_) + " rad is beyond a million turns");
  for (const std::string& name : unknownParams(
           private_nh,
           {"kp", "kd", "ki", "torque_limit", "setpoint", "stamped", "law", "setpoint_table"}))
    ROS_WARN(
        "pd_controller: parameter %s is not read (its parameters: kp, kd, ki, torque_limit, "
        "setpoint, stamped, law, setpoint_table)",
        name.c_str());
  // ~law: a state-feedback file (design lqr --out); a bad one stops start-up naming the field.
  const std::string law_file = pathParam(private_nh, "law");
  if (!law_file.empty()) law_ = readStateFeedbackFile(law_file);
  // ~setpoint_table: the setpoint as a table of time (the same reader as simulate's
  // --torque-csv, reading setpoints: a bad file is named with its line).
  const std::string table_file = pathParam(private_nh, "setpoint_table");
  if (private_nh.hasParam("setpoint_table")) {
    if (table_file.empty())
      throw std::invalid_argument("~setpoint_table: give a CSV of t,setpoint rows, got ''");
    if (law_)
      throw std::invalid_argument(
          "~setpoint_table plays the PD's setpoint, and ~law (" + law_file +
          ") replaces the PD with a state feedback that has none: give one of the two");
    try {
      table_ = TorqueProfile::fromCsvFile(table_file, TorqueProfile::TableValue::kSetpoint);
    } catch (const std::invalid_argument& e) {
      // A relative path is read from the node's working folder (~/.ros under roslaunch).
      throw std::invalid_argument(
          std::string("~setpoint_table: ") + e.what() +
          (table_file[0] == '/' ? ""
                                : " (a relative path is read from this node's working folder, "
                                  "~/.ros under roslaunch: give an absolute one)"));
    }
    table_first_time_ = table_->parts().points.front().first;
  }
  // ~stamped: answer each reading on torque_command_stamped with its stamp, which lockstep
  // (simulation.lockstep) waits for; else the plain torque_command.
  stamped_ = flagParam(private_nh, "stamped", false);
  torque_pub_ = stamped_ ? nh_.advertise<TorqueCommandStamped>("torque_command_stamped", 10)
                         : nh_.advertise<std_msgs::Float64>("torque_command", 10);
  joint_state_sub_ = nh_.subscribe("joint_states", 10, &PdControllerNode::onJointState, this,
                                   ros::TransportHints().tcpNoDelay());
  setpoint_sub_ = nh_.subscribe("setpoint", 10, &PdControllerNode::onSetpoint, this);
  // The simulator's private topic, beside it in this namespace (/kane_sim/reset_event, or
  // /robot_a/kane_sim/reset_event under ns robot_a); remap `kane_sim/reset_event` for another.
  reset_event_sub_ =
      nh_.subscribe("kane_sim/reset_event", 10, &PdControllerNode::onResetEvent, this);
  if (law_)
    ROS_INFO(
        "pd_controller: the state feedback of %s about q1 = %g rad (K = %g %g %g %g), "
        "within +-%g N m",
        law_file.c_str(), law_->state[0], law_->K[0], law_->K[1], law_->K[2], law_->K[3],
        gains_.torque_limit);
  else if (table_)
    ROS_INFO(
        "pd_controller: the crank's setpoint follows %s (%zu rows, t %g to %g s from the first "
        "reading; %g rad before), kp %g N m/rad, kd %g N m s/rad, ki %g N m/(rad s)",
        table_file.c_str(), table_->parts().points.size(), table_first_time_,
        table_->parts().points.back().first, setpoint_, gains_.kp, gains_.kd, gains_.ki);
  else
    ROS_INFO(
        "pd_controller: holding crank_joint at %g rad (kp %g N m/rad, kd %g N m s/rad, ki %g N "
        "m/(rad s))",
        setpoint_, gains_.kp, gains_.kd, gains_.ki);
}

void PdControllerNode::onJointState(const sensor_msgs::JointState::ConstPtr& msg) {
  State x;
  if (!jointReading(*msg, "crank_joint", &x.q1, &x.u1)) {
    ROS_WARN_THROTTLE(5.0,
                      "pd_controller: joint_states without a finite crank_joint position and "
                      "velocity");
    return;
  }
  double torque = 0.0;
  if (law_) {
    if (!jointReading(*msg, "slider4_joint", &x.q2, &x.u2)) {
      ROS_WARN_THROTTLE(5.0,
                        "pd_controller: the state feedback needs slider4_joint's position and "
                        "velocity in joint_states");
      return;
    }
    torque = std::clamp(law_->command(x), -gains_.torque_limit, gains_.torque_limit);
  } else {
    if (table_) followTable(msg->header.stamp);
    const double q1 = x.q1;
    if (!last_sample_.isZero())
      integral_.add(gains_, setpoint_ - q1, (msg->header.stamp - last_sample_).toSec());
    last_sample_ = msg->header.stamp;
    torque = pdTorque(gains_, setpoint_, q1, x.u1, integral_.value());
  }
  if (!std::isfinite(torque)) return;
  if (stamped_) {
    TorqueCommandStamped answer;
    answer.header.stamp = msg->header.stamp;  // the state this answers
    answer.torque = torque;
    torque_pub_.publish(answer);
  } else {
    std_msgs::Float64 plain;
    plain.data = torque;
    torque_pub_.publish(plain);
  }
}

void PdControllerNode::followTable(const ros::Time& stamp) {
  if (!table_origin_) table_origin_ = stamp;
  const double t = (stamp - *table_origin_).toSec();
  if (t >= table_first_time_) setpoint_ = table_->at(t);
}

void PdControllerNode::onSetpoint(const std_msgs::Float64::ConstPtr& msg) {
  if (table_) {
    ROS_WARN_THROTTLE(5.0,
                      "pd_controller: setpoint %g on the topic ignored: ~setpoint_table plays "
                      "the setpoint",
                      msg->data);
    return;
  }
  if (!std::isfinite(msg->data)) {
    ROS_WARN("pd_controller: setpoint %g is not finite: keeping %g rad", msg->data, setpoint_);
    return;
  }
  setpoint_ = msg->data;
  // Debug level: an interactive marker being dragged sends tens of setpoints a second.
  ROS_DEBUG("pd_controller: new setpoint %g rad", setpoint_);
}

void PdControllerNode::onResetEvent(const ResetEvent::ConstPtr& msg) {
  // The motion the integral summed is gone: start it afresh from the moved state.
  integral_.clear();
  last_sample_ = msg->header.stamp;
  ROS_INFO("pd_controller: the mechanism was moved (%s at t = %.3f s): integral cleared",
           msg->cause.c_str(), msg->sim_time);
}

}  // namespace kane_sim
