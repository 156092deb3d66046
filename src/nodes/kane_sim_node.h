// The virtual robot: a thin ROS layer over the ROS-free SimDriver. It wires the parts together
// and paces ticks; StatePublisher sends, SimServices serves, LockstepLink gates, and
// RuntimeParameters reconfigures.
//
// One thread runs the loop: callbacks (torque commands, services, reconfiguration) are served
// between physics ticks, so the driver is never touched concurrently and a command or a new
// parameter is applied from the next physics step on.
#ifndef KANE_SIM_NODES_KANE_SIM_NODE_H
#define KANE_SIM_NODES_KANE_SIM_NODE_H

#include <cstdint>
#include <memory>
#include <string>

#include <ros/ros.h>
#include <std_msgs/Float64.h>

#include "kane_sim/config/config.h"
#include "kane_sim/description/robot_description.h"
#include "kane_sim/sim/sim_driver.h"
#include "lockstep_link.h"
#include "loop/loop_diagnostics.h"
#include "loop/loop_stats.h"
#include "loop/paced_loop.h"
#include "node_interfaces.h"
#include "runtime_parameters.h"
#include "sim_services.h"
#include "state_publisher.h"

namespace kane_sim {

class KaneSimNode {
 public:
  // Reads and validates the private parameters; throws ConfigError naming a bad one.
  KaneSimNode(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh);

  // Runs until ROS shuts down (SIGINT, SIGTERM, rosnode kill).
  void run();

 private:
  void onTorqueCommand(const std_msgs::Float64::ConstPtr& msg);
  void onServoSetpoint(const std_msgs::Float64::ConstPtr& msg);
  void onReconfigure(const Config& config);                 // an accepted runtime parameter change
  std::string reconfigureVeto(const Config& config) const;  // "" or why the node refuses it

  void connect();                // advertise, subscribe, offer the services (io_)
  void reconnect();              // the same again after the master restarted
  void runOneTick();             // paced physics tick (+ publishing on the publish grid)
  void waitWhilePaused();        // serve callbacks, keep wall-clock topics alive
  void maybeReportLoopHealth();  // /diagnostics once per window

  ros::NodeHandle nh_;
  ros::NodeHandle private_nh_;
  YAML::Node parameter_tree_;  // the private namespace the config was loaded from
  Config config_;
  RobotDescription robot_;
  LoopDiagnostics diagnostics_;
  SimDriver driver_;
  PacedLoop loop_;
  LoopStats stats_;
  std::uint64_t ticks_per_publish_;
  std::uint64_t checkpoint_ticks_;   // a periodic ~checkpoint every this many ticks (10 s)
  bool realtime_scheduled_ = false;  // the physics loop's thread runs SCHED_FIFO
  bool stopped_at_time_limit_ = false;

  NodeInterfaces io_;
  LockstepLink lockstep_;
  StatePublisher publisher_;
  SimServices services_;
  std::unique_ptr<RuntimeParameters> runtime_parameters_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_KANE_SIM_NODE_H
