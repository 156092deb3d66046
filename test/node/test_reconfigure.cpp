// Runtime reconfiguration through dynamic_reconfigure (test/node/reconfigure.test): the clamp
// follows torque_limit at once, a physical parameter changes u' from the next step and its
// energy jump lands in parameter_energy, a value the config loader refuses is reverted, and
// `rosrun dynamic_reconfigure dynparam set` works as the README says.
#include <cmath>

#include <gtest/gtest.h>
#include <std_srvs/Empty.h>

#include "kane_sim/MechanismState.h"
#include "node_test_utils.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

class Reconfigure : public test::SimNodeTest {
 protected:
  double set(const std::string& name, double value) { return test::reconfigure(name, value); }
};

TEST_F(Reconfigure, TorqueLimitClampsTheCommandInForce) {
  test::send(torque_, 10.0);
  ASSERT_TRUE(waitForState([](const MechanismState& m) { return m.applied_torque == 10.0; }, 5));
  EXPECT_EQ(set("torque_limit", 4.0), 4.0);
  ASSERT_TRUE(waitForState([](const MechanismState& m) { return m.applied_torque == 4.0; }, 5))
      << "applied " << state_.last().applied_torque;
  EXPECT_EQ(state_.last().commanded_torque, 10.0);
  // Through the command-line tool, as a user would (PATH's python3 must be Debian's).
  const test::CommandResult cli = test::runCommand(
      "PATH=/usr/bin:$PATH rosrun dynamic_reconfigure dynparam set /kane_sim torque_limit 2.5");
  EXPECT_EQ(cli.exit_code, 0) << cli.out << cli.err;
  EXPECT_TRUE(waitForState([](const MechanismState& m) { return m.applied_torque == 2.5; }, 5))
      << "applied " << state_.last().applied_torque;
  set("torque_limit", 50.0);
  test::send(torque_, 0.0);
}

// Gravity 0 and a heavier slider 4 at rest: slider 4's u2' becomes the spring's force / M2
// alone, and the jump of the total energy is booked in parameter_energy.
TEST_F(Reconfigure, PhysicalParametersApplyFromTheNextStepWithTheirEnergyBooked) {
  std_srvs::Empty empty;
  ASSERT_TRUE(ros::service::call("kane_sim/pause", empty));
  test::sleepWall(0.1);
  const MechanismState before = state_.last();
  EXPECT_EQ(set("gravity", 0.0), 0.0);
  EXPECT_EQ(set("slider4_mass", 1.6), 1.6);
  ASSERT_TRUE(ros::service::call("kane_sim/unpause", empty));
  ASSERT_TRUE(waitForState([](const MechanismState& m) { return m.parameter_changes == 2; }, 5));
  ASSERT_TRUE(ros::service::call("kane_sim/pause", empty));
  test::sleepWall(0.1);
  const MechanismState m = state_.last();
  // F2 = M2 g + k e with g = 0: u2' = k e / M2 (k = 200 N/m, e > 0 compressed pushes C down).
  EXPECT_NEAR(m.u_dot[1], 200.0 * m.spring_elongation / 1.6, 1e-9);
  // The gravitational energy went to 0 at the change: that is the booked jump (plus the
  // kinetic change of M2 0.8 -> 1.6 at u2).
  EXPECT_NEAR(m.gravitational_energy, 0.0, 1e-12);
  EXPECT_NE(m.parameter_energy, 0.0);
  const double ledger_before = before.total_energy - before.motor_work - before.parameter_energy;
  const double ledger_after = m.total_energy - m.motor_work - m.parameter_energy;
  EXPECT_NEAR(ledger_after, ledger_before, 1e-5) << "E - W - parameter_energy is conserved";
  ASSERT_TRUE(ros::service::call("kane_sim/unpause", empty));
}

// The loader's rules: rod_mass 0 is refused (must be > 0) and reverted; the node goes on.
TEST_F(Reconfigure, RefusedValuesAreRevertedAndNamed) {
  EXPECT_EQ(set("rod_mass", 0.0), 1.0);
  EXPECT_EQ(set("real_time_factor", 0.0001), 1.0) << "0 or >= 1e-3";
  const size_t n = state_.count();
  EXPECT_TRUE(state_.waitForCount(n + 10, 5.0)) << "the node keeps running";
}

}  // namespace
}  // namespace kane_sim
