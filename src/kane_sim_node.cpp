#include "kane_sim/kane_sim_node.h"

#include <sys/prctl.h>

#include <cmath>
#include <sstream>
#include <thread>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/callback_queue.h>
#include <ros/master.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/JointState.h>

#include "kane_sim/MechanismState.h"
#include "kane_sim/load_config.h"
#include "kane_sim/ros_messages.h"

namespace kane_sim {
namespace {

// Behind schedule by more than this, the loop stops bursting to catch up and re-anchors.
constexpr double kMaxCatchUp = 0.1;         // [s]
constexpr double kDiagnosticsPeriod = 1.0;  // [s] wall
constexpr double kPausedPoll = 0.002;       // [s] wall, callback wait while paused

double wallSeconds(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

}  // namespace

Config KaneSimNode::loadParameters(const ros::NodeHandle& private_nh) {
  XmlRpc::XmlRpcValue params;
  if (!ros::param::get(private_nh.getNamespace(), params) ||
      params.getType() != XmlRpc::XmlRpcValue::TypeStruct)
    throw ConfigError(private_nh.getNamespace(),
                      "has no parameters: load config/mechanism.yaml into the node's private "
                      "namespace (launch/sim.launch does)");
  LoadedConfig loaded = loadConfig(yamlFromXmlRpc(params));
  for (const std::string& warning : loaded.warnings)
    ROS_WARN("%s (in %s)", warning.c_str(), private_nh.getNamespace().c_str());
  return loaded.config;
}

KaneSimNode::KaneSimNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh)
    : nh_(nh),
      config_(loadParameters(private_nh)),
      frames_(config_.frames),
      sim_(config_),
      command_(config_.command),
      scheduler_(config_.simulation.real_time_factor > 0
                     ? 1.0 / (config_.simulation.physics_rate * config_.simulation.real_time_factor)
                     : 0.0,
                 kMaxCatchUp),
      ticks_per_publish_(static_cast<std::uint64_t>(
          std::lround(config_.simulation.physics_rate / config_.simulation.publish_rate))),
      paused_(config_.simulation.start_paused),
      publish_context_{&sim_.model(), &frames_, config_.command.torque_limit} {
  connect();

  const SimulationSettings& s = config_.simulation;
  ROS_INFO("kane_sim: %s at %g Hz, publishing every %lu steps (%g Hz), real_time_factor %g%s%s",
           integratorName(s.integrator), s.physics_rate,
           static_cast<unsigned long>(ticks_per_publish_), s.publish_rate, s.real_time_factor,
           s.publish_clock ? ", publishing /clock" : "", paused_ ? ", paused" : "");
}

void KaneSimNode::connect() {
  torque_sub_ = nh_.subscribe("torque_command", 10, &KaneSimNode::onTorqueCommand, this,
                              ros::TransportHints().tcpNoDelay());
  joint_state_pub_ = nh_.advertise<sensor_msgs::JointState>("joint_states", 10);
  mechanism_state_pub_ = nh_.advertise<kane_sim::MechanismState>("mechanism_state", 10);
  marker_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("visualization_markers", 10);
  diagnostics_pub_ = nh_.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10);
  if (config_.simulation.publish_clock)
    clock_pub_ = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
  services_ = {nh_.advertiseService("reset", &KaneSimNode::onReset, this),
               nh_.advertiseService("pause", &KaneSimNode::onPause, this),
               nh_.advertiseService("unpause", &KaneSimNode::onUnpause, this),
               nh_.advertiseService("step", &KaneSimNode::onStep, this)};
  tf_broadcaster_ = std::make_unique<tf2_ros::TransformBroadcaster>();
  static_tf_broadcaster_ = std::make_unique<tf2_ros::StaticTransformBroadcaster>();
}

void KaneSimNode::reconnect() {
  // roscpp registers topics and services once; a new master knows nothing of them. Drop them
  // (unregistering from a dead master fails quietly) and register everything again.
  torque_sub_.shutdown();
  for (ros::Publisher* pub :
       {&joint_state_pub_, &mechanism_state_pub_, &marker_pub_, &diagnostics_pub_, &clock_pub_})
    pub->shutdown();
  for (ros::ServiceServer& service : services_) service.shutdown();
  tf_broadcaster_.reset();
  static_tf_broadcaster_.reset();
  connect();
  static_tf_broadcaster_->sendTransform(worldToMechanism(frames_, config_.frames, stamp()));
  ROS_WARN(
      "kane_sim: the ROS master restarted; topics and services registered again "
      "(sim time %.3f s, state kept)",
      sim_.time());
}

void KaneSimNode::watchMaster() {
  // Runs beside the loop: an XML-RPC call per second must not delay a physics tick.
  int last_pid = -1;
  while (ros::ok()) {
    XmlRpc::XmlRpcValue args, result, payload;
    args[0] = ros::this_node::getName();
    if (ros::master::execute("getPid", args, result, payload, false)) {
      const int pid = payload;
      if (last_pid != -1 && pid != last_pid) master_restarted_ = true;
      last_pid = pid;
    }
    for (int i = 0; i < 10 && ros::ok(); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

void KaneSimNode::run() {
  std::thread master_watch(&KaneSimNode::watchMaster, this);
  // Linux lets a sleeping thread wake up to 50 µs late by default ("timer slack") to batch
  // wake-ups; a 1 kHz loop wants its deadlines kept to the microsecond.
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  static_tf_broadcaster_->sendTransform(worldToMechanism(frames_, config_.frames, stamp()));
  publishState();
  const auto now = SteadyClock::now();
  scheduler_.anchor(now);
  window_start_wall_ = last_publish_wall_ = now;
  window_start_sim_ = last_publish_sim_ = sim_.time();
  while (ros::ok()) {
    if (master_restarted_.exchange(false)) reconnect();
    ros::getGlobalCallbackQueue()->callAvailable();
    if (paused_) {
      waitWhilePaused();
      continue;
    }
    runOneTick();
  }
  master_watch.join();
}

void KaneSimNode::runOneTick() {
  if (!scheduler_.freeRunning()) std::this_thread::sleep_until(scheduler_.due());
  const TickScheduler::Timing timing = scheduler_.start(SteadyClock::now());
  stats_.recordTick(timing.lateness, timing.overrun, timing.skipped);
  if (timing.skipped > 0)
    ROS_WARN_THROTTLE(5.0,
                      "kane_sim: fell %.3f s behind the %g Hz schedule; dropped that lag, so sim "
                      "time now runs that much behind wall time (see /diagnostics)",
                      timing.skipped, config_.simulation.physics_rate);
  if (physicsStep() && sim_.ticks() % ticks_per_publish_ == 0) publishState();
  maybeReportLoopHealth();
}

void KaneSimNode::waitWhilePaused() {
  ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(kPausedPoll));
  // Wall-stamped topics keep flowing while paused, so viewers keep a live tf tree; in /clock
  // mode time stands still and nothing new is published.
  if (!config_.simulation.publish_clock &&
      wallSeconds(SteadyClock::now() - last_publish_wall_) >= 1.0 / config_.simulation.publish_rate)
    publishState();
  scheduler_.anchor(SteadyClock::now());  // resume on a fresh schedule
  maybeReportLoopHealth();
}

bool KaneSimNode::physicsStep() {
  bool timed_out_now = false;
  const double torque = command_.applied(sim_.time(), &timed_out_now);
  if (timed_out_now)
    ROS_WARN(
        "kane_sim: no torque_command for %g s (command.timeout): applying 0 N m until the "
        "next command",
        config_.command.timeout);
  sim_.setTorque(torque);  // finite and clamped by TorqueCommand
  const std::uint64_t crossings_before = sim_.sliderCrossings();
  const bool coarse_before = sim_.stepTooCoarse();
  const StepResult result = sim_.step();
  if (!result.ok) ROS_ERROR_THROTTLE(1.0, "kane_sim: %s", result.error.c_str());
  if (crossings_before == 0 && sim_.sliderCrossings() > 0)
    ROS_WARN(
        "kane_sim: slider 4 passed through slider 3 at t = %.3f s: the seed models no "
        "contact between the sliders (counted in mechanism_state/slider_crossings; "
        "reported once per start or reset)",
        sim_.time());
  if (!coarse_before && sim_.stepTooCoarse())
    ROS_WARN(
        "kane_sim: the crank turns %.3f rad per physics step at t = %.3f s (u1 = %.1f rad/s): "
        "rk4 at %g Hz no longer resolves the motion and energy is not conserved; use "
        "simulation/integrator dopri5 or a higher simulation/physics_rate (reported once per "
        "start or reset)",
        std::abs(sim_.state().u1) * sim_.stepSize(), sim_.time(), sim_.state().u1,
        config_.simulation.physics_rate);
  return result.ok;
}

ros::Time KaneSimNode::stamp() const {
  return config_.simulation.publish_clock ? simStamp(sim_.time()) : ros::Time::now();
}

void KaneSimNode::publishState() {
  const ros::Time now = stamp();
  const auto wall_now = SteadyClock::now();
  const double wall_elapsed = wallSeconds(wall_now - last_publish_wall_);
  if (wall_elapsed > 0)
    achieved_real_time_factor_ = (sim_.time() - last_publish_sim_) / wall_elapsed;
  last_publish_wall_ = wall_now;
  last_publish_sim_ = sim_.time();

  if (config_.simulation.publish_clock) {
    rosgraph_msgs::Clock clock;
    clock.clock = now;
    clock_pub_.publish(clock);
  }
  const PublishedMessages msgs = buildMessages(
      publish_context_, sim_.snapshot(), command_.commanded(), achieved_real_time_factor_, now);
  joint_state_pub_.publish(msgs.joint_state);
  mechanism_state_pub_.publish(msgs.mechanism_state);
  marker_pub_.publish(msgs.markers);
  if (now > last_tf_stamp_) {
    tf_broadcaster_->sendTransform(msgs.tf.transforms);
    last_tf_stamp_ = now;
  }
}

void KaneSimNode::maybeReportLoopHealth() {
  const auto now = SteadyClock::now();
  const double wall = wallSeconds(now - window_start_wall_);
  if (wall < kDiagnosticsPeriod) return;
  publishDiagnostics(stats_.takeSummary(wall, sim_.time() - window_start_sim_), wall);
  window_start_wall_ = now;
  window_start_sim_ = sim_.time();
}

void KaneSimNode::publishDiagnostics(const LoopStats::Summary& s, double wall_window) {
  const SimulationSettings& cfg = config_.simulation;
  diagnostic_msgs::DiagnosticStatus status;
  status.name = "kane_sim: physics loop (" + ros::this_node::getName() + ")";
  status.hardware_id = "kane_sim" + ros::this_node::getNamespace();
  const bool on_time = s.overruns <= s.ticks / 1000 && s.skipped == 0.0;
  status.level = (paused_ || on_time) ? diagnostic_msgs::DiagnosticStatus::OK
                                      : diagnostic_msgs::DiagnosticStatus::WARN;
  std::ostringstream msg;
  if (paused_)
    msg << "paused";
  else if (on_time)
    msg << "on schedule";
  else
    msg << s.overruns << " of " << s.ticks << " ticks overran, " << s.skipped << " s lag dropped";
  status.message = msg.str();
  auto add = [&status](const std::string& key, double value) {
    diagnostic_msgs::KeyValue kv;
    kv.key = key;
    std::ostringstream v;
    v << value;
    kv.value = v.str();
    status.values.push_back(kv);
  };
  add("physics rate achieved [Hz]", s.physics_rate);
  add("physics rate target [Hz]", paused_ ? 0.0 : cfg.physics_rate * cfg.real_time_factor);
  add("real-time factor achieved", s.real_time_factor);
  add("real-time factor target", cfg.real_time_factor);
  add("tick lateness p50 [us]", s.lateness_p50 * 1e6);
  add("tick lateness p99 [us]", s.lateness_p99 * 1e6);
  add("tick lateness max [us]", s.lateness_max * 1e6);
  add("overruns", static_cast<double>(s.overruns));
  add("ticks", static_cast<double>(s.ticks));
  add("lag dropped [s]", s.skipped);
  add("sim time [s]", sim_.time());
  add("torque commands received [1/s]", wall_window > 0 ? commands_in_window_ / wall_window : 0.0);
  add("torque commands rejected or clamped", static_cast<double>(commands_refused_in_window_));
  commands_in_window_ = 0;
  commands_refused_in_window_ = 0;
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = stamp();
  array.status.push_back(status);
  diagnostics_pub_.publish(array);
}

void KaneSimNode::onTorqueCommand(const std_msgs::Float64::ConstPtr& msg) {
  std::string message;
  ++commands_in_window_;
  if (command_.receive(msg->data, sim_.time(), &message) != TorqueCommand::Verdict::kAccepted) {
    ++commands_refused_in_window_;
    ROS_WARN_THROTTLE(1.0, "kane_sim: %s", message.c_str());
  }
}

bool KaneSimNode::onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  sim_.reset();
  command_.reset();
  ROS_INFO("kane_sim: reset to the initial state (sim time runs on at %.3f s)", sim_.time());
  publishState();
  return true;
}

bool KaneSimNode::onPause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  paused_ = true;
  return true;
}

bool KaneSimNode::onUnpause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  paused_ = false;
  scheduler_.anchor(SteadyClock::now());
  return true;
}

bool KaneSimNode::onStep(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  if (!paused_) {
    res.success = false;
    res.message = "not paused: call pause first (step advances a paused simulation)";
    return true;
  }
  for (std::uint64_t i = 0; i < ticks_per_publish_; ++i) {
    if (!physicsStep()) {
      res.success = false;
      res.message = "a physics step was refused; see the log";
      return true;
    }
  }
  publishState();
  std::ostringstream msg;
  msg << "advanced " << ticks_per_publish_ << " physics steps to t = " << sim_.time() << " s";
  res.success = true;
  res.message = msg.str();
  return true;
}

}  // namespace kane_sim
