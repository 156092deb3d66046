#include "sim_services.h"

#include <chrono>
#include <sstream>

#include "kane_sim/format_number.h"

namespace kane_sim {
namespace {

// ~step_with_command runs for at most this much wall time (SimDriver::stepHeld bounds its
// steps): dopri5 at a violent state once took 24.6 s for 2000 steps while ~pause and Ctrl-C
// waited. A call that runs out answers the state it reached (success false, the reason).
constexpr double kStepCallBudget = 2.0;  // [s] wall

}  // namespace

std::vector<ros::ServiceServer> SimServices::advertise(ros::NodeHandle& nh) {
  return {nh.advertiseService("reset", &SimServices::onReset, this),
          nh.advertiseService("pause", &SimServices::onPause, this),
          nh.advertiseService("unpause", &SimServices::onUnpause, this),
          nh.advertiseService("step", &SimServices::onStep, this),
          nh.advertiseService("set_state", &SimServices::onSetState, this),
          nh.advertiseService("step_with_command", &SimServices::onStepWithCommand, this)};
}

void SimServices::announceMove(const std::string& cause) {
  publisher_.publishMovedState();
  publisher_.publishCheckpoint(cause);
  publisher_.announceReset(cause);
}

bool SimServices::onReset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  driver_.reset();
  ROS_INFO("kane_sim: reset to the initial state (sim time runs on at %.3f s)", driver_.time());
  announceMove("reset");
  return true;
}

bool SimServices::onSetState(SetState::Request& req, SetState::Response& res) {
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
  announceMove("set_state");
  return true;
}

bool SimServices::onPause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  paused_ = true;
  return true;
}

bool SimServices::onUnpause(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
  paused_ = false;
  loop_.anchor();  // resume on a fresh schedule
  return true;
}

bool SimServices::onStep(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  res.success = false;
  if (!paused_) {
    res.message = "not paused: call pause first (step advances a paused simulation)";
    return true;
  }
  for (std::uint64_t i = 0; i < ticks_per_publish_; ++i) {
    if (!driver_.step()) {
      res.message = "a physics step was refused; see the log";
      return true;
    }
  }
  publisher_.publishStateAndReadings();
  std::ostringstream msg;
  msg << "advanced " << ticks_per_publish_ << " physics steps to t = " << driver_.time() << " s";
  res.success = true;
  res.message = msg.str();
  return true;
}

bool SimServices::onStepWithCommand(StepWithCommand::Request& req, StepWithCommand::Response& res) {
  using Clock = std::chrono::steady_clock;
  SimDriver::HeldSteps held;
  if (!paused_) {
    held.message =
        "not paused: call ~pause first (step_with_command advances a paused simulation); nothing "
        "changed";
  } else {
    const auto wall_start = Clock::now();
    held = driver_.stepHeld(req.torque, req.steps, [&wall_start]() -> std::string {
      if (std::chrono::duration<double>(Clock::now() - wall_start).count() > kStepCallBudget)
        return "the call's wall-time budget of " + formatNumber(kStepCallBudget) +
               " s ran out (ask for fewer steps per call)";
      return !ros::ok() || ros::isShuttingDown() ? "the node is shutting down" : "";
    });
  }
  if (!held.refused && paused_) publisher_.publishStateAndReadings();
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
