// kane_sim side by side with MuJoCo (Debian's libmujoco-dev) on the same mechanism, same
// parameters, same held torque, both by RK4 at dt = 1 ms:
//  1. agreement: q1, q2 after 1 s and 10 s against a tight reference (kane_sim, dopri5 at
//     1e-12), and MuJoCo's loop-closure error (its soft equality constraint), for MuJoCo's
//     default constraint softness and the stiffest its integrator safety allows; and, when
//     Debian's libsimbody-dev is installed, Simbody (exact loop closure) as an accuracy peer;
//  2. cost: one step of each (Google Benchmark), with the ratio in the same run.
//   $KANE_SIM_BUILD_DIR/devel/lib/kane_sim/bench_peers [--benchmark_min_time=1]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include <benchmark/benchmark.h>

#include "kane_sim/config/load_config.h"
#include "kane_sim/sim/simulator.h"
#include "mujoco_mechanism.h"
#include "ratio_reporter.h"
#ifdef KANE_SIM_HAVE_SIMBODY
#include "simbody_mechanism.h"
#endif

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

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// kane_sim's state at 1 s and 10 s; returns the wall time of the run [s].
double runKaneSim(kane_sim::Config c, Sample out[2]) {
  const auto start = std::chrono::steady_clock::now();
  kane_sim::Simulator sim(c);
  sim.setTorque(kTorque);
  const int steps_at[2] = {static_cast<int>(std::lround(1.0 * c.simulation.physics_rate)),
                           static_cast<int>(std::lround(10.0 * c.simulation.physics_rate))};
  for (int i = 1, k = 0; k < 2; ++i) {
    sim.step();
    if (i == steps_at[k]) out[k++] = {sim.state().q1, sim.state().q2};
  }
  return secondsSince(start);
}

void printRow(const char* peer, const Sample at[2], const Sample reference[2], double wall,
              const char* loop_error) {
  std::printf("| %s | %.2e | %.2e | %.2e | %.2e | %s | %.2f |\n", peer,
              std::abs(at[0].q1 - reference[0].q1), std::abs(at[0].q2 - reference[0].q2),
              std::abs(at[1].q1 - reference[1].q1), std::abs(at[1].q2 - reference[1].q2),
              loop_error, 1e3 * wall);
}

// The largest |q1| and |q2| error at 1 s and 10 s.
double worstError(const Sample at[2], const Sample reference[2]) {
  double worst = 0.0;
  for (int k = 0; k < 2; ++k)
    worst = std::max(
        {worst, std::abs(at[k].q1 - reference[k].q1), std::abs(at[k].q2 - reference[k].q2)});
  return worst;
}

// Each model must agree with the reference within its stated tolerance (the exit code of the
// benchmark says so): kane_sim rk4 at 1 ms 1e-7, MuJoCo with the stiff loop 1e-3 (its soft
// closure, 80 µm of loop error, moves the motion ~1e-4 in 10 s), Simbody at accuracy 1e-10
// 1e-7. MuJoCo's defaults are reported, not judged (6.8 mm of loop error).
bool agreementOk(const char* peer, double error, double tolerance) {
  if (error <= tolerance) return true;
  std::fprintf(stderr, "error: %s disagrees with the reference by %.3g (tolerance %.3g)\n", peer,
               error, tolerance);
  return false;
}

bool printAgreement() {
  bool ok = true;
  const kane_sim::Config base = defaultConfig();
  kane_sim::Config reference_config = base;
  reference_config.simulation.integrator = kane_sim::IntegratorType::kDopri5;
  reference_config.simulation.absolute_tolerance = 1e-12;
  reference_config.simulation.relative_tolerance = 1e-12;
  Sample reference[2], kane[2];
  runKaneSim(reference_config, reference);
  const double kane_wall = runKaneSim(base, kane);

  std::printf(
      "Agreement with a tight reference (kane_sim dopri5 at 1e-12), torque %g N m held,\n"
      "10 s simulated; MuJoCo %s RK4 at dt = %g s like kane_sim's rk4\n\n",
      kTorque, mj_versionString(), kStep);
  std::printf(
      "| peer | abs(q1 error) 1 s [rad] | abs(q2 error) 1 s [m] | abs(q1 error) 10 s "
      "[rad] | abs(q2 error) 10 s [m] | max loop-closure error [m] | wall time of 10 s [ms] |\n"
      "|---|---|---|---|---|---|---|\n");
  printRow("kane_sim rk4 (generated)", kane, reference, kane_wall, "0 (minimal coordinates)");
  ok &= agreementOk("kane_sim rk4", worstError(kane, reference), 1e-7);
  char text[32];
  for (LoopClosure closure : {LoopClosure::kMujocoDefault, LoopClosure::kStiff}) {
    const auto start = std::chrono::steady_clock::now();
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
    const double wall = secondsSince(start);
    std::snprintf(text, sizeof(text), "%.2e", worst_loop);
    printRow(closure == LoopClosure::kStiff ? "MuJoCo RK4, stiff loop (solref 2 dt, solimp 0.9999)"
                                            : "MuJoCo RK4, default solref/solimp",
             at, reference, wall, text);
    if (closure == LoopClosure::kStiff)
      ok &= agreementOk("MuJoCo (stiff loop)", worstError(at, reference), 1e-3);
  }
#ifdef KANE_SIM_HAVE_SIMBODY
  for (double accuracy : {1e-6, 1e-10}) {
    const auto start = std::chrono::steady_clock::now();
    kane_sim::bench::SimbodyMechanism simbody(base, kTorque, accuracy);
    Sample at[2];
    double worst_loop = 0.0;
    for (int i = 1; i <= 1000; ++i) {  // every 10 ms: the loop-closure error, and 1 s, 10 s
      simbody.advanceTo(i * 0.01);
      worst_loop = std::max(worst_loop, simbody.loopClosureError());
      if (i == 100) at[0] = {simbody.q1(), simbody.q2()};
      if (i == 1000) at[1] = {simbody.q1(), simbody.q2()};
    }
    const double wall = secondsSince(start);
    std::snprintf(text, sizeof(text), "%.2e", worst_loop);
    int major = 0, minor = 0, build = 0;
    SimTK_version_simbody(&major, &minor, &build);
    char peer[64];
    std::snprintf(peer, sizeof(peer), "Simbody %d.%d RK-Merson, accuracy %g", major, minor,
                  accuracy);
    printRow(peer, at, reference, wall, text);
    if (accuracy <= 1e-10) ok &= agreementOk(peer, worstError(at, reference), 1e-7);
  }
#endif
  std::printf("\n");
  return ok;
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
  const bool agreement = printAgreement();
  const int status = kane_sim::bench::runWithRatios(argc, argv, "BM_KaneSimRk4Step");
  return agreement ? status : 1;
}
