// kane_sim_node's private services, as Gazebo's /gazebo/pause_physics (private: two sims, or
// turtlesim's /reset, never collide): ~reset, ~pause, ~unpause, ~step, ~set_state and
// ~step_with_command. Each handler translates: the work is the driver's, the publishing the
// StatePublisher's. Pausing is theirs too: the node's loop asks paused().
#ifndef KANE_SIM_NODES_SIM_SERVICES_H
#define KANE_SIM_NODES_SIM_SERVICES_H

#include <cstdint>
#include <string>
#include <vector>

#include <ros/ros.h>
#include <std_srvs/Empty.h>
#include <std_srvs/Trigger.h>

#include "kane_sim/SetState.h"
#include "kane_sim/StepWithCommand.h"
#include "kane_sim/sim/sim_driver.h"
#include "loop/paced_loop.h"
#include "state_publisher.h"

namespace kane_sim {

class SimServices {
 public:
  // ~step advances `ticks_per_publish` physics steps.
  SimServices(SimDriver* driver, StatePublisher* publisher, PacedLoop* loop, bool start_paused,
              std::uint64_t ticks_per_publish)
      : driver_(*driver),
        publisher_(*publisher),
        loop_(*loop),
        paused_(start_paused),
        ticks_per_publish_(ticks_per_publish) {}

  std::vector<ros::ServiceServer> advertise(ros::NodeHandle& private_nh);

  bool paused() const { return paused_; }
  void pause() { paused_ = true; }

 private:
  bool onReset(std_srvs::Empty::Request& req, std_srvs::Empty::Response& res);
  bool onPause(std_srvs::Empty::Request& req, std_srvs::Empty::Response& res);
  bool onUnpause(std_srvs::Empty::Request& req, std_srvs::Empty::Response& res);
  bool onStep(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  bool onSetState(SetState::Request& req, SetState::Response& res);
  bool onStepWithCommand(StepWithCommand::Request& req, StepWithCommand::Response& res);
  // After reset or set_state: the moved state, a checkpoint, then ~reset_event.
  void announceMove(const std::string& cause);

  SimDriver& driver_;
  StatePublisher& publisher_;
  PacedLoop& loop_;
  bool paused_;
  std::uint64_t ticks_per_publish_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_SIM_SERVICES_H
