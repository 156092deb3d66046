// The node's side of lockstep (simulation.lockstep): joint_states go out through it, so it knows
// which stamp awaits an answer (LockstepGate); torque_command_stamped comes in through it; the
// loop waits on it before the next physics step. Without lockstep it only publishes and applies.
#ifndef KANE_SIM_NODES_LOCKSTEP_LINK_H
#define KANE_SIM_NODES_LOCKSTEP_LINK_H

#include <cstdint>
#include <functional>

#include <ros/ros.h>
#include <sensor_msgs/JointState.h>

#include "kane_sim/TorqueCommandStamped.h"
#include "kane_sim/config/config.h"
#include "kane_sim/sim/sim_driver.h"
#include "loop/lockstep_gate.h"
#include "loop/loop_diagnostics.h"
#include "node_interfaces.h"

namespace kane_sim {

class LockstepLink {
 public:
  // `config` is the node's, read at each call (a reconfiguration takes effect at once).
  LockstepLink(const Config& config, SimDriver* driver, LoopDiagnostics* diagnostics,
               NodeInterfaces* io)
      : config_(config), driver_(driver), diagnostics_(diagnostics), io_(io) {}

  // joint_states (the sensor view or the truth): in lockstep, a new stamp awaits its answer.
  void publish(const sensor_msgs::JointState& msg);

  // torque_command_stamped: applied at once without lockstep; in lockstep only the first answer
  // to the state awaiting one, whatever the timing.
  void onCommand(const ros::MessageEvent<TorqueCommandStamped const>& event);

  // Whether the next physics step may go (no lockstep, or the last state was answered).
  bool released() const { return !config_.simulation.lockstep || gate_.answered(); }

  // Serves callbacks until the state awaiting an answer has one, or until lockstep_timeout's
  // fallback releases it; `between` runs between polls (diagnostics go on while a slow
  // controller thinks). False when `interrupted` (shutdown, pause) said so first.
  bool waitForAnswer(const std::function<bool()>& interrupted,
                     const std::function<void()>& between);

 private:
  uint32_t listeners() const;  // who could answer: joint_states subscribers + stamped publishers

  const Config& config_;
  SimDriver* driver_;
  LoopDiagnostics* diagnostics_;
  NodeInterfaces* io_;
  LockstepGate gate_;
  sensor_msgs::JointState last_joint_states_;  // re-sent to a controller that joins late
  uint32_t listeners_ = 0;
};

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_LOCKSTEP_LINK_H
