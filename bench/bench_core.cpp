// Core throughput (Google Benchmark): one evaluation of the equations of motion through the
// generic Kane assembly and through the generated equations, one rk4 step of the Simulator on
// each, dopri5 per simulated second, and - in the same binary - the floor: a hand-written
// closed-form rk4 step of the same equations. The table at the end gives every time as a ratio
// to that floor.
//   $KANE_SIM_BUILD_DIR/bench_bin/bench_core --benchmark_min_time=0.5
#include <cmath>
#include <vector>

#include <benchmark/benchmark.h>

#include "kane_sim/config/load_config.h"
#include "kane_sim/model/generated_mechanism.h"
#include "kane_sim/model/math_functions.h"
#include "kane_sim/sim/simulator.h"
#include "ratio_reporter.h"

namespace {

kane_sim::Config defaultConfig() {
  return kane_sim::loadConfigFile(KANE_SIM_CONFIG_DIR "/mechanism.yaml").config;
}

// A state in the middle of a driven motion, so no term is trivially zero.
const kane_sim::State kBusyState{0.9, 1.05, 3.2, -0.7};

void BM_KaneEvaluation(benchmark::State& st) {
  const kane_sim::Config c = defaultConfig();
  const kane_sim::MechanismModel model = kane_sim::mechanismModel(c);
  kane_sim::State x = kBusyState;
  for (auto _ : st) {
    benchmark::DoNotOptimize(x);
    const kane_sim::SpeedVector u_dot = model.accelerations(x, 2.0);
    benchmark::DoNotOptimize(u_dot);
  }
  st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_KaneEvaluation);

void BM_GeneratedEvaluation(benchmark::State& st) {
  const kane_sim::Config c = defaultConfig();
  const kane_sim::GeneratedMechanism generated(kane_sim::mechanismModel(c));
  kane_sim::State x = kBusyState;
  for (auto _ : st) {
    benchmark::DoNotOptimize(x);
    const kane_sim::OdeState dx = generated.stateDerivative(x, 2.0);
    benchmark::DoNotOptimize(dx);
  }
  st.SetItemsProcessed(st.iterations());
}
BENCHMARK(BM_GeneratedEvaluation);

// How a step is driven. kHeld: 2 N m throughout (the floor's drive). kSwung: 2 + 10 sin(2 pi t)
// N m, the crank swung through about +-2 rad at 1 Hz, so the mechanism keeps moving whatever
// its loads (under kHeld the lossy mechanism comes to rest within seconds and stays there).
enum class Drive { kHeld, kSwung };

// The dampers and Coulomb friction on (the generated variant with every term).
void turnOnEveryLoad(kane_sim::Config* c) {
  auto& p = c->mechanism;
  p.damping = {0.01, 0.01, 0.5, 0.5, 0.2};  // crank, coupler, slider3, slider4, spring
  p.friction.crank_joint = p.friction.coupler_joint = 0.02;
  p.friction.slider3_joint = p.friction.slider4_joint = 0.3;
}

// every_load, held: at rest within seconds, where every friction tanh is in its smooth part (the
// whole algorithm, |v| < 18.7 v_s). Swung: moving, where most are beyond it (exactly +-1).
void BM_Rk4Step(benchmark::State& st, kane_sim::EquationsSource equations, bool every_load,
                Drive drive) {
  kane_sim::Config c = defaultConfig();
  c.simulation.integrator = kane_sim::IntegratorType::kRk4;
  c.simulation.equations = equations;
  if (every_load) turnOnEveryLoad(&c);
  std::vector<double> swing(static_cast<std::size_t>(std::lround(c.simulation.physics_rate)));
  for (std::size_t i = 0; i < swing.size(); ++i) {
    swing[i] = 2.0 + 10.0 * std::sin(2.0 * M_PI * static_cast<double>(i) / swing.size());
  }
  kane_sim::Simulator sim(c);
  sim.setTorque(2.0);
  for (auto _ : st) {
    if (drive == Drive::kSwung) sim.setTorque(swing[sim.ticks() % swing.size()]);
    if (!sim.step().ok) st.SkipWithError("step refused");
    if (sim.ticks() % 100000 == 0) sim.reset();  // stay in the same regime of motion
  }
  st.SetItemsProcessed(st.iterations());
}
BENCHMARK_CAPTURE(BM_Rk4Step, generated, kane_sim::EquationsSource::kGenerated, false,
                  Drive::kHeld);
BENCHMARK_CAPTURE(BM_Rk4Step, generic, kane_sim::EquationsSource::kGeneric, false, Drive::kHeld);
BENCHMARK_CAPTURE(BM_Rk4Step, generated_every_load, kane_sim::EquationsSource::kGenerated, true,
                  Drive::kHeld);
BENCHMARK_CAPTURE(BM_Rk4Step, generated_swung, kane_sim::EquationsSource::kGenerated, false,
                  Drive::kSwung);
BENCHMARK_CAPTURE(BM_Rk4Step, generated_every_load_swung, kane_sim::EquationsSource::kGenerated,
                  true, Drive::kSwung);

// dopri5: the cost of one simulated second at 1 kHz physics, per tolerance.
void BM_Dopri5PerSimSecond(benchmark::State& st) {
  kane_sim::Config c = defaultConfig();
  c.simulation.integrator = kane_sim::IntegratorType::kDopri5;
  c.simulation.absolute_tolerance = c.simulation.relative_tolerance = std::pow(10.0, -st.range(0));
  for (auto _ : st) {
    kane_sim::Simulator sim(c);
    sim.setTorque(2.0);
    for (int i = 0; i < 1000; ++i)
      if (!sim.step().ok) st.SkipWithError("step refused");
  }
  st.SetItemsProcessed(st.iterations());
  st.SetLabel("tolerance 1e-" + std::to_string(st.range(0)));
}
BENCHMARK(BM_Dopri5PerSimSecond)->Arg(6)->Arg(9)->Arg(12)->Unit(benchmark::kMillisecond);

// ---- the floor: the same equations written out by hand -------------------------------------
// kDeterministicTrig: sin and cos as every path of the simulator takes them (math::sinCos,
// SLEEF's deterministic algorithm without fused multiply-adds); otherwise glibc's, which picks
// an FMA variant on CPUs that have it. The two floors tell the math's share of the ratio.
template <bool kDeterministicTrig>
struct ClosedForm {
  double m, L, M1, M2, k, g, I, separation0;  // separation0 = x_B0 - x_C0, the spring at rest

  // u1' = (F1 + F*1|u'=0) / M11,  u2' = F2 / M2 (M is diagonal for this mechanism).
  void operator()(const double x[4], double torque, double dx[4]) const {
    double s, c;
    if (kDeterministicTrig) {
      kane_sim::math::sinCos(x[0], &s, &c);
    } else {
      s = std::sin(x[0]);
      c = std::cos(x[0]);
    }
    const double e = 4 * L * c - x[1] - separation0;
    const double m11 = m * L * L * (2 + 8 * s * s) + 16 * M1 * L * L * s * s + 2 * I;
    const double f1 = torque - 4 * g * L * (m + M1) * s + 4 * k * L * e * s -
                      (8 * m + 16 * M1) * L * L * s * c * x[2] * x[2];
    dx[0] = x[2];
    dx[1] = x[3];
    dx[2] = f1 / m11;
    dx[3] = (M2 * g + k * e) / M2;
  }
};

template <bool kDeterministicTrig>
void closedFormRk4Steps(benchmark::State& st) {
  const kane_sim::Config c = defaultConfig();
  const auto& p = c.mechanism;
  const ClosedForm<kDeterministicTrig> f{
      p.rod_mass, p.rod_half_length, p.slider3_mass, p.slider4_mass, p.spring_stiffness, p.gravity,
      p.rod_inertia,
      // The model's rest length (x_C0 - x_B0), not a second formula for it.
      -kane_sim::mechanismModel(c).springRestLength()};
  const double h = 1e-3;
  double x[4] = {c.initial_state.q1, c.initial_state.q2, 0, 0};
  long n = 0;
  for (auto _ : st) {
    double k1[4], k2[4], k3[4], k4[4], y[4];
    f(x, 2.0, k1);
    for (int i = 0; i < 4; ++i) y[i] = x[i] + 0.5 * h * k1[i];
    f(y, 2.0, k2);
    for (int i = 0; i < 4; ++i) y[i] = x[i] + 0.5 * h * k2[i];
    f(y, 2.0, k3);
    for (int i = 0; i < 4; ++i) y[i] = x[i] + h * k3[i];
    f(y, 2.0, k4);
    for (int i = 0; i < 4; ++i) x[i] += h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    benchmark::DoNotOptimize(x);
    if (++n % 100000 == 0) x[0] = c.initial_state.q1, x[1] = c.initial_state.q2, x[2] = x[3] = 0;
  }
  st.SetItemsProcessed(st.iterations());
}
void BM_ClosedFormRk4StepFloor(benchmark::State& st) { closedFormRk4Steps<false>(st); }
BENCHMARK(BM_ClosedFormRk4StepFloor);
void BM_ClosedFormRk4StepFloorDeterministicTrig(benchmark::State& st) {
  closedFormRk4Steps<true>(st);
}
BENCHMARK(BM_ClosedFormRk4StepFloorDeterministicTrig);

}  // namespace

int main(int argc, char** argv) {
  return kane_sim::bench::runWithRatios(argc, argv, "BM_ClosedFormRk4StepFloor");
}
