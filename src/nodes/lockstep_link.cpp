#include "lockstep_link.h"

#include <chrono>

#include <ros/callback_queue.h>

namespace kane_sim {

void LockstepLink::publish(const sensor_msgs::JointState& msg) {
  gate_.published(msg.header.stamp);
  last_joint_states_ = msg;
  listeners_ = listeners();
  io_->joint_states.publish(msg);
}

uint32_t LockstepLink::listeners() const {
  return io_->joint_states.getNumSubscribers() + io_->torque_command_stamped.getNumPublishers();
}

void LockstepLink::onCommand(const ros::MessageEvent<TorqueCommandStamped const>& event) {
  const TorqueCommandStamped& msg = *event.getConstMessage();
  const auto apply = [this, &msg] {
    diagnostics_->commandReceived(driver_->command(msg.torque) !=
                                  TorqueCommand::Verdict::kAccepted);
  };
  if (!config_.simulation.lockstep) return apply();
  switch (gate_.answer(msg.header.stamp, event.getPublisherName(), msg.torque)) {
    case LockstepGate::Verdict::kApply:
      return apply();
    case LockstepGate::Verdict::kDuplicate:
      if (!gate_.warning().empty()) ROS_WARN("kane_sim: %s", gate_.warning().c_str());
      return;
    case LockstepGate::Verdict::kLate:
      ROS_DEBUG_THROTTLE(1.0, "kane_sim: lockstep: dropped a late torque_command_stamped");
      return;
    case LockstepGate::Verdict::kUnknown:
      ROS_WARN_THROTTLE(5.0, "kane_sim: %s", gate_.warning().c_str());
      return;
  }
}

bool LockstepLink::waitForAnswer(const std::function<bool()>& interrupted,
                                 const std::function<void()>& between) {
  using Clock = std::chrono::steady_clock;
  const SimulationSettings& s = config_.simulation;
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                           std::chrono::duration<double>(s.lockstep_timeout));
  while (!gate_.answered()) {
    if (interrupted()) return false;
    // A controller that connected since the state went out (at start-up, a restarted one)
    // never heard it: the state awaiting an answer goes out again for it.
    const uint32_t now_listening = listeners();
    if (now_listening > listeners_ && gate_.hasState())
      io_->joint_states.publish(last_joint_states_);
    listeners_ = now_listening;
    if (Clock::now() >= deadline) {
      diagnostics_->lockstepTimedOut();
      const bool zero = s.lockstep_fallback == LockstepFallback::kZero;
      if (zero) driver_->command(0.0);
      ROS_WARN_THROTTLE(5.0, "kane_sim: %s",
                        gate_.timeoutReport(driver_->time(), s.lockstep_timeout, zero).c_str());
      gate_.release();
      break;
    }
    ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(0.001));
    between();
  }
  return true;
}

}  // namespace kane_sim
