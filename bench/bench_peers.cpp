// kane_sim side by side with MuJoCo (Debian's libmujoco-dev) on the same mechanism, same
// parameters, same held torque, both by RK4 at dt = 1 ms:
//  1. agreement: q1, q2 after 1 s and 10 s against a tight reference (kane_sim, dopri5 at
//     1e-12), and MuJoCo's loop-closure error (its soft equality constraint), for MuJoCo's
//     default constraint softness and the stiffest its integrator safety allows;
//  2. cost: one step of each (Google Benchmark), with the ratio in the same run.
//   $KANE_SIM_BUILD_DIR/devel/lib/kane_sim/bench_peers [--benchmark_min_time=1]
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <benchmark/benchmark.h>

#include "kane_sim/config/load_config.h"
#include "kane_sim/sim/simulator.h"
#include "mujoco_mechanism.h"
#include "ratio_reporter.h"

namespace {

using kane_sim::bench::LoopClosure;
using kane_sim::bench::MujocoMechanism;

constexpr double kTorque = 2.0;  // [N m] held: a swing the crank's gravity moment holds
constexpr double kStep = 1e-3;   // [s]

kane_sim::Config defaultConfig() {
  return kane_sim::loadConfigFile(KANE_SIM_CONFIG_DIR "/mechanism.yaml").config;
}

struct Sample {
  double q1 = 0, q2 = 0;
};

// kane_sim's state at 1 s and 10 s.
void runKaneSim(kane_sim::Config c, Sample out[2]) {
  kane_sim::Simulator sim(c);
  sim.setTorque(kTorque);
  const int steps_at[2] = {static_cast<int>(std::lround(1.0 * c.simulation.physics_rate)),
                           static_cast<int>(std::lround(10.0 * c.simulation.physics_rate))};
  for (int i = 1, k = 0; k < 2; ++i) {
    sim.step();
    if (i == steps_at[k]) out[k++] = {sim.state().q1, sim.state().q2};
  }
}

void printAgreement() {
  const kane_sim::Config base = defaultConfig();
  kane_sim::Config reference_config = base;
  reference_config.simulation.integrator = kane_sim::IntegratorType::kDopri5;
  reference_config.simulation.absolute_tolerance = 1e-12;
  reference_config.simulation.relative_tolerance = 1e-12;
  Sample reference[2], kane[2];
  runKaneSim(reference_config, reference);
  runKaneSim(base, kane);

  std::printf(
      "Agreement with a tight reference (kane_sim dopri5 at 1e-12), torque %g N m held,\n"
      "both peers RK4 at dt = %g s (MuJoCo %s)\n\n",
      kTorque, kStep, mj_versionString());
  std::printf(
      "| peer | abs(q1 error) 1 s [rad] | abs(q2 error) 1 s [m] | abs(q1 error) 10 s "
      "[rad] | abs(q2 error) 10 s [m] | max loop-closure error [m] |\n"
      "|---|---|---|---|---|---|\n");
  std::printf(
      "| kane_sim rk4 (generated) | %.2e | %.2e | %.2e | %.2e | 0 (minimal coordinates) |\n",
      std::abs(kane[0].q1 - reference[0].q1), std::abs(kane[0].q2 - reference[0].q2),
      std::abs(kane[1].q1 - reference[1].q1), std::abs(kane[1].q2 - reference[1].q2));
  for (LoopClosure closure : {LoopClosure::kMujocoDefault, LoopClosure::kStiff}) {
    MujocoMechanism mujoco(base, kStep, closure);
    mujoco.setTorque(kTorque);
    Sample at[2];
    double worst_loop = 0.0;
    for (int i = 1; i <= 10000; ++i) {
      mujoco.step();
      worst_loop = std::max(worst_loop, mujoco.loopClosureError());
      if (i == 1000) at[0] = {mujoco.q1(), mujoco.q2()};
      if (i == 10000) at[1] = {mujoco.q1(), mujoco.q2()};
    }
    std::printf("| MuJoCo RK4, %s | %.2e | %.2e | %.2e | %.2e | %.2e |\n",
                closure == LoopClosure::kStiff ? "stiff loop (solref 2 dt, solimp 0.9999)"
                                               : "default solref/solimp",
                std::abs(at[0].q1 - reference[0].q1), std::abs(at[0].q2 - reference[0].q2),
                std::abs(at[1].q1 - reference[1].q1), std::abs(at[1].q2 - reference[1].q2),
                worst_loop);
  }
  std::printf("\n");
}

void BM_KaneSimRk4Step(benchmark::State& st) {
  kane_sim::Simulator sim(defaultConfig());
  sim.setTorque(kTorque);
  for (auto _ : st) {
    if (!sim.step().ok) st.SkipWithError("step refused");
    if (sim.ticks() % 100000 == 0) sim.reset(), sim.setTorque(kTorque);
  }
  st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_KaneSimRk4Step);

void BM_MujocoRk4Step(benchmark::State& st, LoopClosure closure) {
  const kane_sim::Config c = defaultConfig();
  auto mujoco = std::make_unique<MujocoMechanism>(c, kStep, closure);
  mujoco->setTorque(kTorque);
  long n = 0;
  for (auto _ : st) {
    mujoco->step();
    if (++n % 100000 == 0) {
      st.PauseTiming();
      mujoco = std::make_unique<MujocoMechanism>(c, kStep, closure);
      mujoco->setTorque(kTorque);
      st.ResumeTiming();
    }
  }
  st.SetItemsProcessed(st.iterations());
}
BENCHMARK_CAPTURE(BM_MujocoRk4Step, stiff_loop, LoopClosure::kStiff);
BENCHMARK_CAPTURE(BM_MujocoRk4Step, default_loop, LoopClosure::kMujocoDefault);

}  // namespace

int main(int argc, char** argv) {
  printAgreement();
  return kane_sim::bench::runWithRatios(argc, argv, "BM_KaneSimRk4Step");
}
