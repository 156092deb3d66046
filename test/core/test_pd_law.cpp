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

// The integral term: sums e dt, holds ki * integral within the torque limit (no wind-up), skips
// gaps, clears.
TEST(PdLaw, IntegralSumsErrorWithoutWindUpAndClears) {
  PdGains g;
  g.ki = 100.0;
  IntegralTerm integral;
  integral.add(g, 0.1, 0.01);
  EXPECT_DOUBLE_EQ(integral.value(), 0.001);
  integral.add(g, 0.1, 0.0);   // no time passed
  integral.add(g, 0.1, -0.5);  // a stamp from the past
  integral.add(g, 0.1, 5.0);   // a gap, not a sample interval
  EXPECT_DOUBLE_EQ(integral.value(), 0.001);
  for (int i = 0; i < 100000; ++i) integral.add(g, 1.0, 0.01);  // saturated for 1000 s
  EXPECT_DOUBLE_EQ(g.ki * integral.value(), g.torque_limit);
  integral.clear();
  EXPECT_EQ(integral.value(), 0.0);
  PdGains pd;  // ki 0: nothing accumulates, the law is the PD's
  integral.add(pd, 1.0, 0.01);
  EXPECT_EQ(integral.value(), 0.0);
}

// With ki the steady error of the PD (~0.038 rad at 1 rad) goes: closed around the simulator at
// 100 Hz for 6 s, |q1 - setpoint| < 2 mrad (the PD alone stays > 20 mrad off).
TEST(PdLaw, TheIntegralTermRemovesTheSteadyError) {
  for (const double ki : {0.0, 400.0}) {
    Simulator sim(test::defaultConfig());
    PdGains gains;
    gains.ki = ki;
    IntegralTerm integral;
    const double setpoint = 1.0;
    for (int sample = 0; sample < 600; ++sample) {  // 6 s at 100 Hz
      integral.add(gains, setpoint - sim.state().q1, 0.01);
      sim.setTorque(pdTorque(gains, setpoint, sim.state().q1, sim.state().u1, integral.value()));
      for (int i = 0; i < 10; ++i) ASSERT_TRUE(sim.step().ok);
    }
    if (ki > 0)
      EXPECT_LT(std::abs(sim.state().q1 - setpoint), 2e-3);
    else
      EXPECT_GT(std::abs(sim.state().q1 - setpoint), 2e-2);
  }
}

}  // namespace
}  // namespace kane_sim
