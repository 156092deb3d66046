#include "kane_sim/ros/estimate_messages.h"

#include "kane_sim/format_number.h"

#include <algorithm>
#include <cstdio>

#include "kane_sim/model/joint_names.h"

namespace kane_sim {
namespace {

// The index of `joint` in msg.name, or -1.
long jointIndex(const sensor_msgs::JointState& msg, const char* joint) {
  // -1: absent; -2: named twice (which value is the joint's?)
  const auto it = std::find(msg.name.begin(), msg.name.end(), joint);
  if (it == msg.name.end()) return -1;
  if (std::find(it + 1, msg.name.end(), joint) != msg.name.end()) return -2;
  return static_cast<long>(it - msg.name.begin());
}

diagnostic_msgs::KeyValue keyValue(const std::string& key, double value) {
  diagnostic_msgs::KeyValue kv;
  kv.key = key;
  char text[64];
  std::snprintf(text, sizeof text, "%.6g", value);
  kv.value = text;
  return kv;
}

}  // namespace

bool rigReading(const sensor_msgs::JointState& msg, const ros::Time& receipt, RigReading* reading,
                std::string* why) {
  const char* crank = kJointNames[kCrankJoint];
  const char* slider = kJointNames[kSlider4Joint];
  const long c = jointIndex(msg, crank), s = jointIndex(msg, slider);
  if (c == -2 || s == -2) {
    *why = std::string("the message names ") + (c == -2 ? crank : slider) +
           " twice: which value is the joint's?";
    return false;
  }
  if (c < 0 || s < 0) {
    *why = std::string("the message has no ") + (c < 0 ? crank : slider) +
           " (is it this mechanism's joint_states?)";
    return false;
  }
  const auto has = [](const std::vector<double>& v, long i) {
    return static_cast<std::size_t>(i) < v.size();
  };
  if (!has(msg.position, c) || !has(msg.position, s)) {
    *why = "the message has no position for " + std::string(has(msg.position, c) ? slider : crank);
    return false;
  }
  if (!has(msg.effort, c)) {
    *why = std::string("the message has no effort for ") + crank +
           " (the delivered torque the estimator needs)";
    return false;
  }
  RigReading r;
  r.stamp = (msg.header.stamp.isZero() ? receipt : msg.header.stamp).toSec();
  r.q1 = msg.position[c];
  r.q2 = msg.position[s];
  r.torque = msg.effort[c];
  r.has_velocity = has(msg.velocity, c) && has(msg.velocity, s);
  if (r.has_velocity) {
    r.u1 = msg.velocity[c];
    r.u2 = msg.velocity[s];
  }
  *reading = r;
  return true;
}

kane_sim::StateEstimate stateEstimateMessage(const EstimateRow& row,
                                             const MechanismEstimator& estimator,
                                             const ros::Time& stamp) {
  kane_sim::StateEstimate msg;
  msg.header.stamp = stamp;
  const FilterEstimate& e = row.estimate;
  msg.q = {{e.state.q1, e.state.q2}};
  msg.u = {{e.state.u1, e.state.u2}};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) msg.covariance[4 * i + j] = e.covariance(i, j);
  msg.encoder_bias = {{e.bias[0], e.bias[1]}};
  msg.sample_age = estimator.lastStamp() - estimator.atSample().time;
  msg.applied_torque = e.torque;
  msg.nis = row.nis;
  msg.nis_dof = static_cast<std::uint8_t>(row.nis_dof);
  const AlarmReport& alarm = estimator.alarm().report();
  msg.alarm_level = static_cast<std::uint8_t>(alarm.level);
  msg.alarm = alarm.text();
  msg.restarts = static_cast<std::uint32_t>(estimator.restarts());
  return msg;
}

diagnostic_msgs::DiagnosticStatus estimatorStatus(const MechanismEstimator& estimator,
                                                  const std::string& name, double silence) {
  const AlarmReport& alarm = estimator.alarm().report();
  diagnostic_msgs::DiagnosticStatus status;
  status.name = name + ": model mismatch";
  status.hardware_id = "kane_sim observer";
  status.level = static_cast<std::uint8_t>(alarm.level);
  status.message = estimator.started() ? alarm.text() : "waiting for joint_states";
  status.values = {keyValue("window NIS", alarm.nis),
                   keyValue("window degrees of freedom", alarm.dof),
                   keyValue("least likely test's probability", alarm.p_value),
                   keyValue("windows", static_cast<double>(alarm.windows)),
                   keyValue("since [s]", alarm.since),
                   keyValue("restarts", static_cast<double>(estimator.restarts()))};
  if (alarm.level != AlarmLevel::kOk) {
    diagnostic_msgs::KeyValue coordinate;
    coordinate.key = "coordinate";
    coordinate.value = measuredCoordinateName(alarm.coordinate);
    status.values.push_back(coordinate);
  }
  status.values.push_back(keyValue("since the last reading [s]", silence));
  if (estimator.started() && silence > estimator.restartGap()) {
    status.level = diagnostic_msgs::DiagnosticStatus::WARN;
    status.message = "no usable joint_states reading for " + formatNumber(silence) +
                     " s: the estimate is that old (is the rig's driver publishing?); the "
                     "filter starts again from the next reading. Before: " +
                     status.message;
  }
  // The parameters whose change explains the window, most likely first: "change of <name>".
  for (const AlarmReport::Suspect& suspect : alarm.suspects)
    status.values.push_back(
        keyValue("change of " + suspect.name + " [" + suspect.unit + "]", suspect.change));
  if (!alarm.suspects.empty())
    status.values.push_back(keyValue("change seen over [s]", alarm.suspects.front().over));
  return status;
}

}  // namespace kane_sim
