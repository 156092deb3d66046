// What the lockstep rostests share (test_lockstep.cpp, test_sensors.cpp): run the paused node
// with the example controller answering for a number of messages, then read the node's config
// and the controller's law, to step the ROS-free driver the same way.
#ifndef KANE_SIM_TEST_NODE_CONTROLLED_RUN_H
#define KANE_SIM_TEST_NODE_CONTROLLED_RUN_H

#include <gtest/gtest.h>
#include <std_srvs/Empty.h>

#include "kane_sim/ros/param_yaml.h"
#include "kane_sim/sim/config_check.h"
#include "node_test_utils.h"
#include "pd_law.h"

namespace kane_sim {
namespace test {

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
