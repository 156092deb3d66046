// torque_command handling of a running sim (test/node/torque.test, test/node/commands.test).
#include <cmath>
#include <limits>

#include <gtest/gtest.h>
#include <rosgraph_msgs/Log.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Float64.h>

#include "kane_sim/MechanismState.h"
#include "kane_sim/sim/simulator.h"
#include "node_test_utils.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

class Torque : public test::SimNodeTest {};
class Commands : public test::SimNodeTest {};

using test::Recorder;

using test::send;

// A steady 10 N m for 0.5 s moves q1 by roughly ½ (τ / M11) t² ≈ 2 rad more than the unforced
// motion; demand 0.3 rad against the offline simulator at the same sim time.
TEST_F(Torque, PositiveTorqueRaisesQ1AndShowsInEffortAndState) {
  Recorder<sensor_msgs::JointState> js(nh_, "joint_states");
  send(torque_, 10.0);
  ASSERT_TRUE(test::waitFor([&] { return state_.last().applied_torque == 10.0; }, 2.0));
  for (int i = 0; i < 5; ++i) {  // keep commanding, well inside the 0.5 s timeout
    test::sleepWall(0.1);
    send(torque_, 10.0);
  }
  const MechanismState driven = state_.last();
  EXPECT_EQ(driven.applied_torque, 10.0);
  EXPECT_EQ(driven.commanded_torque, 10.0);
  EXPECT_EQ(js.last().effort[0], 10.0);

  Simulator unforced(test::defaultConfig());
  while (unforced.time() < driven.sim_time - 1e-9) unforced.step();
  EXPECT_GT(driven.q[0], unforced.state().q1 + 0.3)
      << "driven " << driven.q[0] << " unforced " << unforced.state().q1
      << " at t = " << driven.sim_time;
}

TEST_F(Commands, NonFiniteCommandIsIgnored) {
  send(torque_, 5.0);
  ASSERT_TRUE(test::waitFor([&] { return state_.last().applied_torque == 5.0; }, 2.0));
  state_.clear();
  for (double bad : {std::nan(""), std::numeric_limits<double>::infinity(),
                     -std::numeric_limits<double>::infinity()})
    send(torque_, bad);
  test::sleepWall(0.2);  // < command.timeout (0.5 s)
  const auto msgs = state_.messages();
  ASSERT_GT(msgs.size(), 5u);
  for (const auto& m : msgs) {
    EXPECT_EQ(m.applied_torque, 5.0);
    EXPECT_EQ(m.commanded_torque, 5.0);
    EXPECT_TRUE(std::isfinite(m.q[0]) && std::isfinite(m.u[0]) && std::isfinite(m.total_energy));
  }
}

TEST_F(Commands, OverLimitCommandIsClamped) {
  send(torque_, 80.0);  // command.torque_limit is 20 in commands.yaml
  ASSERT_TRUE(test::waitFor([&] { return state_.last().commanded_torque == 80.0; }, 2.0));
  EXPECT_EQ(state_.last().applied_torque, 20.0);
  send(torque_, -1e300);
  ASSERT_TRUE(test::waitFor([&] { return state_.last().commanded_torque == -1e300; }, 2.0));
  EXPECT_EQ(state_.last().applied_torque, -20.0);
}

// The driver's events reach the node's log: the timeout once per lapse, clamping throttled.
int countInLog(const Recorder<rosgraph_msgs::Log>& rosout, const std::string& text) {
  int n = 0;
  for (const auto& log : rosout.messages()) n += log.msg.find(text) != std::string::npos;
  return n;
}

TEST_F(Commands, TimeoutZeroesTheTorqueAndNextCommandResumes) {
  Recorder<rosgraph_msgs::Log> rosout(nh_, "/rosout");
  ASSERT_TRUE(test::waitFor([&] { return rosout.connected(); }, 10.0));
  // Earlier tests' commands lapse first (their timeout messages are not this test's).
  ASSERT_TRUE(test::waitFor([&] { return state_.last().applied_torque == 0.0; }, 3.0));
  test::sleepWall(0.5);  // connections to every /rosout publisher, the sim's included
  rosout.clear();
  const size_t before = state_.count();
  send(torque_, 3.0);
  // Zeroed after command.timeout (0.5 s sim time), not before; one publish period of slack. Both
  // instants from the recorded states (the first at 3 N m, the first at 0 after it), not from
  // when this thread looked: on a starved machine it looks late, or after the torque lapsed.
  // Each look scans afresh: a state still at 0 before the command took effect is not "after".
  double on_at = -1.0, off_at = -1.0;
  ASSERT_TRUE(test::waitFor(
      [&] {
        on_at = off_at = -1.0;
        const auto states = state_.messages();
        for (size_t i = before; i < states.size(); ++i) {
          const auto& m = states[i];
          if (on_at < 0.0 && m.applied_torque == 3.0) on_at = m.sim_time;
          if (on_at >= 0.0 && off_at < 0.0 && m.applied_torque == 0.0) off_at = m.sim_time;
        }
        return off_at >= 0.0;
      },
      10.0));
  EXPECT_GE(off_at - on_at, 0.5 - 0.011);
  EXPECT_EQ(state_.last().commanded_torque, 3.0);
  send(torque_, 4.0);
  ASSERT_TRUE(test::waitFor([&] { return state_.last().applied_torque == 4.0; }, 2.0));
  send(torque_, std::nan(""));  // refused, then a clamp right after: both are logged (one
  send(torque_, 80.0);          // throttled call site per kind); 80 is over the 20 N m limit
  ASSERT_TRUE(test::waitFor([&] { return state_.last().applied_torque == 20.0; }, 2.0));
  test::sleepWall(0.3);  // the log reaches us; still inside the 0.5 s timeout
  EXPECT_EQ(countInLog(rosout, "no torque_command for 0.5 s (command.timeout)"), 1);
  EXPECT_GE(countInLog(rosout, "exceeds command.torque_limit 20 N m: clamped to 20 N m"), 1);
  EXPECT_GE(countInLog(rosout, "torque_command nan N m is not finite"), 1);
}

}  // namespace
}  // namespace kane_sim
