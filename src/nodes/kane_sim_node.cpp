#include "kane_sim_node.h"

#include <sys/prctl.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/callback_queue.h>
#include <rosgraph_msgs/Clock.h>
#include <tf2_msgs/TFMessage.h>

#include "event_log.h"
#include "kane_sim/Checkpoint.h"
#include "kane_sim/MechanismState.h"
#include "kane_sim/ResetEvent.h"
#include "kane_sim/ros/messages.h"
#include "kane_sim/sim/config_check.h"
#include "loop/master_watch.h"
#include "loop/realtime.h"

namespace kane_sim {
namespace {

using SteadyClock = std::chrono::steady_clock;

// Behind schedule by more than this, the loop stops bursting to catch up and re-anchors.
constexpr double kMaxCatchUp = 0.1;          // [s]
constexpr double kDiagnosticsPeriod = 1.0;   // [s] wall
constexpr double kPausedPoll = 0.002;        // [s] wall, callback wait while paused
constexpr double kPausedRepeatPeriod = 1.0;  // [s] wall, the last state again in /clock mode
// A periodic ~checkpoint every this much sim time: a bag recorded from any point replays from
// the last one before it (latched) at the cost of ~2 KB per checkpoint.
constexpr double kCheckpointPeriod = 10.0;  // [s] sim

// Wall seconds per physics tick; 0 runs free (real_time_factor 0).
double tickPeriod(const SimulationSettings& s) {
  return s.real_time_factor > 0 ? 1.0 / (s.physics_rate * s.real_time_factor) : 0.0;
}

}  // namespace

KaneSimNode::KaneSimNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh)
    : nh_(nh),
      private_nh_(private_nh),
      parameter_tree_(RuntimeParameters::readTree(private_nh)),
      config_(RuntimeParameters::load(parameter_tree_, private_nh)),
      robot_(describeRobot(config_)),
      diagnostics_(config_.diagnostics),
      driver_(config_, [this](const SimEvent& event) { logSimEvent(event, &diagnostics_); }),
      loop_(tickPeriod(config_.simulation), kMaxCatchUp),
      ticks_per_publish_(static_cast<std::uint64_t>(
          wholeStepsPerPeriod(config_.simulation.physics_rate, config_.simulation.publish_rate))),
      checkpoint_ticks_(std::max<std::uint64_t>(
          1, static_cast<std::uint64_t>(
                 std::llround(kCheckpointPeriod * config_.simulation.physics_rate)))),
      lockstep_(config_, &driver_, &diagnostics_, &io_),
      publisher_(config_, robot_, &driver_, &io_, &lockstep_),
      services_(&driver_, &publisher_, &loop_, config_.simulation.start_paused,
                ticks_per_publish_) {
  connect();
  driver_.setInputHandler([this](const DriverInput& input) { publisher_.logInput(input); });
  runtime_parameters_ = std::make_unique<RuntimeParameters>(
      private_nh_, parameter_tree_, config_, [this](const Config& c) { onReconfigure(c); },
      [this](const Config& c) { return reconfigureVeto(c); });
  publisher_.setConfigTree(runtime_parameters_->tree());

  const SimulationSettings& s = config_.simulation;
  ROS_INFO("kane_sim: %s at %g Hz, publishing every %lu steps (%g Hz), real_time_factor %g%s%s",
           integratorName(s.integrator), s.physics_rate,
           static_cast<unsigned long>(ticks_per_publish_), s.publish_rate, s.real_time_factor,
           s.publish_clock ? ", publishing /clock" : "", services_.paused() ? ", paused" : "");
}

void KaneSimNode::connect() {
  const auto fast = ros::TransportHints().tcpNoDelay();
  io_.torque_command =
      nh_.subscribe("torque_command", 10, &KaneSimNode::onTorqueCommand, this, fast);
  io_.torque_command_stamped =
      nh_.subscribe("torque_command_stamped", 10, &LockstepLink::onCommand, &lockstep_, fast);
  io_.servo_setpoint =
      nh_.subscribe("servo_setpoint", 10, &KaneSimNode::onServoSetpoint, this, fast);
  if (driver_.servoMode()) io_.servo_state = nh_.advertise<ServoState>("servo_state", 10);
  io_.joint_states = nh_.advertise<sensor_msgs::JointState>(kJointStatesTopic, 10);
  if (driver_.sensorsEnabled())
    io_.joint_states_true = nh_.advertise<sensor_msgs::JointState>(truthJointStatesTopic(true), 10);
  io_.mechanism_state = nh_.advertise<MechanismState>("mechanism_state", 10);
  io_.markers = nh_.advertise<visualization_msgs::MarkerArray>("visualization_markers", 10);
  io_.diagnostics = nh_.advertise<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10);
  io_.reset_event = private_nh_.advertise<ResetEvent>("reset_event", 10);
  // A deep queue: a bag needs every input, and step_with_command can send bursts.
  io_.input_log = private_nh_.advertise<InputLog>("input_log", 1000);
  // Latched: a recorder that starts mid-run gets the last one, and its bag replays from there.
  io_.checkpoint = private_nh_.advertise<Checkpoint>("checkpoint", 1, true);
  if (config_.simulation.publish_clock)
    io_.clock = nh_.advertise<rosgraph_msgs::Clock>("/clock", 10);
  io_.services = services_.advertise(private_nh_);
  if (config_.frames.publish_tf) {
    // What tf2_ros::TransformBroadcaster does, with the publisher at hand: its subscriber count
    // tells when a listener joined while the stamp stands still (NodeInterfaces::publishTf).
    io_.tf = nh_.advertise<tf2_msgs::TFMessage>("/tf", 100);
    io_.static_tf = std::make_unique<tf2_ros::StaticTransformBroadcaster>();
  }
}

void KaneSimNode::reconnect() {
  // roscpp registers topics and services once; a new master knows nothing of them. Drop them
  // (unregistering from a dead master fails quietly) and register everything again.
  io_.shutdown();
  connect();
  if (runtime_parameters_) runtime_parameters_->advertise();
  publisher_.publishRobotDescription(nh_);  // a new master has no parameters either
  publisher_.publishStaticTf();             // nor the latched static tf
  publisher_.publishCheckpoint("start");    // the latched one went with the old master
  ROS_WARN(
      "kane_sim: the ROS master restarted; topics and services registered again "
      "(sim time %.3f s, state kept)",
      driver_.time());
}

void KaneSimNode::run() {
  MasterWatch master_watch;  // its thread first: it keeps the normal policy
  const RealtimePolicy realtime = applyRealtimePolicy(config_.simulation.realtime_priority,
                                                      config_.simulation.real_time_factor);
  realtime_scheduled_ = realtime.scheduled;
  if (!realtime.report.empty()) {
    if (realtime.warn)
      ROS_WARN("kane_sim: %s", realtime.report.c_str());
    else
      ROS_INFO("kane_sim: %s", realtime.report.c_str());
  }
  // Linux lets a sleeping thread wake up to 50 µs late by default ("timer slack") to batch
  // wake-ups; a 1 kHz loop wants its deadlines kept to the microsecond.
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  publisher_.checkSimTimeSetting();
  publisher_.publishRobotDescription(nh_);
  publisher_.publishStaticTf();
  publisher_.publishStateAndReadings();  // the reading at start, when it has no latency
  publisher_.publishCheckpoint("start");
  loop_.anchor();
  publisher_.pace().start(SteadyClock::now(), driver_.time());
  while (ros::ok()) {
    if (master_watch.restarted()) reconnect();
    ros::getGlobalCallbackQueue()->callAvailable();
    if (services_.paused()) {
      waitWhilePaused();
      continue;
    }
    runOneTick();
  }
}

void KaneSimNode::runOneTick() {
  const auto interrupted = [this] { return !ros::ok() || services_.paused(); };
  if (!loop_.waitForTick(*ros::getGlobalCallbackQueue(), interrupted)) return;
  if (!isStampable(driver_.time() + 1.0 / config_.simulation.physics_rate)) {
    // Stamps would leave ROS's time range: stop stepping, say why, keep serving.
    if (!stopped_at_time_limit_)
      ROS_ERROR(
          "kane_sim: sim time %.0f s reached the largest ROS can stamp (%.0f s after the sim "
          "epoch): physics stopped, the last state stays published; restart the node",
          driver_.time(), kMaxStampableSimTime);
    stopped_at_time_limit_ = true;
    services_.pause();
    return;
  }
  if (!lockstep_.released()) {
    if (!lockstep_.waitForAnswer(interrupted, [this] { maybeReportLoopHealth(); })) return;
    loop_.anchor();  // waiting for the controller is not lateness
  }
  const TickScheduler::Timing timing = loop_.startTick();
  stats_.recordTick(timing.lateness, timing.overrun, timing.skipped);
  if (timing.skipped > 0)
    ROS_WARN_THROTTLE(5.0,
                      "kane_sim: fell %.3f s behind the %g Hz schedule; dropped that lag, so sim "
                      "time now runs that much behind wall time (see /diagnostics)",
                      timing.skipped, config_.simulation.physics_rate);
  if (driver_.step()) {
    if (driver_.ticks() % ticks_per_publish_ == 0) publisher_.publishState();
    publisher_.publishDueSensorReadings();
    if (driver_.ticks() % checkpoint_ticks_ == 0) publisher_.publishCheckpoint("periodic");
  } else if (publisher_.pace().dueByWallClock(SteadyClock::now())) {
    // Refused steps: the last good state keeps flowing, freshly stamped (on the wall clock).
    if (!config_.simulation.publish_clock) publisher_.restamp();
    publisher_.publishState();
  }
  maybeReportLoopHealth();
}

void KaneSimNode::waitWhilePaused() {
  ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(kPausedPoll));
  // Wall-stamped topics keep flowing while paused, so viewers keep a live tf tree. In /clock
  // mode time stands still: the last state and /clock are repeated with their stamp, slowly, so
  // that a late subscriber (rviz, rostopic echo /clock) sees the robot and the time.
  const PublishPace& pace = publisher_.pace();
  if (!config_.simulation.publish_clock) {
    if (pace.dueByWallClock(SteadyClock::now())) {
      publisher_.restamp();  // a repeat at a later wall time: a later stamp
      publisher_.publishState();
    }
  } else if (pace.sinceLastPublish(SteadyClock::now()) >= kPausedRepeatPeriod) {
    publisher_.publishState();  // the same stamp: /tf goes only to listeners that joined since
  }
  loop_.anchor();  // resume on a fresh schedule
  maybeReportLoopHealth();
}

void KaneSimNode::maybeReportLoopHealth() {
  const auto now = SteadyClock::now();
  PublishPace& pace = publisher_.pace();
  const double wall = pace.windowWall(now);
  if (wall < kDiagnosticsPeriod) return;
  publisher_.checkSimTimeSetting();
  const SimulationSettings& cfg = config_.simulation;
  const LoopDiagnostics::LoopState loop{ros::this_node::getName(),
                                        ros::this_node::getNamespace(),
                                        services_.paused(),
                                        stopped_at_time_limit_,
                                        cfg.physics_rate,
                                        cfg.real_time_factor,
                                        driver_.time()};
  diagnostic_msgs::DiagnosticArray array;
  array.status.push_back(diagnostics_.close(
      stats_.takeSummary(wall, pace.closeWindow(now, driver_.time())), wall, loop));
  array.header.stamp = publisher_.stamp();
  io_.diagnostics.publish(array);
}

void KaneSimNode::onServoSetpoint(const std_msgs::Float64::ConstPtr& msg) {
  diagnostics_.commandReceived(driver_.setpoint(msg->data) != TorqueCommand::Verdict::kAccepted);
}

void KaneSimNode::onTorqueCommand(const std_msgs::Float64::ConstPtr& msg) {
  diagnostics_.commandReceived(driver_.command(msg->data) != TorqueCommand::Verdict::kAccepted);
}

std::string KaneSimNode::reconfigureVeto(const Config& config) const {
  if (realtime_scheduled_ && config.simulation.real_time_factor == 0.0)
    return "real_time_factor 0 while the physics loop runs at SCHED_FIFO priority " +
           std::to_string(config_.simulation.realtime_priority) +
           ": a loop that never sleeps would hold a core at real-time priority; start the node "
           "with real_time_factor 0 instead (realtime_priority is then ignored)";
  return "";
}

void KaneSimNode::onReconfigure(const Config& config) {
  const double old_factor = config_.simulation.real_time_factor;
  driver_.reconfigure(config);
  config_ = config;                 // what cannot be reconfigured comes back as it was
  robot_ = describeRobot(config_);  // masses and inertia are in the URDF
  publisher_.publishRobotDescription(nh_);
  if (config_.simulation.real_time_factor != old_factor)
    loop_.setPeriod(tickPeriod(config_.simulation));
  publisher_.setConfigTree(runtime_parameters_->tree());
  publisher_.publishCheckpoint("reconfigure");
  ROS_INFO("kane_sim: reconfigured (from the next physics step): %s",
           RuntimeParameters::summary(config_).c_str());
}

}  // namespace kane_sim
