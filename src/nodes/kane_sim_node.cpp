#include "kane_sim_node.h"

#include <sys/prctl.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <thread>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <ros/callback_queue.h>
#include <ros/master.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/JointState.h>
#include <tf2_msgs/TFMessage.h>

#include "event_log.h"
#include "kane_sim/MechanismState.h"
#include "kane_sim/ResetEvent.h"
#include "kane_sim/config/load_config.h"
#include "kane_sim/description/urdf.h"
#include "kane_sim/format_number.h"
#include "kane_sim/ros/messages.h"
#include "kane_sim/ros/param_yaml.h"
#include "kane_sim/sim/config_check.h"
#include "loop/master_watch.h"
#include "loop/realtime.h"

namespace kane_sim {
namespace {

// Behind schedule by more than this, the loop stops bursting to catch up and re-anchors.
constexpr double kMaxCatchUp = 0.1;          // [s]
constexpr double kDiagnosticsPeriod = 1.0;   // [s] wall
constexpr double kPausedPoll = 0.002;        // [s] wall, callback wait while paused
constexpr double kPausedRepeatPeriod = 1.0;  // [s] wall, the last state again in /clock mode
// ~step_with_command runs for at most this much wall time (SimDriver::stepHeld bounds its
// steps): dopri5 at a violent state once took 24.6 s for 2000 steps while ~pause and Ctrl-C
// waited. A call that runs out answers the state it reached (success false, the reason).
constexpr double kStepCallBudget = 2.0;  // [s] wall
// A periodic ~checkpoint every this much sim time: a bag recorded from any point replays from
// the last one before it (latched) at the cost of ~2 KB per checkpoint.
constexpr double kCheckpointPeriod = 10.0;  // [s] sim

// Wall seconds per physics tick; 0 runs free (real_time_factor 0).
double tickPeriod(const SimulationSettings& s) {
  return s.real_time_factor > 0 ? 1.0 / (s.physics_rate * s.real_time_factor) : 0.0;
}

double wallSeconds(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

}  // namespace

KaneSimNode::KaneSimNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh)
    : nh_(nh),
      private_nh_(private_nh),
      parameter_tree_(RuntimeParameters::readTree(private_nh)),
      config_(RuntimeParameters::load(parameter_tree_, private_nh)),
      robot_(describeRobot(config_)),
      driver_(config_, [this](const SimEvent& event) { logSimEvent(event, &diagnostics_); }),
      loop_(tickPeriod(config_.simulation), kMaxCatchUp),
      diagnostics_(config_.diagnostics),
      stamp_clock_(config_.simulation.publish_clock),
      ticks_per_publish_(static_cast<std::uint64_t>(
          wholeStepsPerPeriod(config_.simulation.physics_rate, config_.simulation.publish_rate))),
      paused_(config_.simulation.start_paused),
      checkpoint_ticks_(std::max<std::uint64_t>(
          1, static_cast<std::uint64_t>(
                 std::llround(kCheckpointPeriod * config_.simulation.physics_rate)))),
      pace_(config_.simulation.publish_rate) {
  connect();
  driver_.setInputHandler([this](const DriverInput& input) {
    io_.input_log.publish(inputLogMessage(input, stamp(), input_seq_++));
  });
  runtime_parameters_ = std::make_unique<RuntimeParameters>(
      private_nh_, parameter_tree_, config_, [this](const Config& c) { onReconfigure(c); },
      [this](const Config& c) { return reconfigureVeto(c); });

  const SimulationSettings& s = config_.simulation;
  ROS_INFO("kane_sim: %s at %g Hz, publishing every %lu steps (%g Hz), real_time_factor %g%s%s",
           integratorName(s.integrator), s.physics_rate,
           static_cast<unsigned long>(ticks_per_publish_), s.publish_rate, s.real_time_factor,
           s.publish_clock ? ", publishing /clock" : "", paused_ ? ", paused" : "");
}

void KaneSimNode::connect() {
  const auto fast = ros::TransportHints().tcpNoDelay();
  io_.torque_command =
      nh_.subscribe("torque_command", 10, &KaneSimNode::onTorqueCommand, this, fast);
  io_.torque_command_stamped =
      nh_.subscribe("torque_command_stamped", 10, &KaneSimNode::onTorqueCommandStamped, this, fast);
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
  // Private, as Gazebo's /gazebo/pause_physics: two sims (or turtlesim's /reset) never collide.
  io_.services = {
      private_nh_.advertiseService("reset", &KaneSimNode::onReset, this),
      private_nh_.advertiseService("pause", &KaneSimNode::onPause, this),
      private_nh_.advertiseService("unpause", &KaneSimNode::onUnpause, this),
      private_nh_.advertiseService("step", &KaneSimNode::onStep, this),
      private_nh_.advertiseService("set_state", &KaneSimNode::onSetState, this),
      private_nh_.advertiseService("step_with_command", &KaneSimNode::onStepWithCommand, this)};
  if (config_.frames.publish_tf) {
    // What tf2_ros::TransformBroadcaster does, with the publisher at hand: its subscriber count
    // tells when a listener joined while the stamp stands still (NodeInterfaces::publishTf).
    io_.tf = nh_.advertise<tf2_msgs::TFMessage>("/tf", 100);
    io_.static_tf = std::make_unique<tf2_ros::StaticTransformBroadcaster>();
  }
}

void KaneSimNode::publishRobotDescription() {
  // Relative: under ns:=robot_a it is /robot_a/robot_description, beside that robot's topics.
  nh_.setParam("robot_description", toUrdf(robot_));
  if (io_.static_tf) io_.static_tf->sendTransform(staticTransforms(robot_, stamp()));
}

void KaneSimNode::reconnect() {
  // roscpp registers topics and services once; a new master knows nothing of them. Drop them
  // (unregistering from a dead master fails quietly) and register everything again.
  io_.shutdown();
  connect();
  if (runtime_parameters_) runtime_parameters_->advertise();
  publishRobotDescription();   // a new master has no parameters either
  publishCheckpoint("start");  // the latched one went with the old master
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
  checkSimTimeSetting();
  publishRobotDescription();
  publishState();
  publishDueSensorReadings();  // the reading at start, when it has no latency
  publishCheckpoint("start");
  const auto now = SteadyClock::now();
  loop_.anchor();
  pace_.start(now, driver_.time());
  while (ros::ok()) {
    if (master_watch.restarted()) reconnect();
    ros::getGlobalCallbackQueue()->callAvailable();
    if (paused_) {
      waitWhilePaused();
      continue;
    }
    runOneTick();
  }
}

void KaneSimNode::runOneTick() {
  if (!loop_.waitForTick(*ros::getGlobalCallbackQueue(), [this] { return !ros::ok() || paused_; }))
    return;
  if (!isStampable(driver_.time() + 1.0 / config_.simulation.physics_rate)) {
    // Stamps would leave ROS's time range: stop stepping, say why, keep serving.
    if (!stopped_at_time_limit_)
      ROS_ERROR(
          "kane_sim: sim time %.0f s reached the largest ROS can stamp (%.0f s after the sim "
          "epoch): physics stopped, the last state stays published; restart the node",
          driver_.time(), kMaxStampableSimTime);
    stopped_at_time_limit_ = paused_ = true;
    return;
  }
  if (config_.simulation.lockstep && !lockstep_.answered()) {
    if (!waitForLockstepAnswer()) return;
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
    if (driver_.ticks() % ticks_per_publish_ == 0) publishState();
    publishDueSensorReadings();
    if (driver_.ticks() % checkpoint_ticks_ == 0) publishCheckpoint("periodic");
  } else if (pace_.dueByWallClock(SteadyClock::now())) {
    // Refused steps: the last good state keeps flowing, freshly stamped (on the wall clock).
    if (!config_.simulation.publish_clock) stamp_valid_ = false;
    publishState();
  }
  maybeReportLoopHealth();
}

void KaneSimNode::waitWhilePaused() {
  ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(kPausedPoll));
  // Wall-stamped topics keep flowing while paused, so viewers keep a live tf tree. In /clock
  // mode time stands still: the last state and /clock are repeated with their stamp, slowly, so
  // that a late subscriber (rviz, rostopic echo /clock) sees the robot and the time.
  if (!config_.simulation.publish_clock) {
    if (pace_.dueByWallClock(SteadyClock::now())) {
      stamp_valid_ = false;  // a repeat at a later wall time: a later stamp
      publishState();
    }
  } else if (pace_.sinceLastPublish(SteadyClock::now()) >= kPausedRepeatPeriod) {
    publishState();  // the same stamp: /tf goes only to listeners that joined since
  }
  loop_.anchor();  // resume on a fresh schedule
  maybeReportLoopHealth();
}

ros::Time KaneSimNode::stamp() {
  // One stamp per physics tick for everything published at it (state, sensor readings, truth,
  // tf, /clock): a reading pairs with its truth by stamp.
  if (stamp_valid_ && stamped_tick_ == driver_.ticks()) return tick_stamp_;
  double went_back = 0.0;
  const ros::Time now = stamp_clock_.stamp(driver_.time(), ros::WallTime::now(), &went_back);
  if (went_back > 0.01)
    ROS_WARN_THROTTLE(10.0,
                      "kane_sim: the system clock went back by %.3f s; stamps are held "
                      "monotonic until it catches up",
                      went_back);
  tick_stamp_ = now;
  stamped_tick_ = driver_.ticks();
  stamp_valid_ = true;
  return now;
}

void KaneSimNode::checkSimTimeSetting() {
  bool use_sim_time = false;
  ros::param::getCached("/use_sim_time", use_sim_time);
  const std::string warning = stamp_clock_.checkUseSimTime(use_sim_time);
  if (!warning.empty()) ROS_WARN("kane_sim: %s", warning.c_str());
}

void KaneSimNode::publishJointStates(const sensor_msgs::JointState& msg) {
  lockstep_.published(msg.header.stamp);
  last_joint_states_ = msg;
  lockstep_listeners_ = lockstepListeners();
  io_.joint_states.publish(msg);
}

uint32_t KaneSimNode::lockstepListeners() const {
  return io_.joint_states.getNumSubscribers() + io_.torque_command_stamped.getNumPublishers();
}

void KaneSimNode::publishDueSensorReadings() {
  SensorReading reading;
  while (driver_.takeSensorReading(&reading)) {
    const sensor_msgs::JointState msg = jointStateMessage(reading.joints, stamp());
    const auto finite = [](const std::vector<double>& v) {
      return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
    };
    if (!finite(msg.position) || !finite(msg.velocity) || !finite(msg.effort)) {
      ROS_ERROR_THROTTLE(1.0,
                         "kane_sim: a sensor reading sampled at t = %.6f s is not finite; not "
                         "published (please report this with the config)",
                         reading.sample_time);
      continue;
    }
    publishJointStates(msg);
  }
}

void KaneSimNode::publishState() {
  const ros::Time now = stamp();
  last_state_stamp_ = now;
  pace_.published(SteadyClock::now(), driver_.time());

  if (config_.simulation.publish_clock) {
    rosgraph_msgs::Clock clock;
    clock.clock = now;
    io_.clock.publish(clock);
  }
  const Snapshot snapshot = driver_.snapshot();
  if (!snapshot.allFinite()) {
    // Never sent: a subscriber must not receive inf or NaN. The core refuses states and steps
    // that would give one, so this is a defect to report, not an expected path.
    ROS_ERROR_THROTTLE(1.0,
                       "kane_sim: the state at t = %.6f s has a non-finite derived quantity; "
                       "nothing published (please report this with the config and commands)",
                       driver_.time());
    return;
  }
  const PublishedMessages msgs = buildMessages(snapshot, robot_, pace_.realTimeFactor(), now);
  if (driver_.sensorsEnabled())
    io_.joint_states_true.publish(msgs.joint_state);
  else
    publishJointStates(msgs.joint_state);
  io_.mechanism_state.publish(msgs.mechanism_state);
  if (io_.servo_state)
    io_.servo_state.publish(servoStateMessage(snapshot, config_.command.mode, now));
  io_.markers.publish(msgs.markers);
  io_.publishTf(msgs.tf, now);
}

void KaneSimNode::maybeReportLoopHealth() {
  const auto now = SteadyClock::now();
  const double wall = pace_.windowWall(now);
  if (wall < kDiagnosticsPeriod) return;
  checkSimTimeSetting();
  const SimulationSettings& cfg = config_.simulation;
  const LoopDiagnostics::LoopState loop{ros::this_node::getName(),
                                        ros::this_node::getNamespace(),
                                        paused_,
                                        stopped_at_time_limit_,
                                        cfg.physics_rate,
                                        cfg.real_time_factor,
                                        driver_.time()};
  diagnostic_msgs::DiagnosticArray array;
  array.status.push_back(diagnostics_.close(
      stats_.takeSummary(wall, pace_.closeWindow(now, driver_.time())), wall, loop));
  array.header.stamp = stamp();
  io_.diagnostics.publish(array);
}

void KaneSimNode::onTorqueCommandStamped(
    const ros::MessageEvent<TorqueCommandStamped const>& event) {
  const TorqueCommandStamped& msg = *event.getConstMessage();
  const auto apply = [this, &msg] {
    diagnostics_.commandReceived(driver_.command(msg.torque) != TorqueCommand::Verdict::kAccepted);
  };
  if (!config_.simulation.lockstep) return apply();
  // In lockstep only the first answer to the state in force is applied, whatever the timing.
  switch (lockstep_.answer(msg.header.stamp, event.getPublisherName(), msg.torque)) {
    case LockstepGate::Verdict::kApply:
      return apply();
    case LockstepGate::Verdict::kDuplicate:
      if (!lockstep_.warning().empty()) ROS_WARN("kane_sim: %s", lockstep_.warning().c_str());
      return;
    case LockstepGate::Verdict::kLate:
      ROS_DEBUG_THROTTLE(1.0, "kane_sim: lockstep: dropped a late torque_command_stamped");
      return;
    case LockstepGate::Verdict::kUnknown:
      ROS_WARN_THROTTLE(5.0, "kane_sim: %s", lockstep_.warning().c_str());
      return;
  }
}

bool KaneSimNode::waitForLockstepAnswer() {
  const auto deadline =
      SteadyClock::now() + std::chrono::duration_cast<SteadyClock::duration>(
                               std::chrono::duration<double>(config_.simulation.lockstep_timeout));
  while (!lockstep_.answered()) {
    if (!ros::ok() || paused_) return false;
    // A controller that connected since the state went out (at start-up, a restarted one)
    // never heard it: the state awaiting an answer goes out again for it.
    const uint32_t listeners = lockstepListeners();
    if (listeners > lockstep_listeners_ && lockstep_.hasState())
      io_.joint_states.publish(last_joint_states_);
    lockstep_listeners_ = listeners;
    if (SteadyClock::now() >= deadline) {
      diagnostics_.lockstepTimedOut();
      const bool zero = config_.simulation.lockstep_fallback == LockstepFallback::kZero;
      if (zero) driver_.command(0.0);
      ROS_WARN_THROTTLE(
          5.0, "kane_sim: %s",
          lockstep_.timeoutReport(driver_.time(), config_.simulation.lockstep_timeout, zero)
              .c_str());
      lockstep_.release();
      break;
    }
    ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(0.001));
    maybeReportLoopHealth();  // /diagnostics goes on while a slow controller thinks
  }
  return true;
}

void KaneSimNode::onServoSetpoint(const std_msgs::Float64::ConstPtr& msg) {
  diagnostics_.commandReceived(driver_.setpoint(msg->data) != TorqueCommand::Verdict::kAccepted);
}

void KaneSimNode::onTorqueCommand(const std_msgs::Float64::ConstPtr& msg) {
  diagnostics_.commandReceived(driver_.command(msg->data) != TorqueCommand::Verdict::kAccepted);
}

bool KaneSimNode::onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  driver_.reset();
  ROS_INFO("kane_sim: reset to the initial state (sim time runs on at %.3f s)", driver_.time());
  publishMovedState();
  publishCheckpoint("reset");
  announceReset("reset");
  return true;
}

bool KaneSimNode::onSetState(SetState::Request& req, SetState::Response& res) {
  State target{req.q1, req.q2, req.u1, req.u2};
  if (req.spring_at_rest) target = driver_.simulator().model().withSpringAtRest(target);
  const Status result = driver_.setState(target);
  res.success = result.ok;
  if (!result.ok) {
    res.message = "set_state refused: " + result.error;
    ROS_WARN("kane_sim: %s", res.message.c_str());
    return true;
  }
  std::ostringstream msg;
  msg << "state set to q1 = " << target.q1 << " rad, q2 = " << target.q2 << " m, u1 = " << target.u1
      << " rad/s, u2 = " << target.u2 << " m/s at t = " << driver_.time() << " s";
  res.message = msg.str();
  ROS_INFO("kane_sim: %s", res.message.c_str());
  publishMovedState();
  publishCheckpoint("set_state");
  announceReset("set_state");
  return true;
}

void KaneSimNode::publishCheckpoint(const std::string& cause) {
  kane_sim::Checkpoint msg;
  msg.header.stamp = stamp();
  msg.cause = cause;
  msg.tick = driver_.ticks();
  msg.next_input = input_seq_;
  // The config's text changes only at a reconfiguration: written once per change, not per
  // periodic checkpoint.
  if (checkpoint_config_.empty())
    checkpoint_config_ =
        YAML::Dump(runtime_parameters_ ? runtime_parameters_->tree() : parameter_tree_);
  msg.config = checkpoint_config_;
  msg.state = checkpointText(driver_.checkpoint());
  io_.checkpoint.publish(msg);
}

void KaneSimNode::publishMovedState() {
  // A stamp after every earlier one, also in /clock mode where sim time stands still: tf
  // listeners take the moved pose at it, and in lockstep only an answer to it releases the
  // next step (a stale answer to the state before the move matches nothing).
  stamp_valid_ = false;
  stamp_clock_.forceNext();
  publishState();
  // With sensors on, joint_states goes on with readings of the moved state as they arrive,
  // each answered as it comes.
  publishDueSensorReadings();
}

void KaneSimNode::announceReset(const std::string& cause) {
  io_.reset_event.publish(
      resetEventMessage(cause, driver_.time(), driver_.simulator().state(), last_state_stamp_));
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
  publishRobotDescription();
  if (config_.simulation.real_time_factor != old_factor)
    loop_.setPeriod(tickPeriod(config_.simulation));
  checkpoint_config_.clear();  // the tree changed: written again at this checkpoint
  publishCheckpoint("reconfigure");
  ROS_INFO("kane_sim: reconfigured (from the next physics step): %s",
           RuntimeParameters::summary(config_).c_str());
}

bool KaneSimNode::onPause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  paused_ = true;
  return true;
}

bool KaneSimNode::onUnpause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  paused_ = false;
  loop_.anchor();
  return true;
}

bool KaneSimNode::onStep(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  if (!paused_) {
    res.success = false;
    res.message = "not paused: call pause first (step advances a paused simulation)";
    return true;
  }
  for (std::uint64_t i = 0; i < ticks_per_publish_; ++i) {
    if (!driver_.step()) {
      res.success = false;
      res.message = "a physics step was refused; see the log";
      return true;
    }
  }
  publishState();
  publishDueSensorReadings();
  std::ostringstream msg;
  msg << "advanced " << ticks_per_publish_ << " physics steps to t = " << driver_.time() << " s";
  res.success = true;
  res.message = msg.str();
  return true;
}

bool KaneSimNode::onStepWithCommand(StepWithCommand::Request& req, StepWithCommand::Response& res) {
  SimDriver::HeldSteps held;
  if (!paused_) {
    held.message =
        "not paused: call ~pause first (step_with_command advances a paused simulation); nothing "
        "changed";
  } else {
    const auto wall_start = SteadyClock::now();
    held = driver_.stepHeld(req.torque, req.steps, [&wall_start]() -> std::string {
      if (wallSeconds(SteadyClock::now() - wall_start) > kStepCallBudget)
        return "the call's wall-time budget of " + formatNumber(kStepCallBudget) +
               " s ran out (ask for fewer steps per call)";
      return !ros::ok() || ros::isShuttingDown() ? "the node is shutting down" : "";
    });
  }
  if (!held.refused && paused_) {
    publishState();
    publishDueSensorReadings();
  }
  // The state as it is (a refusal never answers zeros).
  const Snapshot snapshot = driver_.snapshot();
  res.time = snapshot.time;
  res.q1 = snapshot.state.q1, res.q2 = snapshot.state.q2;
  res.u1 = snapshot.state.u1, res.u2 = snapshot.state.u2;
  res.applied_torque = snapshot.torque;
  res.success = held.finished;
  res.message = held.message;
  return true;
}

}  // namespace kane_sim
