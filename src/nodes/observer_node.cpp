#include "observer_node.h"

#include <stdexcept>

#include <diagnostic_msgs/DiagnosticArray.h>

#include "kane_sim/MechanismState.h"
#include "kane_sim/StateEstimate.h"
#include "kane_sim/config/frame_names.h"
#include "kane_sim/config/load_config.h"
#include "kane_sim/ros/estimate_messages.h"
#include "kane_sim/ros/messages.h"
#include "kane_sim/ros/param_yaml.h"
#include "kane_sim/sim/config_check.h"

namespace kane_sim {

ObserverNode::ObserverNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh) : nh_(nh) {
  // ~config: the rig's mechanism and sensors (a fitted config from identify, say), or
  // ~config_from: the parameter namespace of a running kane_sim_node (its config at start).
  std::string path, from;
  private_nh.getParam("config", path);
  private_nh.getParam("config_from", from);
  if (!path.empty() && !from.empty())
    throw std::invalid_argument(
        "both ~config (" + path + ") and ~config_from (" + from +
        ") are set: give one (a value left by an earlier rosrun stays on the parameter server: "
        "rosparam delete " +
        private_nh.resolveName("config_from") + ")");
  try {
    LoadedConfig loaded;
    if (!from.empty()) {
      XmlRpc::XmlRpcValue params;
      if (!ros::param::get(from, params))
        throw std::invalid_argument("~config_from " + from + ": no such parameter namespace");
      loaded = loadSimulationConfig(yamlFromXmlRpc(params));
      path = "the parameters of " + from;
    } else {
      if (path.empty()) {
        path = defaultConfigFile();
        ROS_WARN("observer: no ~config: estimating with the package's default %s", path.c_str());
      }
      loaded = loadSimulationConfigFile(path);
    }
    for (const std::string& warning : loaded.warnings) ROS_WARN("observer: %s", warning.c_str());
    config_ = loaded.config;
  } catch (const ConfigError& e) {
    throw std::invalid_argument((from.empty() ? "~config " + path : "~config_from " + from) + ": " +
                                e.what());
  }
  estimator_ = std::make_unique<MechanismEstimator>(config_);
  sensors_ = std::make_unique<VirtualSensors>(config_);
  frames_ = std::make_unique<const FrameNames>(config_.frames);
  ros::NodeHandle pnh(private_nh);
  estimate_pub_ = pnh.advertise<StateEstimate>("estimate", 10);
  joint_state_pub_ = pnh.advertise<sensor_msgs::JointState>("joint_states", 10);
  mechanism_state_pub_ = pnh.advertise<MechanismState>("mechanism_state", 10);
  diagnostics_pub_ = nh_.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10);
  diagnostics_timer_ =
      nh_.createSteadyTimer(ros::WallDuration(1.0), [this](const ros::SteadyTimerEvent&) {
        const auto held = inline_queue_.hold();
        publishDiagnostics();
      });
  // Each reading is filtered in the thread that received it: at 1 kHz a spinner's wake-up per
  // message costs more than the filter.
  joint_state_sub_ = inline_queue_.subscribe<sensor_msgs::JointState>(
      nh_, "joint_states", 100, [this](const auto& msg) { onJointState(msg); },
      ros::TransportHints().tcpNoDelay());
  reset_event_sub_ = inline_queue_.subscribe<ResetEvent>(
      nh_, "kane_sim/reset_event", 10, [this](const auto& msg) { onResetEvent(msg); });
  const MeasurementNoise& noise = estimator_->noise();
  ROS_INFO(
      "observer: estimating from %s with %s; readings sampled %.4g s before their stamp; "
      "alarm: windows of %g s, ERROR %g times per hour on a rig that is its model",
      nh_.resolveName("joint_states").c_str(), path.c_str(), noise.latency,
      config_.estimator.alarm_window, config_.estimator.false_alarms_per_hour);
}

void ObserverNode::onJointState(const sensor_msgs::JointState::ConstPtr& msg) {
  RigReading reading;
  std::string why;
  if (!rigReading(*msg, ros::Time::now(), &reading, &why)) {
    ROS_WARN_THROTTLE(1.0, "observer: a joint_states message is not usable: %s", why.c_str());
    return;
  }
  const EstimatorStep step = estimator_->update(reading);
  if (step.event == EstimatorEvent::kRefused) {
    ROS_WARN_THROTTLE(1.0, "observer: reading refused, estimate kept: %s", step.reason.c_str());
    return;
  }
  last_reading_ = ros::SteadyTime::now();
  if (step.event == EstimatorEvent::kStarted || step.event == EstimatorEvent::kRestarted)
    first_stamp_ = reading.stamp;
  // Throttled: a driver whose clock jumps at every reading would restart it at every reading
  // (each restart is counted in ~estimate's restarts).
  if (step.event == EstimatorEvent::kRestarted)
    ROS_WARN_THROTTLE(1.0, "observer: the filter restarted: %s", step.reason.c_str());
  // The virtual sensors cost a snapshot of the model: only for someone listening.
  const bool virtual_sensors =
      joint_state_pub_.getNumSubscribers() > 0 || mechanism_state_pub_.getNumSubscribers() > 0;
  EstimateRow row;
  if (!estimateRow(*estimator_, virtual_sensors ? sensors_.get() : nullptr, first_stamp_, &row,
                   &why)) {
    ROS_WARN_THROTTLE(1.0, "observer: estimate not published: %s", why.c_str());
    return;
  }
  const ros::Time stamp = msg->header.stamp.isZero() ? ros::Time(reading.stamp) : msg->header.stamp;
  if (estimate_pub_.getNumSubscribers() > 0)
    estimate_pub_.publish(stateEstimateMessage(row, *estimator_, stamp));
  if (virtual_sensors) {
    joint_state_pub_.publish(jointStateMessage(row.snapshot, stamp));
    mechanism_state_pub_.publish(
        mechanismStateMessage(row.snapshot, 0.0, stamp, frames_->mechanism));
  }
  if (estimator_->alarm().report().level != published_level_) publishDiagnostics();
}

void ObserverNode::onResetEvent(const ResetEvent::ConstPtr& msg) {
  ROS_INFO_THROTTLE(1.0, "observer: the rig was moved (%s): the filter starts again",
                    msg->cause.c_str());
  estimator_->restart();
}

void ObserverNode::publishDiagnostics() {  // with inline_queue_ held
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = ros::Time::now();
  const double silence =
      last_reading_.isZero() ? 0.0 : (ros::SteadyTime::now() - last_reading_).toSec();
  array.status.push_back(estimatorStatus(*estimator_, ros::this_node::getName(), silence));
  published_level_ = estimator_->alarm().report().level;
  diagnostics_pub_.publish(array);
}

}  // namespace kane_sim
