// What the lockstep rostests share (test_lockstep.cpp, test_sensors.cpp): run the paused node
// with the example controller answering for a number of messages, then read the node's config
// and the controller's law, to step the ROS-free driver the same way.
#ifndef KANE_SIM_TEST_NODE_CONTROLLED_RUN_H
#define KANE_SIM_TEST_NODE_CONTROLLED_RUN_H

#include <vector>

#include <gtest/gtest.h>
#include <sensor_msgs/JointState.h>
#include <std_srvs/Empty.h>

#include "kane_sim/ros/param_yaml.h"
#include "kane_sim/sim/config_check.h"
#include "kane_sim/sim/sim_driver.h"
#include "node_test_utils.h"
#include "pd_law.h"

namespace kane_sim {
namespace test {

// The paused node's start, as every lockstep case begins: its initial state published and answered
// by the controller (in /clock mode the paused state is repeated once a second; its answer is in
// after 1.5 s), then `recorder` cleared. Returns the paused state's stamp: a repeat that lands
// after the clear carries it and is not a stepped state (steppedMessages drops it).
template <class M>
::testing::AssertionResult awaitPausedStart(Recorder<M>* recorder, ros::Time* paused_stamp) {
  if (!recorder->waitForCount(1, 20.0))
    return ::testing::AssertionFailure() << "no paused initial state in 20 s";
  const bool repeated = waitFor(
      [] {
        return ros::topic::waitForMessage<sensor_msgs::JointState>("joint_states",
                                                                   ros::Duration(2.0)) != nullptr;
      },
      5.0);
  if (!repeated) return ::testing::AssertionFailure() << "joint_states stopped while paused";
  sleepWall(1.5);
  *paused_stamp = recorder->last().header.stamp;
  recorder->clear();
  return ::testing::AssertionSuccess();
}

// What `recorder` holds but repeats of the paused state.
template <class M>
std::vector<M> steppedMessages(const Recorder<M>& recorder, const ros::Time& paused_stamp) {
  std::vector<M> stepped;
  for (const M& m : recorder.messages())
    if (m.header.stamp != paused_stamp) stepped.push_back(m);
  return stepped;
}

// Unpauses the node, waits until `recorder` holds `count` messages (`timeout_s` at most), pauses
// it.
template <class M>
::testing::AssertionResult runUnpausedFor(const Recorder<M>& recorder, size_t count,
                                          double timeout_s = 60.0) {
  std_srvs::Empty empty;
  if (!ros::service::waitForService("kane_sim/unpause", ros::Duration(10.0)) ||
      !ros::service::call("kane_sim/unpause", empty))
    return ::testing::AssertionFailure() << "kane_sim/unpause not served";
  const bool enough = recorder.waitForCount(count, timeout_s);
  ros::service::call("kane_sim/pause", empty);
  if (!enough) return ::testing::AssertionFailure() << "only " << recorder.count() << " messages";
  return ::testing::AssertionSuccess();
}

// Steps `driver` one publish period (`ticks` physics steps, the torque already commanded) and
// compares its joint positions and velocities with the node's k-th stepped message, bit for bit.
inline ::testing::AssertionResult stepsAsPublished(SimDriver* driver, int ticks,
                                                   const sensor_msgs::JointState& published,
                                                   size_t k) {
  for (int i = 0; i < ticks; ++i)
    if (!driver->step()) return ::testing::AssertionFailure() << "step refused, publish " << k;
  const Snapshot s = driver->snapshot();
  if (published.position.size() != 4u || published.velocity.size() != 4u)
    return ::testing::AssertionFailure() << "publish " << k << " has not 4 joints";
  for (int j = 0; j < 4; ++j)
    if (published.position[j] != s.joints.position[j] ||
        published.velocity[j] != s.joints.velocity[j])
      return ::testing::AssertionFailure()
             << "publish " << k << " joint " << j << ": node " << published.position[j] << ", "
             << published.velocity[j] << "; driver " << s.joints.position[j] << ", "
             << s.joints.velocity[j];
  return ::testing::AssertionSuccess();
}

// The node's config (/kane_sim) and the example controller's law (/pd_controller).
struct ControlledRun {
  Config config;
  PdGains gains;
  double setpoint = 0.0;
};

inline ::testing::AssertionResult readControlledRun(ControlledRun* run) {
  XmlRpc::XmlRpcValue params;
  if (!ros::param::get("/kane_sim", params))
    return ::testing::AssertionFailure() << "no /kane_sim parameters";
  run->config = loadSimulationConfig(yamlFromXmlRpc(params)).config;
  if (!ros::param::get("/pd_controller/kp", run->gains.kp) ||
      !ros::param::get("/pd_controller/kd", run->gains.kd) ||
      !ros::param::get("/pd_controller/torque_limit", run->gains.torque_limit) ||
      !ros::param::get("/pd_controller/setpoint", run->setpoint))
    return ::testing::AssertionFailure() << "/pd_controller's kp, kd, torque_limit, setpoint";
  return ::testing::AssertionSuccess();
}

}  // namespace test
}  // namespace kane_sim

#endif  // KANE_SIM_TEST_NODE_CONTROLLED_RUN_H
