// The virtual robot: a thin ROS layer over the ROS-free SimDriver. It paces ticks, turns ROS
// input into driver calls and driver snapshots and events into messages and log lines.
//
// One thread runs the loop: callbacks (torque commands, services, reconfiguration) are served
// between physics ticks, so the driver is never touched concurrently and a command or a new
// parameter is applied from the next physics step on.
#ifndef KANE_SIM_NODES_KANE_SIM_NODE_H
#define KANE_SIM_NODES_KANE_SIM_NODE_H

#include <atomic>
#include <chrono>
#include <memory>
#include <string>

#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Float64.h>
#include <std_srvs/Empty.h>
#include <std_srvs/Trigger.h>

#include "kane_sim/Checkpoint.h"
#include "kane_sim/SetState.h"
#include "kane_sim/StepWithCommand.h"
#include "kane_sim/TorqueCommandStamped.h"
#include "kane_sim/config/config.h"
#include "kane_sim/description/robot_description.h"
#include "kane_sim/sim/sim_driver.h"
#include "loop/lockstep_gate.h"
#include "loop/loop_diagnostics.h"
#include "loop/loop_stats.h"
#include "loop/paced_loop.h"
#include "loop/publish_pace.h"
#include "loop/stamp_clock.h"
#include "node_interfaces.h"
#include "runtime_parameters.h"

namespace kane_sim {

class KaneSimNode {
 public:
  // Reads and validates the private parameters; throws ConfigError naming a bad one.
  KaneSimNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh);

  // Runs until ROS shuts down (SIGINT, SIGTERM, rosnode kill).
  void run();

 private:
  using SteadyClock = std::chrono::steady_clock;

  void onTorqueCommand(const std_msgs::Float64::ConstPtr& msg);
  void onTorqueCommandStamped(const ros::MessageEvent<TorqueCommandStamped const>& event);
  void onServoSetpoint(const std_msgs::Float64::ConstPtr& msg);
  // Lockstep: serves callbacks until the last published state is answered (or the timeout's
  // fallback); false when interrupted (shutdown, pause).
  bool waitForLockstepAnswer();
  bool onReset(std_srvs::Empty::Request& req, std_srvs::Empty::Response& res);
  bool onPause(std_srvs::Empty::Request& req, std_srvs::Empty::Response& res);
  bool onUnpause(std_srvs::Empty::Request& req, std_srvs::Empty::Response& res);
  bool onStep(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  bool onSetState(SetState::Request& req, SetState::Response& res);
  bool onStepWithCommand(StepWithCommand::Request& req, StepWithCommand::Response& res);
  void onReconfigure(const Config& config);                 // an accepted runtime parameter change
  std::string reconfigureVeto(const Config& config) const;  // "" or why the node refuses it
  // ~reset_event after the moved state is published, with its stamp: controllers clear their
  // state, and tf at that stamp is the new pose.
  void announceReset(const std::string& cause);
  // A state moved by reset or set_state: published at a new stamp (see the .cpp).
  void publishMovedState();
  // ~checkpoint (latched): the driver's whole state now, with the config and the next input's
  // seq, so that simulate --replay can start a bag here.
  void publishCheckpoint(const std::string& cause);
  uint32_t lockstepListeners() const;  // who could answer: see waitForLockstepAnswer

  void connect();                   // advertise, subscribe, offer the services (io_)
  void publishRobotDescription();   // robot_description (URDF) and the static tf
  void reconnect();                 // the same again after the master restarted
  void runOneTick();                // paced physics tick (+ publishing on the publish grid)
  void waitWhilePaused();           // serve callbacks, keep wall-clock topics alive
  void checkSimTimeSetting();       // warn once when /use_sim_time contradicts our stamps
  void publishState();              // joint_states, tf, mechanism_state (+ /clock)
  void publishDueSensorReadings();  // sensors on: readings due by now on joint_states
  // joint_states (sensor view or truth): in lockstep, a new stamp awaits its answer.
  void publishJointStates(const sensor_msgs::JointState& msg);
  void maybeReportLoopHealth();  // /diagnostics once per window
  ros::Time stamp();             // StampClock's, warning when the system clock went back

  ros::NodeHandle nh_;
  ros::NodeHandle private_nh_;
  YAML::Node parameter_tree_;  // the private namespace the config was loaded from
  Config config_;
  RobotDescription robot_;
  SimDriver driver_;
  PacedLoop loop_;
  LoopStats stats_;
  LoopDiagnostics diagnostics_;
  StampClock stamp_clock_;
  std::uint64_t ticks_per_publish_;
  bool paused_;
  std::uint64_t checkpoint_ticks_;   // a periodic ~checkpoint every this many ticks (10 s)
  std::string checkpoint_config_;    // the config in force as YAML ("" until written)
  bool realtime_scheduled_ = false;  // the physics loop's thread runs SCHED_FIFO

  NodeInterfaces io_;
  std::unique_ptr<RuntimeParameters> runtime_parameters_;

  ros::Time last_state_stamp_;                 // the stamp of the last published state
  LockstepGate lockstep_;                      // which joint_states stamp awaits its answer
  sensor_msgs::JointState last_joint_states_;  // re-sent to a controller that joins late
  uint32_t lockstep_listeners_ = 0;  // joint_states subscribers + torque_command_stamped publishers
  ros::Time tick_stamp_;             // the stamp of tick stamped_tick_ (one per tick)
  std::uint64_t stamped_tick_ = 0;
  bool stamp_valid_ = false;
  std::uint64_t input_seq_ = 0;  // ~input_log's sequence number of the next input
  bool stopped_at_time_limit_ = false;
  PublishPace pace_;  // achieved real-time factor, wall-clock publishes, diagnostics window
};

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_KANE_SIM_NODE_H
