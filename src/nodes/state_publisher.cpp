#include "state_publisher.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <rosgraph_msgs/Clock.h>

#include "kane_sim/Checkpoint.h"
#include "kane_sim/description/urdf.h"
#include "kane_sim/ros/messages.h"
#include "kane_sim/sim/checkpoint.h"

namespace kane_sim {

StatePublisher::StatePublisher(const Config& config, const RobotDescription& robot,
                               SimDriver* driver, NodeInterfaces* io, LockstepLink* lockstep)
    : config_(config),
      robot_(robot),
      driver_(*driver),
      io_(io),
      lockstep_(lockstep),
      stamp_clock_(config.simulation.publish_clock),
      pace_(config.simulation.publish_rate) {}

ros::Time StatePublisher::stamp() {
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

void StatePublisher::checkSimTimeSetting() {
  bool use_sim_time = false;
  ros::param::getCached("/use_sim_time", use_sim_time);
  const std::string warning = stamp_clock_.checkUseSimTime(use_sim_time);
  if (!warning.empty()) ROS_WARN("kane_sim: %s", warning.c_str());
}

void StatePublisher::publishState() {
  const ros::Time now = stamp();
  last_state_stamp_ = now;
  pace_.published(std::chrono::steady_clock::now(), driver_.time());
  if (config_.simulation.publish_clock) {
    rosgraph_msgs::Clock clock;
    clock.clock = now;
    io_->clock.publish(clock);
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
    io_->joint_states_true.publish(msgs.joint_state);
  else
    lockstep_->publish(msgs.joint_state);
  io_->mechanism_state.publish(msgs.mechanism_state);
  if (io_->servo_state)
    io_->servo_state.publish(servoStateMessage(snapshot, config_.command.mode, now));
  io_->markers.publish(msgs.markers);
  io_->publishTf(msgs.tf, now);
}

void StatePublisher::publishDueSensorReadings() {
  const auto finite = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
  };
  SensorReading reading;
  while (driver_.takeSensorReading(&reading)) {
    const sensor_msgs::JointState msg = jointStateMessage(reading.joints, stamp());
    if (finite(msg.position) && finite(msg.velocity) && finite(msg.effort)) {
      lockstep_->publish(msg);
      continue;
    }
    ROS_ERROR_THROTTLE(1.0,
                       "kane_sim: a sensor reading sampled at t = %.6f s is not finite; not "
                       "published (please report this with the config)",
                       reading.sample_time);
  }
}

void StatePublisher::publishMovedState() {
  // In lockstep only an answer to the new stamp releases the next step: a stale answer to the
  // state before the move matches nothing.
  stamp_valid_ = false;
  stamp_clock_.forceNext();
  publishStateAndReadings();
}

void StatePublisher::announceReset(const std::string& cause) {
  io_->reset_event.publish(
      resetEventMessage(cause, driver_.time(), driver_.simulator().state(), last_state_stamp_));
}

void StatePublisher::publishCheckpoint(const std::string& cause) {
  kane_sim::Checkpoint msg;
  msg.header.stamp = stamp();
  msg.cause = cause;
  msg.tick = driver_.ticks();
  msg.next_input = input_seq_;
  msg.config = config_text_;
  msg.state = checkpointText(driver_.checkpoint());
  io_->checkpoint.publish(msg);
}

void StatePublisher::logInput(const DriverInput& input) {
  io_->input_log.publish(inputLogMessage(input, stamp(), input_seq_++));
}

void StatePublisher::publishRobotDescription(ros::NodeHandle& nh) {
  // Relative: under ns:=robot_a it is /robot_a/robot_description, beside that robot's topics.
  nh.setParam("robot_description", toUrdf(robot_));
}

void StatePublisher::publishStaticTf() {
  if (io_->static_tf) io_->static_tf->sendTransform(staticTransforms(robot_, stamp()));
}

}  // namespace kane_sim
