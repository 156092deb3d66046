// Running a sweep: each case through the one driver and runProfile, on a thread per core,
// results handed to the sink in case order.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <system_error>
#include <thread>

#include "kane_sim/sim/parallel.h"
#include "kane_sim/sim/profile_commands.h"
#include "kane_sim/sim/sim_driver.h"
#include "kane_sim/sim/sweep.h"
#include "lane_sweep.h"

namespace kane_sim {

namespace {
// Cases per task with lanes: 8 blocks of AVX-512's 8; small enough that two threads share a
// 1000-case sweep evenly.
constexpr size_t kSweepChunk = 64;
}  // namespace

unsigned maxSweepJobs() { return 4 * coreCount(); }

SweepResult runSweepCase(const Config& config, const SweepSettings& settings) {
  const auto wall_start = std::chrono::steady_clock::now();
  SweepResult r;
  std::string refusal;
  SimDriver driver(config, [&refusal](const SimEvent& event) {
    if (event.kind == SimEvent::Kind::kStepRefused) refusal = event.message;
  });
  const long steps = std::lround(settings.duration * config.simulation.physics_rate);
  const long steps_per_sample =
      std::max(1L, std::lround(config.simulation.physics_rate / settings.ledger_rate));
  const double start_balance = driver.snapshot().energyBalance();
  const TorqueProfile profile = profileOrHold(driver, settings.torque);
  ProfileCommands commands(profile, config.command.timeout);
  commands.update(driver);
  const RunEnd end = runProfile(
      driver, commands, steps, steps_per_sample, settings.stop,
      [&r](const SimDriver& d) {
        const State& x = d.simulator().state();
        r.max_abs_q1 = std::max(r.max_abs_q1, std::abs(x.q1));
        r.max_abs_q2 = std::max(r.max_abs_q2, std::abs(x.q2));
      },
      [&](const SimDriver& d) {
        r.ledger_error =
            std::max(r.ledger_error, std::abs(d.snapshot().energyBalance() - start_balance));
      });
  r.status = end == RunEnd::kFinished  ? "ok"
             : end == RunEnd::kStopped ? "interrupted"
                                       : "step_refused";
  if (end == RunEnd::kStepRefused) r.error = refusal;
  const Simulator& sim = driver.simulator();
  r.final_state = sim.state();
  r.time = sim.time();
  r.motor_work = sim.motorWork();
  r.dissipated_energy = sim.dissipatedEnergy();
  r.contact_impacts = sim.contactImpacts();
  r.slider_crossings = sim.sliderCrossings();
  r.steps = sim.ticks();
  r.wall_time =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return r;
}

std::vector<SweepResult> runSweep(const YAML::Node& base, const SweepPlan& plan,
                                  const SweepSettings& settings, const SweepSink& sink) {
  const size_t n = plan.cases.size();
  std::vector<SweepResult> results(n);
  std::vector<char> done(n, 0);
  std::atomic<size_t> next{0};
  std::mutex mutex;    // guards done, written and the sink
  size_t written = 0;  // cases 0 .. written - 1 are with the sink
  const auto stopped = [&settings] {
    return settings.stop && settings.stop->load(std::memory_order_relaxed);
  };
  const bool lanes = settings.simd != "off";
  const LaneArch arch = lanes ? parseLaneArch(settings.simd) : LaneArch::kScalar;
  // Cases go to the threads in chunks: a chunk's lane-eligible cases step together.
  const size_t chunk = lanes ? kSweepChunk : 1;
  const SweepCaseConfigs case_configs(base, plan);
  // yaml-cpp nodes share state between copies: each worker clones the base once, alone.
  auto worker = [&](const YAML::Node& own_base) {
    std::vector<SweepResult> own(chunk);
    std::vector<Config> configs(chunk);
    for (size_t begin = chunk * next++; begin < n && !stopped(); begin = chunk * next++) {
      const size_t end = std::min(n, begin + chunk);
      std::vector<const Config*> on_lanes;
      std::vector<SweepResult*> lane_results;
      for (size_t i = begin; i < end; ++i) {
        SweepResult& result = own[i - begin];
        result = SweepResult();
        try {
          configs[i - begin] = case_configs.at(own_base, i);
        } catch (const std::exception& e) {
          result.status = "config_refused";
          result.error = e.what();
          continue;
        }
        if (settings.torque) {
          // A table whose header named a setpoint is no effort mode's torque, and the reverse.
          try {
            settings.torque->checkPlaysAs(configs[i - begin].command.mode != CommandMode::kEffort);
          } catch (const std::invalid_argument& e) {
            result.status = "config_refused";
            result.error = std::string("the torque profile: ") + e.what();
            continue;
          }
        }
        if (lanes && laneEligible(configs[i - begin], settings)) {
          on_lanes.push_back(&configs[i - begin]);
          lane_results.push_back(&result);
        } else {
          result = runSweepCase(configs[i - begin], settings);
        }
      }
      if (!on_lanes.empty()) runSweepLanes(on_lanes, settings, arch, lane_results);
      std::lock_guard<std::mutex> lock(mutex);
      for (size_t i = begin; i < end; ++i) {
        if (own[i - begin].status == "interrupted") continue;  // not finished: no row
        results[i] = std::move(own[i - begin]);
        done[i] = 1;
      }
      // Rows go out in case order as soon as every case before them is finished.
      for (; written < n && done[written]; ++written)
        if (sink) sink(written, results[written]);
    }
  };
  unsigned jobs = settings.jobs ? settings.jobs : coreCount();
  jobs =
      static_cast<unsigned>(std::max<size_t>(1, std::min<size_t>(jobs, (n + chunk - 1) / chunk)));
  std::vector<YAML::Node> bases;
  for (unsigned j = 0; j < jobs; ++j) bases.push_back(YAML::Clone(base));
  // A thread the system would not give (a process or memory limit): the others take its cases
  // from the shared counter, and the user is told.
  runWorkers(
      jobs, [&](unsigned j) { worker(bases[j]); },
      [&](unsigned started, const std::string& why) {
        if (settings.on_warning)
          settings.on_warning("could start only " + std::to_string(started) + " of " +
                              std::to_string(jobs) + " sweep threads (" + why +
                              "); running on those");
      });
  // Interrupted: the finished cases after an unfinished one go out too, still in case order.
  for (size_t i = written; i < n; ++i)
    if (done[i] && sink) sink(i, results[i]);
  for (size_t i = 0; i < n; ++i)
    if (!done[i]) results[i].status = "interrupted";
  return results;
}

}  // namespace kane_sim
