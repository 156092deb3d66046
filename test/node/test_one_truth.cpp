// The node's doors of the one-truth matrix (test/node/one_truth.test): each paused node is
// driven through its own doors — ~step_with_command in effort mode; servo_setpoint and ~step in
// the servo modes — and must end where `simulate` ends for the same case (the node's own
// parameters as --config, the same command as a constant profile), bit for bit.
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <std_msgs/Float64.h>
#include <std_srvs/Trigger.h>

#include "kane_sim/MechanismState.h"
#include "kane_sim/StepWithCommand.h"
#include "kane_sim/ros/param_yaml.h"
#include "node_test_utils.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

using test::Recorder;

struct Case {
  const char* ns;
  bool servo;
  double command;  // torque [N m], or the servo's setpoint [rad | rad/s]
};

// simulate's last CSV row for the node's own parameters: {t, q1, q2, u1, u2}.
std::vector<double> simulateFinal(const std::string& ns, double command, double duration) {
  XmlRpc::XmlRpcValue params;
  EXPECT_TRUE(ros::param::get("/" + ns + "/kane_sim", params));
  const std::string config = ::testing::TempDir() + "/one_truth_" + ns + ".yaml";
  std::ofstream(config) << yamlFromXmlRpc(params);
  const test::CommandResult r = test::runCommand(
      std::string(KANE_SIM_SIMULATE_EXE) + " --config " + config + " --duration " +
      std::to_string(duration) + " --torque " + std::to_string(command) + " --output-rate 100");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::string header;
  const auto rows = test::parseCsv(r.out, &header);
  EXPECT_FALSE(rows.empty());
  return rows.empty() ? std::vector<double>(5, 0.0) : rows.back();
}

TEST(OneTruth, EachNodeDoorEndsWhereSimulateEnds) {
  ros::NodeHandle nh;
  const Case cases[] = {{"effort_plain", false, 3.0},
                        {"effort_sensors_contact", false, -4.0},
                        {"position_servo", true, 0.9},
                        {"velocity_sensors", true, 1.5}};
  constexpr std::uint32_t kSteps = 500;  // 0.5 s at 1 kHz
  for (const Case& c : cases) {
    SCOPED_TRACE(c.ns);
    const std::string node = std::string("/") + c.ns + "/kane_sim";
    Recorder<MechanismState> state(nh, std::string("/") + c.ns + "/mechanism_state");
    ASSERT_TRUE(state.waitForCount(1, 20.0));
    double q1 = 0, q2 = 0, u1 = 0, u2 = 0, t = 0;
    if (!c.servo) {
      StepWithCommand step;
      step.request.torque = c.command;
      step.request.steps = kSteps;
      ASSERT_TRUE(ros::service::waitForService(node + "/step_with_command", ros::Duration(10)));
      ASSERT_TRUE(ros::service::call(node + "/step_with_command", step));
      ASSERT_TRUE(step.response.success) << step.response.message;
      t = step.response.time, q1 = step.response.q1, q2 = step.response.q2;
      u1 = step.response.u1, u2 = step.response.u2;
    } else {
      ros::Publisher setpoint = test::connectedPublisher<std_msgs::Float64>(
          nh, std::string("/") + c.ns + "/servo_setpoint");
      test::send(setpoint, c.command);
      // In force once the node has it: the paused node serves callbacks every 2 ms.
      test::sleepWall(0.5);
      std_srvs::Trigger step;
      ASSERT_TRUE(ros::service::waitForService(node + "/step", ros::Duration(10)));
      // One persistent connection for the 50 calls (a fresh one per call once failed to connect
      // on a loaded machine).
      ros::ServiceClient stepper = nh.serviceClient<std_srvs::Trigger>(node + "/step", true);
      for (std::uint32_t i = 0; i < kSteps / 10; ++i) {  // each ~step: one publish period
        ASSERT_TRUE(stepper.call(step)) << "call " << i;
        ASSERT_TRUE(step.response.success) << step.response.message;
      }
      ASSERT_TRUE(test::waitFor([&] { return state.last().sim_time >= 0.5 - 1e-9; }, 5.0));
      const MechanismState m = state.last();
      t = m.sim_time, q1 = m.q[0], q2 = m.q[1], u1 = m.u[0], u2 = m.u[1];
    }
    const std::vector<double> want = simulateFinal(c.ns, c.command, 0.5);
    ASSERT_GE(want.size(), 5u);
    EXPECT_EQ(t, want[0]);
    EXPECT_EQ(q1, want[1]);
    EXPECT_EQ(q2, want[2]);
    EXPECT_EQ(u1, want[3]);
    EXPECT_EQ(u2, want[4]);
  }
}

}  // namespace
}  // namespace kane_sim
