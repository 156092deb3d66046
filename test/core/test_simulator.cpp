// Time stepping: the fixed time grid, both integrators, torque hold, motor work, refusals, reset.
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "kane_sim/sim/csv_format.h"
#include "kane_sim/sim/simulator.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

TEST(Simulator, EachStepAdvancesExactlyOnePhysicsPeriod) {
  Config c = test::defaultConfig();
  c.simulation.physics_rate = 1000;
  Simulator sim(c);
  for (int i = 0; i < 2500; ++i) ASSERT_TRUE(sim.step().ok);
  EXPECT_EQ(sim.ticks(), 2500u);
  EXPECT_DOUBLE_EQ(sim.time(), 2.5);
}

// Both integrators solve the same equations: after 2 s they agree to the accuracy of rk4 at
// 1 kHz (local error ~h^5 f^(5), global ~1e-10 here; 1e-7 leaves room for the chaotic-looking
// but smooth motion to amplify it).
TEST(Simulator, Rk4AndDopri5Agree) {
  Config c = test::defaultConfig();
  c.simulation.integrator = IntegratorType::kRk4;
  Simulator rk4(c);
  c.simulation.integrator = IntegratorType::kDopri5;
  c.simulation.absolute_tolerance = c.simulation.relative_tolerance = 1e-12;
  Simulator dopri5(c);
  for (Simulator* sim : {&rk4, &dopri5}) {
    sim->setTorque(1.5);
    for (int i = 0; i < 2000; ++i) ASSERT_TRUE(sim->step().ok);
  }
  EXPECT_DOUBLE_EQ(rk4.time(), dopri5.time());
  EXPECT_NEAR(rk4.state().q1, dopri5.state().q1, 1e-7);
  EXPECT_NEAR(rk4.state().q2, dopri5.state().q2, 1e-7);
  EXPECT_NEAR(rk4.state().u1, dopri5.state().u1, 1e-6);
  EXPECT_NEAR(rk4.state().u2, dopri5.state().u2, 1e-6);
}

// dopri5 reuses its last derivative while the torque stays put; when the torque changes, that
// derivative is stale. Its error controller then shrinks the first sub-step until the (weakly
// weighted) stale stage passes the tolerance, so a loose tolerance shows the damage best: at
// 1e-6 a reused stale derivative leaves q1 1.7e-4 rad off after 40 switches (measured with the
// reset disabled); with it, dopri5 and rk4 agree to 4e-9 rad.
TEST(Simulator, Dopri5FollowsTorqueChanges) {
  Config c = test::defaultConfig();
  c.simulation.integrator = IntegratorType::kRk4;
  Simulator rk4(c);
  c.simulation.integrator = IntegratorType::kDopri5;
  c.simulation.absolute_tolerance = c.simulation.relative_tolerance = 1e-6;
  Simulator dopri5(c);
  for (int i = 0; i < 2000; ++i) {
    const double torque = (i / 50) % 2 ? -4.0 : 6.0;
    for (Simulator* sim : {&rk4, &dopri5}) {
      ASSERT_TRUE(sim->setTorque(torque).ok);
      ASSERT_TRUE(sim->step().ok);
    }
  }
  EXPECT_NEAR(rk4.state().q1, dopri5.state().q1, 1e-7);
  EXPECT_NEAR(rk4.state().u1, dopri5.state().u1, 1e-6);
  EXPECT_NEAR(rk4.state().q2, dopri5.state().q2, 1e-7);
}

TEST(Simulator, TorqueIsHeldAndItsWorkIsTorqueTimesCrankRotation) {
  Simulator sim(test::defaultConfig());
  const double q1_start = sim.state().q1;
  ASSERT_TRUE(sim.setTorque(3.0).ok);
  for (int i = 0; i < 500; ++i) ASSERT_TRUE(sim.step().ok);
  EXPECT_DOUBLE_EQ(sim.torque(), 3.0);
  EXPECT_NEAR(sim.motorWork(), 3.0 * (sim.state().q1 - q1_start), 1e-12);
  EXPECT_DOUBLE_EQ(sim.snapshot().torque, 3.0);
}

TEST(Simulator, PositiveTorqueRaisesQ1RelativeToUnforcedRun) {
  Simulator free_run(test::defaultConfig()), driven(test::defaultConfig());
  driven.setTorque(2.0);
  for (int i = 0; i < 300; ++i) {
    ASSERT_TRUE(free_run.step().ok);
    ASSERT_TRUE(driven.step().ok);
  }
  EXPECT_GT(driven.state().q1, free_run.state().q1 + 0.05);
}

TEST(Simulator, NonFiniteTorqueIsRefusedAndTheLastOneKept) {
  Simulator sim(test::defaultConfig());
  ASSERT_TRUE(sim.setTorque(1.0).ok);
  for (double bad : {std::nan(""), std::numeric_limits<double>::infinity(),
                     -std::numeric_limits<double>::infinity()}) {
    const Status r = sim.setTorque(bad);
    EXPECT_FALSE(r.ok);
    EXPECT_NE(r.error.find("not finite"), std::string::npos) << r.error;
    EXPECT_DOUBLE_EQ(sim.torque(), 1.0);
  }
}

// An absurd torque drives the speeds past double range within a few steps; the step that would
// produce inf/NaN is refused and the state, time and work stay at the last good values.
TEST(Simulator, StepThatWouldGoNonFiniteIsRefused) {
  for (IntegratorType type : {IntegratorType::kRk4, IntegratorType::kDopri5}) {
    Config c = test::defaultConfig();
    c.simulation.integrator = type;
    Simulator sim(c);
    sim.setTorque(1e300);
    Status result;
    int steps = 0;
    for (; steps < 50 && result.ok; ++steps) {
      const State before = sim.state();
      const double time_before = sim.time();
      result = sim.step();
      if (!result.ok) {
        EXPECT_TRUE(sim.state().isFinite());
        EXPECT_EQ(sim.state().q1, before.q1);
        EXPECT_EQ(sim.state().u1, before.u1);
        EXPECT_EQ(sim.time(), time_before);
        EXPECT_NE(result.error.find("state kept"), std::string::npos) << result.error;
      }
    }
    EXPECT_FALSE(result.ok) << integratorName(type) << " never refused a step";
    const Snapshot snap = sim.snapshot();
    EXPECT_TRUE(snap.state.isFinite());
  }
}

// set_state's hostile states: each refused naming the field and the reason, nothing changed.
// u1 = 1e5 rad/s and q1 = 1e308 were accepted and put inf/NaN on every topic within 2 ms.
TEST(Simulator, SetStateRefusesStatesThatCannotBeIntegrated) {
  Config c = test::defaultConfig();
  c.mechanism.contact.enabled = true;
  Simulator sim(c);
  const State before = sim.state();
  const struct {
    State state;
    const char* says;
  } refused[] = {
      {{0.0, 1.2, 100000.0, 0.0}, "more than 1 rad per rk4 step"},
      {{0.5, 1e5, 0.0, 0.0}, "too stiff for rk4 at 1000 Hz"},  // the spring stretched 1e5 m
      {{1e308, 1.2, 0.0, 0.0}, "q1 = 1e+308 rad is beyond"},
      {{0.0, 1e308, 0.0, 0.0}, "non-finite energy"},
      {{0.0, 1.2, 0.0, 1e200}, "non-finite energy"},
      {{0.0, 1.0, 0.0, 0.0}, "closer than contact.gap"},  // x_B = 1.0: touching
      {{0.0, 0.5, 0.0, 0.0}, "closer than contact.gap"},  // slider 4 above slider 3: crossed
      {{0.0, std::nan(""), 0.0, 0.0}, "q2 = nan is not finite"},
      {{0.0, 1.2, -INFINITY, 0.0}, "u1 = -inf is not finite"},
  };
  for (const auto& r : refused) {
    const Status result = sim.setState(r.state);
    EXPECT_FALSE(result.ok) << r.says;
    EXPECT_NE(result.error.find(r.says), std::string::npos) << result.error;
    EXPECT_NE(result.error.find("state kept"), std::string::npos) << result.error;
    EXPECT_EQ(sim.state().q1, before.q1);
    EXPECT_EQ(sim.state().u1, before.u1);
  }
  EXPECT_TRUE(sim.setState(State{0.0, 1.2, 20.0, 0.0}).ok);  // a fast but resolvable spin
}

// One rule for set_state and step: a state set_state accepts takes its next step (u1 h = 1
// exactly was accepted at q1 = pi/2, and the step after it refused).
TEST(Simulator, AStateSetStateAcceptsTakesItsNextStep) {
  Simulator sim(test::defaultConfig());
  const Status edge = sim.setState(State{1.5707963, 1.2, 1000.0, 0.0});
  EXPECT_FALSE(edge.ok);
  EXPECT_NE(edge.error.find("within its first rk4 step"), std::string::npos) << edge.error;
  int accepted = 0;
  for (double u1 = 990.0; u1 <= 1000.0; u1 += 0.25)
    for (double q1 : {0.0, 0.7, 1.5707963, 3.0}) {
      if (!sim.setState(State{q1, 1.2, u1, 0.0}).ok) continue;
      ++accepted;
      EXPECT_TRUE(sim.step().ok) << "q1 " << q1 << " u1 " << u1;
    }
  EXPECT_GT(accepted, 20);
}

// Whatever state set_state accepts, every snapshot after it (published as it is) is finite:
// random states over 20 decades, each accepted one stepped 200 times (dopri5: 20).
TEST(Simulator, EverySnapshotAfterAnAcceptedStateIsFinite) {
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> exponent(-10.0, 10.0), sign(-1.0, 1.0);
  const auto wild = [&] { return std::copysign(std::pow(10.0, exponent(rng)), sign(rng)); };
  for (IntegratorType type : {IntegratorType::kRk4, IntegratorType::kDopri5}) {
    Config c = test::defaultConfig();
    c.simulation.integrator = type;
    Simulator sim(c);
    int accepted = 0;
    for (int trial = 0; trial < 400; ++trial) {
      if (!sim.setState(State{wild(), wild(), wild(), wild()}).ok) continue;
      ++accepted;
      ASSERT_TRUE(sim.snapshot().allFinite());
      // dopri5 takes as many sub-steps as a stiff state needs (thousands for the wildest): fewer.
      const int steps = type == IntegratorType::kRk4 ? 200 : 20;
      for (int i = 0; i < steps; ++i) {
        const bool stepped = sim.step().ok;  // refused or not, what is published stays finite
        const Snapshot snap = sim.snapshot();
        ASSERT_TRUE(snap.allFinite())
            << integratorName(type) << " trial " << trial << " step " << i << ": q "
            << snap.state.q1 << " " << snap.state.q2 << " u " << snap.state.u1 << " "
            << snap.state.u2 << " E " << snap.energy.total() << " W " << snap.motor_work;
        if (!stepped) break;  // refused steps repeat (dopri5's take 1e5 sub-steps each)
      }
    }
    EXPECT_GT(accepted, 20) << integratorName(type);
  }
}

TEST(Simulator, ResetRestoresInitialStateAndWorkButTimeRunsOn) {
  const Config c = test::defaultConfig();
  Simulator sim(c);
  sim.setTorque(4.0);
  for (int i = 0; i < 100; ++i) ASSERT_TRUE(sim.step().ok);
  sim.reset();
  EXPECT_EQ(sim.ticks(), 100u);
  EXPECT_EQ(sim.motorWork(), 0.0);
  EXPECT_EQ(sim.torque(), 0.0);
  EXPECT_EQ(sim.state().q1, c.initial_state.q1);
  EXPECT_EQ(sim.state().q2, c.initial_state.q2);
  EXPECT_EQ(sim.state().u1, c.initial_state.u1);
  EXPECT_EQ(sim.state().u2, c.initial_state.u2);
}

TEST(Simulator, SnapshotCarriesKaneForcesThatCancel) {
  Simulator sim(test::defaultConfig());
  sim.setTorque(2.0);
  for (int i = 0; i < 123; ++i) ASSERT_TRUE(sim.step().ok);
  const Snapshot s = sim.snapshot();
  EXPECT_LT((s.inertia_forces + s.active_forces).norm(), 1e-12);
  EXPECT_GT(s.active_forces.norm(), 0.1);
  EXPECT_NEAR(s.spring_elongation,
              sim.model().springElongation(sim.model().geometry(s.state.q1, s.state.q2)), 0.0);
}

// doc/reference/outputs.md's table is the output table's (a load added to the model adds its row).
TEST(OutputTable, TheDocumentedTableIsTheCodes) {
  EXPECT_EQ(
      test::generatedDocSection("doc/reference/outputs.md", "rosrun kane_sim config_info outputs"),
      outputTable())
      << "regenerate the table of doc/reference/outputs.md: rosrun kane_sim config_info outputs";
}

}  // namespace
}  // namespace kane_sim
