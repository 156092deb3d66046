// The physics options through the live node (test/node/options.test, test/node/options.yaml:
// all four joint dampers on, slider contact on with e = 0.5, motor line off at start):
// mechanism_state carries the energy ledger, a damper changed through dynamic_reconfigure
// acts from the next step, contact holds under the hard drive, and the motor line set at
// runtime limits the applied torque. The tests share one node and run in this order.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "kane_sim/MechanismState.h"
#include "node_test_utils.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

class Options : public test::SimNodeTest {
 protected:
  // Messages that arrive in the next `seconds` of wall time (the node runs at real time).
  std::vector<MechanismState> record(double seconds) {
    state_.clear();
    test::sleepWall(seconds);
    return state_.messages();
  }
  void setAllDampers(double crank, double coupler, double slider3, double slider4) {
    EXPECT_EQ(test::reconfigure("crank_damping", crank), crank);
    EXPECT_EQ(test::reconfigure("coupler_damping", coupler), coupler);
    EXPECT_EQ(test::reconfigure("slider3_damping", slider3), slider3);
    EXPECT_EQ(test::reconfigure("slider4_damping", slider4), slider4);
  }
};

double spread(const std::vector<MechanismState>& ms, double MechanismState::*field) {
  const auto [lo, hi] = std::minmax_element(
      ms.begin(), ms.end(), [&](const auto& a, const auto& b) { return a.*field < b.*field; });
  return (*hi).*field - (*lo).*field;
}

// Released from rest under gravity with the dampers of options.yaml: the energy only falls,
// the dampers' take only grows, and E + D - W stays constant (rk4 at 1 kHz keeps it to ~1e-9 J
// over 10 s offline; 1e-7 J leaves margin and is still 1e-5 of the D accumulated here).
TEST_F(Options, DampersDissipateAndTheLedgerHolds) {
  const std::vector<MechanismState> ms = record(2.0);
  ASSERT_GT(ms.size(), 150u);
  for (size_t i = 1; i < ms.size(); ++i) {
    EXPECT_GE(ms[i].dissipated_energy, ms[i - 1].dissipated_energy - 1e-12) << i;
    EXPECT_LE(ms[i].total_energy, ms[i - 1].total_energy + 1e-9) << i;
  }
  EXPECT_GT(ms.back().dissipated_energy, 0.01) << "the dampers took nothing";
  EXPECT_EQ(ms.back().motor_work, 0.0);
  EXPECT_LT(spread(ms, &MechanismState::energy_balance), 1e-7);
  EXPECT_EQ(ms.back().contact_impacts, 0u) << "no impact in the free swing";
}

// Dampers off through dynamic_reconfigure: D stops growing while the crank still turns. One
// damper back on: D grows by the crank damper's power c_O u1^2 alone, and a damping change
// books no energy jump (the ledger carries on).
TEST_F(Options, ReconfiguredDampersActFromTheNextStep) {
  test::send(torque_, 5.0);
  setAllDampers(0.0, 0.0, 0.0, 0.0);
  test::sleepWall(0.1);  // in force from the node's next tick
  std::vector<MechanismState> ms = record(1.0);
  ASSERT_GT(ms.size(), 80u);
  EXPECT_LT(spread(ms, &MechanismState::dissipated_energy), 1e-12);
  EXPECT_GT(std::abs(ms.back().u[0]) + std::abs(ms.front().u[0]), 0.1) << "the crank stands";

  const double c_O = 0.5;
  EXPECT_EQ(test::reconfigure("crank_damping", c_O), c_O);
  test::sleepWall(0.1);
  ms = record(1.0);
  ASSERT_GT(ms.size(), 80u);
  // Trapezoid over the published samples (10 ms apart in sim time) of c_O u1^2.
  double predicted = 0.0;
  for (size_t i = 1; i < ms.size(); ++i)
    predicted += 0.5 * c_O * (ms[i].u[0] * ms[i].u[0] + ms[i - 1].u[0] * ms[i - 1].u[0]) *
                 (ms[i].sim_time - ms[i - 1].sim_time);
  const double taken = ms.back().dissipated_energy - ms.front().dissipated_energy;
  EXPECT_GT(taken, 0.05);
  EXPECT_NEAR(taken, predicted, 0.01 * predicted) << "D' = c_O u1^2";
  EXPECT_EQ(ms.back().parameter_energy, ms.front().parameter_energy);
  EXPECT_LT(spread(ms, &MechanismState::energy_balance), 1e-7);
  setAllDampers(0.05, 0.02, 0.5, 0.5);
  test::send(torque_, 0.0);
}

// The drive that makes the sliders pass through each other in the textbook model: with
// contact on they bounce (e = 0.5), never come closer than the gap, never cross, and the
// impacts' losses land in D so the ledger holds (rk4 at these speeds: 2e-5 of W, as offline).
TEST_F(Options, HardDriveWithContactNeverCrosses) {
  test::send(torque_, 50.0);
  const std::vector<MechanismState> ms = record(2.0);
  test::send(torque_, 0.0);
  ASSERT_GT(ms.size(), 150u);
  for (const MechanismState& m : ms) EXPECT_GE(m.slider_separation, 0.07 - 1e-9) << m.sim_time;
  EXPECT_EQ(ms.back().slider_crossings, 0u);
  EXPECT_GT(ms.back().contact_impacts, ms.front().contact_impacts) << "the drive hit nothing";
  const double work = ms.back().motor_work - ms.front().motor_work;
  EXPECT_GT(work, 100.0);
  EXPECT_LT(spread(ms, &MechanismState::energy_balance), 2e-5 * work);
}

// The motor line switched on at runtime (w0 = 20 rad/s, stall torque = torque_limit 50 N m):
// under a held 50 N m command the applied torque never exceeds 50 (1 - |u1|/20) in the
// direction the crank turns, the command stays visible, and the speed stays bounded.
TEST_F(Options, MotorLineSetAtRuntimeLimitsTheAppliedTorque) {
  EXPECT_EQ(test::reconfigure("motor_no_load_speed", 20.0), 20.0);
  test::send(torque_, 50.0);
  ASSERT_TRUE(waitForState([](const MechanismState& m) { return m.commanded_torque == 50.0; }, 5));
  test::sleepWall(0.1);
  const std::vector<MechanismState> ms = record(3.0);
  test::send(torque_, 0.0);
  ASSERT_GT(ms.size(), 250u);
  double max_speed = 0.0;
  for (const MechanismState& m : ms) {
    const double u1 = m.u[0];
    EXPECT_EQ(m.commanded_torque, 50.0);
    EXPECT_LE(std::abs(m.applied_torque), 50.0);
    if (m.applied_torque * u1 > 0.0) {
      EXPECT_LE(std::abs(m.applied_torque), 50.0 * std::max(0.0, 1.0 - std::abs(u1) / 20.0) + 1e-9)
          << "u1 " << u1 << " at " << m.sim_time;
    }
    max_speed = std::max(max_speed, std::abs(u1));
  }
  // Offline the same line swings u1 within [-38, 57] rad/s with rk4 (doc/reference/parameters.md);
  // without it > 100.
  EXPECT_LT(max_speed, 80.0);
  EXPECT_TRUE(std::any_of(ms.begin(), ms.end(), [](const MechanismState& m) {
    return m.applied_torque < 40.0;
  })) << "the line never acted";
}

// Resting contact live (the repro: `dynparam set /kane_sim "{gravity: -100.0, spring_stiffness:
// 0.0}"` let slider 4 through slider 3): with gravity pulling slider 4 up onto slider 3 and no
// spring, it lands, comes to rest on it and stays: every message at least the gap apart, no
// crossing, the contact force pushing. Then the rk4 bound refuses what it cannot integrate, by
// the loader's rule (rod_mass 1e-4 was accepted and stalled the node).
TEST_F(Options, RestingContactHoldsUnderReversedGravity) {
  EXPECT_EQ(test::reconfigure("motor_no_load_speed", 0.0), 0.0);
  test::send(torque_, 0.0);
  EXPECT_EQ(test::reconfigure("spring_stiffness", 0.0), 0.0);
  EXPECT_EQ(test::reconfigure("gravity", -100.0), -100.0);
  const std::vector<MechanismState> ms = record(4.0);
  ASSERT_GT(ms.size(), 300u);
  bool rested = false;
  for (const MechanismState& m : ms) {
    EXPECT_GE(m.slider_separation, 0.07 - 1e-9) << "at " << m.sim_time;
    EXPECT_GE(m.contact_force, 0.0) << "at " << m.sim_time;
    rested = rested || m.resting_contact;
  }
  EXPECT_TRUE(rested) << "slider 4 never came to rest on slider 3";
  EXPECT_EQ(ms.back().slider_crossings, ms.front().slider_crossings);
  EXPECT_EQ(test::reconfigure("rod_mass", 1e-4), 1.0) << "beyond rk4 at 1 kHz: refused";
  EXPECT_EQ(test::reconfigure("gravity", 9.81), 9.81);
  EXPECT_EQ(test::reconfigure("spring_stiffness", 200.0), 200.0);
}

}  // namespace
}  // namespace kane_sim
