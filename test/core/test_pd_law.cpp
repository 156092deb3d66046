// The example controller's law, closed around the real simulator offline, with the node's
// 100 Hz joint_states sampling (torque held between samples) as in the demo.
#include <cmath>

#include <gtest/gtest.h>

#include "kane_sim/sim/simulator.h"
#include "pd_law.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

TEST(PdLaw, ProportionalDampedAndClamped) {
  const PdGains g;
  EXPECT_NEAR(pdTorque(g, 1.0, 0.99, 0.0), g.kp * 0.01, 1e-9);
  EXPECT_DOUBLE_EQ(pdTorque(g, 1.0, 1.0, 0.1), -g.kd * 0.1);
  EXPECT_DOUBLE_EQ(pdTorque(g, 10.0, 0.0, 0.0), g.torque_limit);
  EXPECT_DOUBLE_EQ(pdTorque(g, -10.0, 0.0, 0.0), -g.torque_limit);
}

// Holding q1 = 1 rad needs up to ~4 g L (m + M1) sin q1 + spring ≈ 14 N m: the steady error of a
// PD is that moment / kp = 14 / 500 ≈ 0.03 rad. The stated tolerance is 0.05 rad after 3 s.
TEST(PdLaw, HoldsTheCrankAtTheSetpointInClosedLoop) {
  Simulator sim(test::defaultConfig());
  const PdGains gains;
  const double setpoint = 1.0;
  for (int sample = 0; sample < 300; ++sample) {  // 3 s at 100 Hz
    sim.setTorque(pdTorque(gains, setpoint, sim.state().q1, sim.state().u1));
    for (int i = 0; i < 10; ++i) ASSERT_TRUE(sim.step().ok);
  }
  EXPECT_NEAR(sim.state().q1, setpoint, 0.05);
  EXPECT_NEAR(sim.state().u1, 0.0, 0.5);
}

}  // namespace
}  // namespace kane_sim
