// Controller design's costs (Google Benchmark): the generated exact Jacobian against one
// evaluation of the rates it differentiates, the linearization at a state, every equilibrium
// around the turn, and an LQR design at the upright crank (the equilibrium, the linearization,
// the controllable subspace, the Riccati equation); the swing-up's plan (config/swing_up.yaml:
// 3 s, 200 Hermite-Simpson intervals, IPOPT) and the tracking law a controller evaluates per
// reading (the shipped plan, interpolated, clamped).
//   $KANE_SIM_BUILD_DIR/bench_bin/bench_design --benchmark_min_time=0.5
#include <cmath>

#include <benchmark/benchmark.h>

#include "kane_sim/analysis/linear_analysis.h"
#include "kane_sim/config/load_config.h"
#include "kane_sim/design/lqr.h"
#include "kane_sim/design/plan_file.h"
#include "kane_sim/design/plan_follower.h"
#include "kane_sim/model/generated_mechanism.h"
#include "kane_sim/plan/plan_design.h"

namespace {

kane_sim::Config defaultConfig() {
  return kane_sim::loadConfigFile(KANE_SIM_CONFIG_DIR "/mechanism.yaml").config;
}

const kane_sim::State kBusyState{0.9, 1.05, 3.2, -0.7};

void BM_GeneratedRates(benchmark::State& st) {
  const kane_sim::GeneratedMechanism generated(kane_sim::mechanismModel(defaultConfig()));
  kane_sim::State x = kBusyState;
  for (auto _ : st) {
    benchmark::DoNotOptimize(x);
    const kane_sim::generated::Rates r =
        kane_sim::generated::rates(generated.constants(), x.q1, x.q2, x.u1, x.u2, 2.0);
    benchmark::DoNotOptimize(r);
  }
}
BENCHMARK(BM_GeneratedRates);

void BM_GeneratedJacobian(benchmark::State& st) {
  const kane_sim::GeneratedMechanism generated(kane_sim::mechanismModel(defaultConfig()));
  kane_sim::State x = kBusyState;
  for (auto _ : st) {
    benchmark::DoNotOptimize(x);
    const kane_sim::generated::RateJacobian j =
        kane_sim::generated::rateJacobian(generated.constants(), x.q1, x.q2, x.u1, x.u2, 2.0);
    benchmark::DoNotOptimize(j);
  }
}
BENCHMARK(BM_GeneratedJacobian);

void BM_Linearize(benchmark::State& st) {
  const kane_sim::MechanismModel model = kane_sim::mechanismModel(defaultConfig());
  for (auto _ : st) benchmark::DoNotOptimize(kane_sim::linearize(model, kBusyState, 2.0));
}
BENCHMARK(BM_Linearize)->Unit(benchmark::kMicrosecond);

void BM_Equilibria(benchmark::State& st) {
  const kane_sim::MechanismModel model = kane_sim::mechanismModel(defaultConfig());
  for (auto _ : st) benchmark::DoNotOptimize(kane_sim::equilibria(model, 0.0));
}
BENCHMARK(BM_Equilibria)->Unit(benchmark::kMillisecond);

void BM_LqrDesignUpright(benchmark::State& st) {
  const kane_sim::Config c = defaultConfig();
  const kane_sim::MechanismModel model = kane_sim::mechanismModel(c);
  const kane_sim::LqrWeights weights = kane_sim::defaultLqrWeights(c, model);
  for (auto _ : st) benchmark::DoNotOptimize(kane_sim::designLqr(model, M_PI, weights));
}
BENCHMARK(BM_LqrDesignUpright)->Unit(benchmark::kMicrosecond);

// design plan --config config/swing_up.yaml --to pi --duration 3 --intervals 200
//   --torque-limit 8 --Q 100,1,1,1 --R 1 (rows at the physics rate)
void BM_PlanSwingUp200(benchmark::State& st) {
  const kane_sim::Config c = kane_sim::loadConfigFile(KANE_SIM_CONFIG_DIR "/swing_up.yaml").config;
  const kane_sim::MechanismModel model = kane_sim::mechanismModel(c);
  kane_sim::CollocationProblem problem;
  problem.start = c.initial_state;
  problem.goal = kane_sim::equilibriumAt(model, M_PI).state;
  problem.duration = 3.0;
  problem.intervals = 200;
  problem.torque_limit = 8.0;
  kane_sim::LqrWeights weights;
  weights.Q = Eigen::Vector4d(100, 1, 1, 1).asDiagonal();
  weights.R = 1.0;
  for (auto _ : st)
    benchmark::DoNotOptimize(kane_sim::designPlan(model, problem, 1000.0, weights, {}, {}));
}
BENCHMARK(BM_PlanSwingUp200)->Unit(benchmark::kMillisecond)->Iterations(3);

// One reading answered by the tracking law (what tracking_controller does per joint_states).
void BM_PlanFollowerCommand(benchmark::State& st) {
  const kane_sim::PlanFile file = kane_sim::readPlanCsv(KANE_SIM_CONFIG_DIR "/swing_up_plan.csv");
  kane_sim::PlanFollower follower(file.plan, 10.0);
  std::int64_t stamp = 0;
  kane_sim::State x{0.1, 1.3, 0.2, 0.0};
  for (auto _ : st) {
    stamp = (stamp + 1000000) % 4000000000;  // 1 ms readings over the plan and past its end
    benchmark::DoNotOptimize(follower.command(stamp, x));
  }
}
BENCHMARK(BM_PlanFollowerCommand)->Unit(benchmark::kNanosecond);

}  // namespace

BENCHMARK_MAIN();
