// Everything kane_sim_node sends about the mechanism, with one stamp per physics tick: the
// state topics (joint_states or its truth, mechanism_state, servo_state, markers, tf, /clock),
// the sensor readings, a moved state (reset, set_state), ~checkpoint, ~reset_event,
// ~input_log and robot_description. Nothing non-finite ever goes out.
#ifndef KANE_SIM_NODES_STATE_PUBLISHER_H
#define KANE_SIM_NODES_STATE_PUBLISHER_H

#include <chrono>
#include <cstdint>
#include <string>

#include <ros/ros.h>
#include <yaml-cpp/yaml.h>

#include "kane_sim/config/config.h"
#include "kane_sim/description/robot_description.h"
#include "kane_sim/sim/sim_driver.h"
#include "lockstep_link.h"
#include "loop/publish_pace.h"
#include "loop/stamp_clock.h"
#include "node_interfaces.h"

namespace kane_sim {

class StatePublisher {
 public:
  // `config` and `robot` are the node's, read at each publish (they change at reconfiguration).
  StatePublisher(const Config& config, const RobotDescription& robot, SimDriver* driver,
                 NodeInterfaces* io, LockstepLink* lockstep);

  // The stamp of the current physics tick (one for everything published at it: a reading pairs
  // with its truth by stamp); warns when the system clock went back.
  ros::Time stamp();
  // The next stamp() is a fresh one even at the same tick (a repeat at a later wall time).
  void restamp() { stamp_valid_ = false; }

  // The state at the current tick on every state topic.
  void publishState();
  // Sensors on: the readings due by now on joint_states.
  void publishDueSensorReadings();
  // Both: after a start, ~step or ~step_with_command.
  void publishStateAndReadings() {
    publishState();
    publishDueSensorReadings();
  }
  // A state moved by reset or set_state: at a stamp after every earlier one, also in /clock
  // mode where sim time stands still, then the readings of the moved state as they come.
  void publishMovedState();
  // ~reset_event after the moved state, with its stamp: controllers clear their state.
  void announceReset(const std::string& cause);
  // ~checkpoint (latched): the driver's whole state, the config in force and the next input's
  // seq, so that simulate --replay can start a bag here.
  void publishCheckpoint(const std::string& cause);
  // The parameter tree in force, written once per change into the checkpoints.
  void setConfigTree(const YAML::Node& tree) { config_text_ = YAML::Dump(tree); }
  // A driver input on ~input_log, numbered.
  void logInput(const DriverInput& input);
  // robot_description (relative to `nh`): at start-up, on a new master, and after every
  // reconfiguration (the masses and inertia are in the URDF).
  void publishRobotDescription(ros::NodeHandle& nh);
  // The static tf (world -> mechanism), latched: at start-up and on a new master only (nothing
  // a reconfiguration can change moves it).
  void publishStaticTf();
  // Warns when /use_sim_time contradicts the stamps.
  void checkSimTimeSetting();

  PublishPace& pace() { return pace_; }

 private:
  const Config& config_;
  const RobotDescription& robot_;
  SimDriver& driver_;
  NodeInterfaces* io_;
  LockstepLink* lockstep_;
  StampClock stamp_clock_;
  PublishPace pace_;  // achieved real-time factor, wall-clock publishes, diagnostics window
  ros::Time last_state_stamp_;  // the stamp of the last published state
  ros::Time tick_stamp_;        // the stamp of tick stamped_tick_
  std::uint64_t stamped_tick_ = 0;
  bool stamp_valid_ = false;
  std::uint64_t input_seq_ = 0;  // ~input_log's sequence number of the next input
  std::string config_text_;      // the config in force as YAML
};

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_STATE_PUBLISHER_H
