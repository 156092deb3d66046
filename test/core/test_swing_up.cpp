// The swing-up (config/swing_up.yaml): a crank hanging at rest lifted to upright by a drive of
// 10 N m where gravity needs 22.6 N m, planned by direct collocation (plan/plan_design.h) and run
// by the plan follower (design/plan_follower.h) against the sensors, in the loop as the node runs
// it in lockstep (sim/closed_loop.h). Checked: the collocation's defects on a second road (the
// generic Kane assembly), the plan played open loop, and a family of 30 rigs whose masses,
// stiffness and dampers differ from the design's by up to 5 %.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "kane_sim/design/plan_file.h"
#include "kane_sim/design/plan_follower.h"
#include "kane_sim/plan/plan_design.h"
#include "kane_sim/sim/closed_loop.h"
#include "kane_sim/sim/sim_driver.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

Config swingUpConfig() { return loadConfigFile(test::configPath("swing_up.yaml")).config; }

// The recipe of config/swing_up.yaml's header, its rows at the physics rate.
const PlanDesign& swingUpPlan() {
  static const PlanDesign design = [] {
    const Config config = swingUpConfig();
    const MechanismModel model = mechanismModel(config);
    CollocationProblem problem;
    problem.start = config.initial_state;
    problem.goal = equilibriumAt(model, M_PI).state;
    problem.duration = 3.0;
    problem.torque_limit = 8.0;
    problem.intervals = 200;
    LqrWeights weights;
    weights.Q = Eigen::Vector4d(100, 1, 1, 1).asDiagonal();
    weights.R = 1.0;
    return designPlan(model, problem, config.simulation.physics_rate, weights, {}, {});
  }();
  return design;
}

double crankError(double q1) { return std::abs(std::remainder(q1 - M_PI, 2 * M_PI)); }

TEST(SwingUp, CollocationDefectsVanishOnTheGenericAssemblyToo) {
  const PlanDesign& d = swingUpPlan();
  const CollocationSolution& s = d.solution;
  EXPECT_LE(s.max_defect, 1e-8);
  // The same defects from the generic Kane assembly's rates (not the generated equations IPOPT
  // saw): they agree to rounding, so the defects stay below 1e-8 there too.
  const MechanismModel model = mechanismModel(swingUpConfig());
  const auto rate = [&](size_t k) {
    const Eigen::Vector4d& x = s.x[k];
    const OdeState f = model.stateDerivative(State{x[0], x[1], x[2], x[3]}, s.torque[k]);
    return Eigen::Vector4d(f[0], f[1], f[2], f[3]);
  };
  const size_t intervals = (s.x.size() - 1) / 2;
  const double h = s.duration / static_cast<double>(intervals);
  double worst = 0.0;
  for (size_t i = 0; i < intervals; ++i) {
    const size_t a = 2 * i, m = a + 1, b = a + 2;
    const Eigen::Vector4d mid = s.x[m] - (s.x[a] + s.x[b]) / 2 - h / 8 * (rate(a) - rate(b));
    const Eigen::Vector4d simpson = s.x[b] - s.x[a] - h / 6 * (rate(a) + 4 * rate(m) + rate(b));
    worst = std::max({worst, mid.cwiseAbs().maxCoeff(), simpson.cwiseAbs().maxCoeff()});
  }
  EXPECT_LE(worst, 1e-8);
  for (double torque : s.torque) EXPECT_LE(std::abs(torque), 8.0 + 1e-8);
  // The crank really must pump: the plan swings back before it rises.
  double lowest = 0.0;
  for (const auto& x : s.x) lowest = std::min(lowest, x[0]);
  EXPECT_LT(lowest, -0.3);
  std::printf("collocation: %d iterations, largest defect %.2e (generated) %.2e (generic)\n",
              s.iterations, s.max_defect, worst);
}

// Open loop (the plan's torques held over each physics step, as `simulate --torque-csv` plays
// them) the motion follows the plan until the crank nears the top, where upright's instability
// (a real eigenvalue of 11.6 1/s: errors grow e-fold in 86 ms) takes the small differences
// between the collocation's polynomials and the integrator's steps and throws the crank off.
TEST(SwingUp, PlayedOpenLoopItFollowsThePlanToTheTopAndFallsOff) {
  const Plan& plan = swingUpPlan().plan;
  Config config = swingUpConfig();
  config.sensors.enabled = false;
  SimDriver driver(config, {});
  double closest = M_PI, largest_gap = 0.0, within = 0.0, near_top_at = -1.0;
  while (driver.time() < plan.duration() + 3.0) {
    driver.command(plan.at(driver.time()).torque);
    ASSERT_TRUE(driver.step());
    const double q1 = driver.simulator().state().q1;
    const PlanPoint reference = plan.at(driver.time());
    if (near_top_at < 0) largest_gap = std::max(largest_gap, std::abs(q1 - reference.x[0]));
    if (near_top_at < 0 && crankError(reference.x[0]) < 0.1) near_top_at = driver.time();
    closest = std::min(closest, crankError(q1));
    if (crankError(q1) <= 0.05) within += 1.0 / config.simulation.physics_rate;
  }
  std::printf(
      "open loop: within %.2g rad of the plan until it nears the top (t = %.3f s); closest to "
      "upright %.3g rad; within 0.05 rad for %.3g s in all\n",
      largest_gap, near_top_at, closest, within);
  ASSERT_GT(near_top_at, 0.0);
  EXPECT_LT(largest_gap, 0.01);
  EXPECT_LT(closest, 0.1);  // the goal's neighbourhood: measured 0.076 rad
  EXPECT_GT(crankError(driver.simulator().state().q1), 0.05);  // and then it falls
}

struct RigResult {
  bool held = false;
  double final_error = 0.0;  // [rad] |q1 - pi| at the end
  double worst_hold = 0.0;   // [rad] the largest over the hold
  double peak_torque = 0.0;
  double ledger = 0.0;  // [J] |E - E0 - W + D|
};

RigResult runRig(const Config& rig, const Plan& plan, double hold) {
  SimDriver driver(rig, {});
  PlanFollower follower(plan, rig.command.torque_limit);
  const double e0 = driver.snapshot().energy.total();
  RigResult r;
  runClosedLoop(
      driver, plan.duration() + hold,
      [&](std::int64_t stamp, const JointValues& joints) {
        return follower.command(stamp, stateFromJoints(joints));
      },
      [&](const SimDriver& d) {
        const State& x = d.simulator().state();
        r.peak_torque = std::max(r.peak_torque, std::abs(d.simulator().torque()));
        if (d.time() >= plan.duration()) r.worst_hold = std::max(r.worst_hold, crankError(x.q1));
        return true;
      });
  const Snapshot s = driver.snapshot();
  r.final_error = crankError(s.state.q1);
  r.held = r.worst_hold <= 0.05 && driver.time() >= plan.duration() + hold - 1e-6;
  r.ledger = std::abs(s.energy.total() - e0 - s.motor_work + s.dissipated_energy);
  return r;
}

// The shipped plan (config/swing_up_plan.csv, rows every 5 ms), as the node's tracking
// controller reads it, on 30 rigs: each mass, the rod's inertia, k and both dampers drawn within
// 5 % of the design's (the scale of identify's error bars), the sensors of config/sensors.yaml
// with a seed of their own.
TEST(SwingUp, AFamilyOfRigsFivePercentOffIsSwungUpAndHeld) {
  const PlanFile file = readPlanCsv(test::configPath("swing_up_plan.csv"));
  ASSERT_EQ(planMismatch(file, swingUpConfig()), "");
  const Plan& plan = file.plan;
  const Config nominal = swingUpConfig();
  std::mt19937 random(20261127);
  std::uniform_real_distribution<double> off(0.95, 1.05);
  std::vector<RigResult> results;
  for (int rig = 0; rig < 30; ++rig) {
    Config c = nominal;
    MechanismParameters& m = c.mechanism;
    m.rod_mass *= off(random);
    m.rod_inertia *= off(random);
    m.slider3_mass *= off(random);
    m.slider4_mass *= off(random);
    m.spring_stiffness *= off(random);
    m.damping.crank_joint *= off(random);
    m.damping.slider4_joint *= off(random);
    c.sensors.seed = static_cast<std::uint64_t>(rig + 1);
    results.push_back(runRig(c, plan, 60.0));
  }
  int held = 0;
  std::vector<double> errors, peaks, ledgers;
  for (const RigResult& r : results) {
    held += r.held;
    errors.push_back(r.worst_hold);
    peaks.push_back(r.peak_torque);
    ledgers.push_back(r.ledger);
  }
  std::sort(errors.begin(), errors.end());
  std::sort(peaks.begin(), peaks.end());
  std::printf(
      "family: %d of 30 held within 0.05 rad for 60 s; worst error over the hold median %.4f, "
      "worst %.4f rad; peak torque median %.3f, worst %.3f N m; ledger worst %.2e J\n",
      held, errors[15], errors.back(), peaks[15], peaks.back(),
      *std::max_element(ledgers.begin(), ledgers.end()));
  EXPECT_GE(held, 27);
  for (double ledger : ledgers) EXPECT_LT(ledger, 1e-6);
}

}  // namespace
}  // namespace kane_sim
