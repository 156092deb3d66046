// Sweep cases on SIMD lanes: the same rows as their single runs (runSweepCase), computed W at a
// time. What runSweepCase books per step (max |q|, crossings) the lanes book; what it books per
// sample (the ledger) the lanes' sample callback books from the same model's energy.
#include "lane_sweep.h"

#include <chrono>
#include <cmath>
#include <map>
#include <utility>

#include "kane_sim/model/generated_mechanism.h"
#include "kane_sim/sim/profile_commands.h"

namespace kane_sim {

std::string whyNotOnLanes(const Config& config) {
  if (config.simulation.integrator != IntegratorType::kRk4) return "simulation.integrator dopri5";
  if (config.simulation.equations != EquationsSource::kGenerated)
    return "simulation.equations generic";
  if (config.command.mode != CommandMode::kEffort)
    return std::string("command.mode ") + commandModeName(config.command.mode);
  if (config.mechanism.contact.enabled) return "contact.enabled";
  if (config.mechanism.motor.no_load_speed > 0.0)
    return "a motor line (command.motor_no_load_speed)";
  if (config.sensors.command_latency != 0.0) return "sensors.command_latency";
  return "";
}

bool laneEligible(const Config& config, const SweepSettings& settings) {
  const long steps = std::lround(settings.duration * config.simulation.physics_rate);
  return whyNotOnLanes(config).empty() && steps <= kMaxLaneSteps;
}

namespace {

// The ledger of each lane: max |(E + D - W)(t) - (E + D - W)(0)| at the samples, as
// runSweepCase's on_sample computes it from the driver's snapshot.
struct Ledgers {
  std::vector<MechanismModel> models;
  std::vector<double> start_balance;
  std::vector<double> error;
};

void bookSample(void* context, std::size_t lane, const LaneState& x) {
  Ledgers& ledgers = *static_cast<Ledgers*>(context);
  const double balance =
      ledgers.models[lane].energy(State{x[0], x[1], x[2], x[3]}).total() + x[5] - x[4];
  ledgers.error[lane] =
      std::max(ledgers.error[lane], std::abs(balance - ledgers.start_balance[lane]));
}

void runGroup(generated::RatesVariant variant, const std::vector<size_t>& members,
              const std::vector<const Config*>& configs, const SweepSettings& settings,
              LaneArch arch, std::vector<SweepResult*>& results) {
  const auto wall_start = std::chrono::steady_clock::now();
  const Config& first = *configs[members.front()];
  const double rate = first.simulation.physics_rate;
  const double step = 1.0 / rate;  // as Simulator's step_size_
  const long steps = std::lround(settings.duration * rate);
  LaneRun run;
  run.step = step;
  run.variant = variant;  // the group's, chosen once per case when grouping
  run.steps_per_sample = std::max(1L, std::lround(rate / settings.ledger_rate));
  run.stop = settings.stop;
  run.vector_trig = settings.vector_trig;
  // Effort mode without a profile holds 0 N m (profileOrHold); a profile's value at t = i h,
  // i h as Simulator::time() computes it, in force during step i.
  const TorqueProfile profile = settings.torque ? *settings.torque : TorqueProfile::constant(0.0);
  run.command.resize(steps);
  for (long i = 0; i < steps; ++i) run.command[i] = profile.at(static_cast<double>(i) * step);
  Ledgers ledgers;
  for (size_t m : members) {
    const Config& c = *configs[m];
    const MechanismModel model = mechanismModel(c);
    run.constants.push_back(GeneratedMechanism(model).constants());
    run.torque_limit.push_back(c.command.torque_limit);
    const State& x0 = c.initial_state;
    run.start.push_back({x0.q1, x0.q2, x0.u1, x0.u2, 0.0, 0.0});
    ledgers.start_balance.push_back(model.energy(x0).total());
    ledgers.models.push_back(model);
  }
  ledgers.error.assign(members.size(), 0.0);
  run.on_sample = bookSample;
  run.sample_context = &ledgers;
  const std::vector<LaneOutcome> outcomes = runLanes(run, arch);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  for (size_t k = 0; k < members.size(); ++k) {
    const LaneOutcome& o = outcomes[k];
    SweepResult& r = *results[members[k]];
    if (o.refused) {  // the single run says why, and where it ended
      r = runSweepCase(*configs[members[k]], settings);
      continue;
    }
    r = SweepResult();
    r.status = o.stopped ? "interrupted" : "ok";
    r.final_state = State{o.state[0], o.state[1], o.state[2], o.state[3]};
    r.time = static_cast<double>(o.steps) * step;
    r.max_abs_q1 = o.max_abs_q1;
    r.max_abs_q2 = o.max_abs_q2;
    r.ledger_error = ledgers.error[k];
    r.motor_work = o.state[4];
    r.dissipated_energy = o.state[5];
    r.slider_crossings = o.slider_crossings;
    r.steps = static_cast<std::uint64_t>(o.steps);
    r.wall_time = wall / static_cast<double>(members.size());  // the lanes share their time
  }
}

}  // namespace

void runSweepLanes(const std::vector<const Config*>& configs, const SweepSettings& settings,
                   LaneArch arch, std::vector<SweepResult*>& results) {
  // One command stream and one equations variant per group.
  std::map<std::pair<double, generated::RatesVariant>, std::vector<size_t>> groups;
  for (size_t i = 0; i < configs.size(); ++i) {
    const auto variant = GeneratedMechanism(mechanismModel(*configs[i])).variant();
    groups[{configs[i]->simulation.physics_rate, variant}].push_back(i);
  }
  for (const auto& group : groups)
    runGroup(group.first.second, group.second, configs, settings, arch, results);
}

}  // namespace kane_sim
