// Many mechanisms stepped together: SIMD lanes where every lane's config allows them, drivers
// otherwise; either way lane i is what a single SimDriver of configs[i] does.
#include "kane_sim/sim/batch_simulator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "kane_sim/batch/lanes.h"
#include "kane_sim/format_number.h"
#include "kane_sim/model/generated_mechanism.h"
#include "kane_sim/sim/profile_commands.h"
#include "kane_sim/sim/worker_pool.h"
#include "lane_sweep.h"

namespace kane_sim {

namespace {

std::string num(double v) { return formatNumber(v); }
std::string timeText(double t) {  // a tick's time without its rounding's tail: 0.477, not ...04
  char text[32];
  std::snprintf(text, sizeof(text), "%.9g", t);
  return text;
}

// Why the lanes path is not taken for all of `configs`, or "": every lane on it, one rate.
std::string whyDrivers(const std::vector<Config>& configs, const BatchSettings& settings) {
  if (settings.simd == "off") return "simd off";
  for (std::size_t i = 0; i < configs.size(); ++i) {
    const std::string why = whyNotOnLanes(configs[i]);
    if (!why.empty()) return "lane " + std::to_string(i) + ": " + why;
    if (configs[i].sensors.enabled) return "lane " + std::to_string(i) + ": sensors.enabled";
    if (configs[i].simulation.physics_rate != configs[0].simulation.physics_rate)
      return "lanes 0 and " + std::to_string(i) + " differ in simulation.physics_rate";
  }
  return "";
}

}  // namespace

BatchSimulator::BatchSimulator(std::vector<Config> configs, const BatchSettings& settings)
    : configs_(std::move(configs)),
      settings_(settings),
      lanes_(configs_.size()),
      terminated_(configs_.size(), 0) {
  if (configs_.empty()) throw std::invalid_argument("a batch needs at least one mechanism");
  if (settings_.threads < 1)
    throw std::invalid_argument("threads must be 1 or more, got " +
                                std::to_string(settings_.threads));
  checkLaneEnvironment();  // a bad KANE_SIM_SIMD_MAX, whatever `simd` says
  const LaneArch arch =
      settings_.simd == "off" ? LaneArch::kScalar : parseLaneArch(settings_.simd);  // names a typo
  step_size_ = 1.0 / configs_[0].simulation.physics_rate;  // as Simulator's step_size_
  pool_ = std::make_unique<WorkerPool>(static_cast<unsigned>(settings_.threads));
  const std::string why = whyDrivers(configs_, settings_);
  on_lanes_ = why.empty();
  for (const Config& c : configs_) sensors_ = sensors_ || c.sensors.enabled;
  if (!on_lanes_) {
    path_ = "drivers (" + why + ")";
    readings_.resize(size());
    for (std::size_t i = 0; i < size(); ++i) buildDriver(i, configs_[i]);
    return;
  }
  arch_ = arch;
  path_ = std::string(laneArchName(arch_)) + " lanes" +
          (settings_.vector_trig ? " (vector sin/cos)" : "");
  // Each mechanism's constants once: its variant and its lane's numbers.
  std::vector<generated::Constants> constants(size());
  for (std::size_t i = 0; i < size(); ++i)
    constants[i] = GeneratedMechanism(mechanismModel(configs_[i])).constants();
  layoutLanes(constants, std::vector<LaneState>(size()), std::vector<std::uint64_t>(size(), 0));
  std::vector<bool> all(size(), true);
  reset(all);
}

BatchSimulator::~BatchSimulator() = default;

void BatchSimulator::layoutLanes(const std::vector<generated::Constants>& constants,
                                 const std::vector<LaneState>& states,
                                 const std::vector<std::uint64_t>& ticks) {
  // Lanes of one equations variant run together (the single Simulator picks it per config);
  // each variant's lanes are cut into chunks of whole blocks of the width: one with one thread,
  // else four per thread, taken by whichever thread is free (a thread that wakes late leaves its
  // share to the others instead of holding the call up).
  chunks_.clear();
  const std::size_t width = laneWidth(arch_);
  std::vector<generated::RatesVariant> variants(size());
  for (std::size_t i = 0; i < size(); ++i) variants[i] = generated::variantFor(constants[i]);
  for (generated::RatesVariant variant : generated::kRatesVariants) {
    std::vector<std::size_t> members;
    for (std::size_t i = 0; i < size(); ++i)
      if (variants[i] == variant) members.push_back(i);
    if (members.empty()) continue;
    const std::size_t blocks = (members.size() + width - 1) / width;
    const std::size_t pieces =
        settings_.threads == 1 ? 1 : 4 * static_cast<std::size_t>(settings_.threads);
    const std::size_t per_chunk = width * ((blocks + pieces - 1) / pieces);
    for (std::size_t first = 0; first < members.size(); first += per_chunk) {
      Chunk chunk;
      chunk.members.assign(
          members.begin() + static_cast<long>(first),
          members.begin() + static_cast<long>(std::min(first + per_chunk, members.size())));
      LaneRun& run = chunk.run;
      run.variant = variant;
      run.step = step_size_;
      run.vector_trig = settings_.vector_trig;
      run.stop_at_crossing = true;
      run.steps_per_sample = 1L << 40;  // no samples: the state is read after the call
      for (std::size_t i : chunk.members) {
        run.constants.push_back(constants[i]);
        run.torque_limit.push_back(configs_[i].command.torque_limit);
        run.start.push_back(states[i]);
        chunk.ticks.push_back(ticks[i]);
      }
      packLanes(run, arch_);  // laid out once for every call (again when a lane's change)
      run.lane_command.resize(chunk.members.size());
      chunk.outcomes.resize(chunk.members.size());
      for (std::size_t k = 0; k < chunk.members.size(); ++k) {
        lanes_[chunk.members[k]].chunk = chunks_.size();
        lanes_[chunk.members[k]].slot = k;
      }
      chunks_.push_back(std::move(chunk));
    }
  }
}

void BatchSimulator::buildDriver(std::size_t lane, const Config& config) {
  Lane& l = lanes_[lane];
  l.driver = std::make_unique<SimDriver>(config, [this, lane](const SimEvent& e) {
    // What ends a lane: its first refused step, its sliders crossing.
    if (terminated_[lane]) return;
    if (e.kind == SimEvent::Kind::kStepRefused || e.kind == SimEvent::Kind::kFirstSliderCrossing) {
      terminated_[lane] = 1;
      lanes_[lane].reason = "t = " + timeText(e.time) + " s: " + e.message;
    }
  });
  terminated_[lane] = 0;
  l.reason.clear();
  readings_[lane] = l.driver->simulator().joints();
}

template <class F>
void BatchSimulator::parallel(std::size_t count, const F& work) {
  pool_->forEach(count, work);
}

bool BatchSimulator::step(const double* actions, long steps, const std::vector<bool>* active,
                          const std::atomic<bool>* stop, double* states_out) {
  if (steps < 1)
    throw std::invalid_argument("steps must be 1 or more, got " + std::to_string(steps));
  if (active && active->size() != size())
    throw std::invalid_argument("active must hold one flag per lane");
  // Everything is checked before any lane moves.
  for (std::size_t i = 0; i < size(); ++i) {
    if (!std::isfinite(actions[i]))
      throw std::invalid_argument("actions[" + std::to_string(i) + "] = " + num(actions[i]) +
                                  " is not finite");
    if (!on_lanes_ && lanes_[i].driver->servoMode()) {
      const std::string problem = lanes_[i].driver->setpointProblem(actions[i]);
      if (!problem.empty())
        throw std::invalid_argument("actions[" + std::to_string(i) + "]: " + problem);
    }
  }
  active_ = active;
  stop_ = stop;
  if (on_lanes_) {
    for (Chunk& chunk : chunks_) chunk.run.stop = stop;
    parallel(chunks_.size(), [&](std::size_t k) { stepLanes(actions, steps, k, states_out); });
  } else {
    const std::size_t threads = static_cast<std::size_t>(settings_.threads);
    const std::size_t per = (size() + threads - 1) / threads;
    parallel(threads, [&](std::size_t k) {
      stepDrivers(actions, steps, k * per, std::min(size(), (k + 1) * per));
    });
    if (states_out) states(states_out);
  }
  active_ = nullptr;
  stop_ = nullptr;
  return !(stop && stop->load());
}

void BatchSimulator::stepDrivers(const double* actions, long steps, std::size_t begin,
                                 std::size_t end) {
  SensorReading reading;
  for (std::size_t i = begin; i < end; ++i) {
    Lane& l = lanes_[i];
    if (!stepping(i)) continue;
    SimDriver& d = *l.driver;
    // A single Simulator's set_torque(a) then step(steps): the command sent, then re-sent by
    // the held profile whenever command.timeout would otherwise lapse.
    sendCommand(d, actions[i]);
    const TorqueProfile held = TorqueProfile::constant(actions[i]);
    ProfileCommands commands(held, configs_[i].command.timeout);
    commands.update(d);
    for (long s = 0; s < steps && !terminated_[i]; ++s) {
      if (stop_ && stop_->load(std::memory_order_relaxed)) return;
      d.step();
      commands.update(d);
      while (d.takeSensorReading(&reading)) readings_[i] = reading.joints;
    }
  }
}

void BatchSimulator::stepLanes(const double* actions, long steps, std::size_t chunk_index,
                               double* states_out) {
  Chunk& chunk = chunks_[chunk_index];
  LaneRun& run = chunk.run;
  // Running lanes only: a terminated lane keeps its state (it is run, its result dropped).
  for (std::size_t k = 0; k < chunk.members.size(); ++k) {
    const std::size_t i = chunk.members[k];
    run.lane_command[k] = stepping(i) ? actions[i] : 0.0;
  }
  run.held_steps = steps;
  runLanes(run, arch_, chunk.outcomes.data());
  for (std::size_t k = 0; k < chunk.members.size(); ++k) {
    const std::size_t i = chunk.members[k];
    if (!stepping(i)) continue;
    const LaneOutcome& o = chunk.outcomes[k];
    run.start[k] = o.state;
    chunk.ticks[k] += static_cast<std::uint64_t>(o.steps);
    if (!o.refused && o.slider_crossings == 0) continue;  // the common case: no text to make
    Lane& l = lanes_[i];
    const std::string at =
        "t = " + timeText(static_cast<double>(chunk.ticks[k]) * step_size_) + " s: ";
    if (o.refused) {
      terminated_[i] = 1;
      l.reason = at + refusalText(i, fromOdeState(run.start[k]), actions[i]);
    } else if (o.slider_crossings > 0) {
      terminated_[i] = 1;
      l.reason = at + kSliderCrossingReport;
    }
  }
  if (!states_out) return;
  for (std::size_t k = 0; k < chunk.members.size(); ++k) {  // every lane's row, stepped or not
    double* row = states_out + 4 * chunk.members[k];
    const LaneState& x = run.start[k];
    row[0] = x[0], row[1] = x[1], row[2] = x[2], row[3] = x[3];
  }
}

std::string BatchSimulator::refusalText(std::size_t lane, const State& x, double action) const {
  // The lane knows only that a check refused its step: the single run's own step from the same
  // state under the same torque says which, in the drivers path's words (rare: a refusal ends
  // the lane).
  const double torque = std::clamp(action, -configs_[lane].command.torque_limit,
                                   configs_[lane].command.torque_limit);  // as the driver sends it
  Simulator single(configs_[lane]);
  const Status placed = single.setState(x);
  if (placed.ok && single.setTorque(torque).ok) {
    const Status step = single.step();
    if (!step.ok) return step.error;
  }
  // A state whose first rk4 step set_state already judges too fast: the step's own words (a
  // lane is refused where the single run's step is, from the same state).
  if (!placed.ok && placed.error.find("more than 1 rad") != std::string::npos)
    return std::string(Simulator::kCrankTurnRefusal) + " from " + Simulator::stateText(x) +
           " with M_m = " + num(torque) + " N m; step refused, the last good state is kept";
  return "the step was refused (it would go non-finite or beyond 1e100, or turn the crank more "
         "than 1 rad) from " +
         Simulator::stateText(x) + " with M_m = " + num(torque) +
         " N m; the last good state is kept";
}

void BatchSimulator::reset(const std::vector<bool>& mask) {
  for (std::size_t i = 0; i < size(); ++i)
    if (mask[i]) resetLane(i);
}

void BatchSimulator::resetLane(std::size_t i) {
  Lane& l = lanes_[i];
  terminated_[i] = 0;
  l.reason.clear();
  if (l.driver) {
    l.driver->reset();
    readings_[i] = l.driver->simulator().joints();
  } else {
    const State& x0 = configs_[i].initial_state;
    laneState(i) = {x0.q1, x0.q2, x0.u1, x0.u2, 0.0, 0.0};
  }
}

Status BatchSimulator::checkState(std::size_t i, const State& x) const {
  const Lane& l = lanes_[i];
  // The lanes path has no Simulator of its own: one of the lane's config checks the state.
  const Status status =
      l.driver ? l.driver->simulator().checkState(x) : Simulator(configs_[i]).checkState(x);
  if (!status.ok) return {false, status.error + "; state kept"};
  return {};
}

Status BatchSimulator::setState(std::size_t i, const State& x) {
  Lane& l = lanes_[i];
  if (l.driver) {
    const Status status = l.driver->setState(x);
    if (!status.ok) return status;
    readings_[i] = l.driver->simulator().joints();
  } else {
    const Status status = checkState(i, x);
    if (!status.ok) return status;
    laneState(i) = {x.q1, x.q2, x.u1, x.u2, 0.0, 0.0};
  }
  terminated_[i] = 0;
  l.reason.clear();
  return {};
}

void BatchSimulator::reseed(const std::vector<bool>& mask,
                            const std::vector<std::uint64_t>& seeds) {
  for (std::size_t i = 0; i < size(); ++i) {
    if (!mask[i]) continue;
    configs_[i].sensors.seed = static_cast<int>(seeds[i]);  // Python keeps it <= 2^31 - 1
    if (on_lanes_) {  // no sensors on lanes: a fresh start, its clock at 0
      laneTicks(i) = 0;
      resetLane(i);
    } else {
      buildDriver(i, configs_[i]);
    }
  }
}

void BatchSimulator::reconfigure(const std::vector<std::size_t>& lanes,
                                 const std::vector<Config>& configs,
                                 const std::vector<State>* starts) {
  if (lanes.size() != configs.size() || (starts && starts->size() != lanes.size()))
    throw std::invalid_argument("reconfigure: one config (and start) per mechanism named");
  // Everything is checked before any mechanism changes.
  for (std::size_t k = 0; k < lanes.size(); ++k) {
    const std::size_t i = lanes[k];
    if (i >= size())
      throw std::invalid_argument("mechanism " + std::to_string(i) + " is not one of the " +
                                  std::to_string(size()));
    if (starts) {  // judged by the new config, as a Simulator of it would
      const Status placed = Simulator(configs[k]).checkState((*starts)[k]);
      if (!placed.ok)
        throw std::invalid_argument("mechanism " + std::to_string(i) + ": " + placed.error +
                                    "; nothing changed");
    }
    if (!on_lanes_) continue;
    std::string why = whyNotOnLanes(configs[k]);
    if (why.empty() && configs[k].sensors.enabled) why = "sensors.enabled";
    if (why.empty() && configs[k].simulation.physics_rate != configs_[0].simulation.physics_rate)
      why = "simulation.physics_rate " + num(configs[k].simulation.physics_rate) + " is not the " +
            "batch's " + num(configs_[0].simulation.physics_rate);
    if (!why.empty())
      throw std::invalid_argument("mechanism " + std::to_string(i) + ": " + why +
                                  " would take it off the batch's " + path_ +
                                  ": build the batch with it (or with simd=\"off\") to change it");
  }
  if (!on_lanes_) {
    for (std::size_t k = 0; k < lanes.size(); ++k) {
      configs_[lanes[k]] = configs[k];
      sensors_ = sensors_ || configs[k].sensors.enabled;
      buildDriver(lanes[k], configs_[lanes[k]]);
      if (starts) static_cast<void>(setState(lanes[k], (*starts)[k]));  // checked above
    }
    return;
  }
  // A mechanism whose variant stays is rewritten in its slot (its chunk laid out again); one
  // whose variant changes moves to the chunks of its new variant: every lane is laid out again.
  bool moved = false;
  std::vector<std::size_t> touched;
  std::vector<std::pair<std::size_t, generated::Constants>> changed;
  for (std::size_t k = 0; k < lanes.size(); ++k) {
    const std::size_t i = lanes[k];
    configs_[i] = configs[k];
    const generated::Constants c = GeneratedMechanism(mechanismModel(configs_[i])).constants();
    Chunk& chunk = chunks_[lanes_[i].chunk];
    if (generated::variantFor(c) != chunk.run.variant) moved = true;
    changed.emplace_back(i, c);
    if (moved) continue;
    chunk.run.constants[lanes_[i].slot] = c;
    chunk.run.torque_limit[lanes_[i].slot] = configs_[i].command.torque_limit;
    touched.push_back(lanes_[i].chunk);
  }
  if (moved) {
    std::vector<generated::Constants> constants(size());
    std::vector<LaneState> states(size());
    std::vector<std::uint64_t> ticks(size());
    for (std::size_t i = 0; i < size(); ++i) {
      constants[i] = chunks_[lanes_[i].chunk].run.constants[lanes_[i].slot];
      states[i] = laneState(i);
      ticks[i] = laneTicks(i);
    }
    for (const auto& [i, c] : changed) constants[i] = c;
    layoutLanes(constants, states, ticks);
  } else {
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    for (std::size_t chunk : touched) packLanes(chunks_[chunk].run, arch_);
  }
  for (std::size_t k = 0; k < lanes.size(); ++k) {
    laneTicks(lanes[k]) = 0;
    resetLane(lanes[k]);
    if (starts) static_cast<void>(setState(lanes[k], (*starts)[k]));  // checked above
  }
}

State BatchSimulator::state(std::size_t lane) const {
  const Lane& l = lanes_[lane];
  return l.driver ? l.driver->simulator().state() : fromOdeState(laneState(lane));
}

void BatchSimulator::states(double* out) const {
  const auto put = [out](std::size_t lane, const State& x) {
    double* row = out + 4 * lane;
    row[0] = x.q1, row[1] = x.q2, row[2] = x.u1, row[3] = x.u2;
  };
  if (!on_lanes_) {
    for (std::size_t i = 0; i < size(); ++i) put(i, lanes_[i].driver->simulator().state());
    return;
  }
  for (const Chunk& chunk : chunks_)
    for (std::size_t k = 0; k < chunk.members.size(); ++k)
      put(chunk.members[k], fromOdeState(chunk.run.start[k]));
}

double BatchSimulator::time(std::size_t lane) const {
  const Lane& l = lanes_[lane];
  return l.driver ? l.driver->time() : static_cast<double>(laneTicks(lane)) * step_size_;
}

}  // namespace kane_sim
