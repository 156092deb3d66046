#include "kane_sim/sim/sweep.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <thread>

#include "kane_sim/config/load_config.h"
#include "kane_sim/sim/csv_format.h"
#include "kane_sim/sim/profile_commands.h"
#include "kane_sim/sim/sim_driver.h"

namespace kane_sim {
namespace {

double parseNumber(const std::string& text, const std::string& what) {
  try {
    size_t used = 0;
    const double value = std::stod(text, &used);
    if (used == text.size() && std::isfinite(value)) return value;
  } catch (const std::exception&) {
  }
  throw std::invalid_argument(what + ": '" + text + "' is not a finite number");
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::istringstream in(text);
  std::string part;
  while (std::getline(in, part, separator)) parts.push_back(part);
  if (!text.empty() && text.back() == separator) parts.emplace_back();
  return parts;
}

std::string trim(const std::string& s) {
  const size_t begin = s.find_first_not_of(" \t\r");
  const size_t end = s.find_last_not_of(" \t\r");
  return begin == std::string::npos ? "" : s.substr(begin, end - begin + 1);
}

bool isName(const std::string& part) {
  return !part.empty() && std::all_of(part.begin(), part.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
}

void requireKey(const std::string& key) {
  const std::vector<std::string> parts = split(key, '.');
  if (parts.size() != 2 || !isName(parts[0]) || !isName(parts[1]))
    throw std::invalid_argument(
        "sweep key '" + key +
        "' must be section.key as in the config file, of letters, digits and '_' (e.g. "
        "mechanism.spring_stiffness; a cell starting with =, +, - or @ would be a spreadsheet "
        "formula)");
}

// The key, or its whole section, was not read by the loader.
bool isUnknown(const LoadedConfig& loaded, const std::string& key) {
  const std::string section = key.substr(0, key.find('.'));
  for (const std::string& unknown : loaded.unknown_keys)
    if (unknown == key || unknown == section) return true;
  return false;
}

// At most this many cases: a grid typo (count 1e9) should be an error, not an out-of-memory.
constexpr double kMaxCases = 1e7;

}  // namespace

SweepAxis parseSweepAxis(const std::string& spec) {
  const size_t equals = spec.find('=');
  if (equals == std::string::npos)
    throw std::invalid_argument("--sweep '" + spec + "' must be KEY=START:STOP:COUNT");
  SweepAxis axis;
  axis.key = trim(spec.substr(0, equals));
  requireKey(axis.key);
  const std::vector<std::string> range = split(spec.substr(equals + 1), ':');
  if (range.size() != 3)
    throw std::invalid_argument("--sweep '" + spec + "': the range must be START:STOP:COUNT");
  const double start = parseNumber(range[0], "--sweep " + axis.key + " START");
  const double stop = parseNumber(range[1], "--sweep " + axis.key + " STOP");
  const double count = parseNumber(range[2], "--sweep " + axis.key + " COUNT");
  if (!(count >= 1 && count <= kMaxCases && count == std::floor(count)))
    throw std::invalid_argument("--sweep " + axis.key + " COUNT must be a whole number in [1, " +
                                std::to_string(static_cast<long>(kMaxCases)) + "], got '" +
                                range[2] + "'");
  const long n = static_cast<long>(count);
  // start (1 - t) + stop t: no stop - start, which overflows for -1e308:1e308; t = 1 gives stop.
  for (long i = 0; i < n; ++i) {
    const double t = n == 1 ? 0.0 : static_cast<double>(i) / static_cast<double>(n - 1);
    axis.values.push_back(start * (1.0 - t) + stop * t);
  }
  return axis;
}

SweepPlan sweepGrid(const std::vector<SweepAxis>& axes) {
  SweepPlan plan;
  double total = 1;
  for (const SweepAxis& axis : axes) {
    if (std::find(plan.keys.begin(), plan.keys.end(), axis.key) != plan.keys.end())
      throw std::invalid_argument("--sweep names " + axis.key + " twice");
    plan.keys.push_back(axis.key);
    total *= static_cast<double>(axis.values.size());
  }
  if (axes.empty() || total > kMaxCases)
    throw std::invalid_argument("a sweep needs 1 to " +
                                std::to_string(static_cast<long>(kMaxCases)) +
                                " cases, the grid has " + std::to_string(total));
  std::vector<size_t> at(axes.size(), 0);
  for (long c = 0; c < static_cast<long>(total); ++c) {
    std::vector<double> values;
    for (size_t a = 0; a < axes.size(); ++a) values.push_back(axes[a].values[at[a]]);
    plan.cases.push_back(std::move(values));
    for (size_t a = axes.size(); a-- > 0;) {  // the last axis varies fastest
      if (++at[a] < axes[a].values.size()) break;
      at[a] = 0;
    }
  }
  return plan;
}

SweepPlan sweepFromCsv(std::istream& in) {
  SweepPlan plan;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    // A UTF-8 byte-order mark (spreadsheets write one) is not part of the first key.
    if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line = line.substr(3);
    line = trim(line);
    if (line.empty() || line[0] == '#') continue;
    const std::vector<std::string> fields = split(line, ',');
    if (plan.keys.empty()) {
      for (const std::string& field : fields) {
        plan.keys.push_back(trim(field));
        requireKey(plan.keys.back());
        if (std::count(plan.keys.begin(), plan.keys.end(), plan.keys.back()) > 1)
          throw std::invalid_argument("line 1: " + plan.keys.back() + " appears twice");
      }
      continue;
    }
    if (fields.size() != plan.keys.size())
      throw std::invalid_argument("line " + std::to_string(number) + " has " +
                                  std::to_string(fields.size()) + " values for " +
                                  std::to_string(plan.keys.size()) + " keys");
    std::vector<double> values;
    for (size_t i = 0; i < fields.size(); ++i)
      values.push_back(
          parseNumber(trim(fields[i]), "line " + std::to_string(number) + ", " + plan.keys[i]));
    plan.cases.push_back(std::move(values));
    if (plan.cases.size() > kMaxCases) throw std::invalid_argument("more cases than a sweep takes");
  }
  if (plan.keys.empty() || plan.cases.empty())
    throw std::invalid_argument("needs a header of keys and at least one row of values");
  return plan;
}

namespace {

// `base` with the case's values set; ConfigError when a key's section is not a map.
YAML::Node caseTree(const YAML::Node& base, const SweepPlan& plan, size_t index) {
  YAML::Node root = YAML::Clone(base);
  for (size_t k = 0; k < plan.keys.size(); ++k) {
    const std::vector<std::string> parts = split(plan.keys[k], '.');
    if (!root[parts[0]] || root[parts[0]].IsNull())
      root[parts[0]] = YAML::Node(YAML::NodeType::Map);
    if (!root[parts[0]].IsMap())
      throw ConfigError(plan.keys[k], "cannot be set: '" + parts[0] + "' is not a section");
    root[parts[0]][parts[1]] = plan.cases[index][k];
  }
  return root;
}

}  // namespace

Config sweepCaseConfig(const YAML::Node& base, const SweepPlan& plan, size_t index) {
  const LoadedConfig loaded = loadConfig(caseTree(base, plan, index));
  for (const std::string& key : plan.keys)
    if (isUnknown(loaded, key))
      throw ConfigError(key, "is not a config key the simulation reads (a typo?)");
  return loaded.config;
}

void checkSweepKeys(const YAML::Node& base, const SweepPlan& plan) {
  for (size_t k = 0; k < plan.keys.size(); ++k) {
    // One key at a time at its first value. A ConfigError means the loader read the key (it
    // refused its value, or the tree): unknown keys are never errors, only reported, so a load
    // that passes tells whether the key is one it reads.
    const SweepPlan one{{plan.keys[k]}, {{plan.cases.front()[k]}}};
    bool unknown = false;
    try {
      unknown = isUnknown(loadConfig(caseTree(base, one, 0)), plan.keys[k]);
    } catch (const ConfigError&) {
    }
    if (unknown)
      throw std::invalid_argument("sweep key '" + plan.keys[k] +
                                  "' is not a config key the simulation reads (a typo?)");
  }
}

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
  r.status = "ok";
  ProfileCommands commands(settings.torque, config.command.timeout);
  commands.update(driver);
  for (long i = 1; i <= steps; ++i) {
    if (settings.stop && settings.stop->load(std::memory_order_relaxed)) {
      r.status = "interrupted";
      break;
    }
    if (!driver.step()) {
      r.status = "step_refused";
      r.error = refusal;
      break;
    }
    commands.update(driver);
    const State& x = driver.simulator().state();
    r.max_abs_q1 = std::max(r.max_abs_q1, std::abs(x.q1));
    r.max_abs_q2 = std::max(r.max_abs_q2, std::abs(x.q2));
    if (i % steps_per_sample == 0 || i == steps)
      r.ledger_error =
          std::max(r.ledger_error, std::abs(driver.snapshot().energyBalance() - start_balance));
  }
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
  // yaml-cpp nodes share state between copies: each worker clones the base once, alone.
  auto worker = [&](const YAML::Node& own_base) {
    for (size_t i = next++; i < n && !stopped(); i = next++) {
      SweepResult result;
      try {
        result = runSweepCase(sweepCaseConfig(own_base, plan, i), settings);
      } catch (const std::exception& e) {
        result.status = "config_refused";
        result.error = e.what();
      }
      if (result.status == "interrupted") continue;  // not finished: no row
      std::lock_guard<std::mutex> lock(mutex);
      results[i] = std::move(result);
      done[i] = 1;
      // Rows go out in case order as soon as every case before them is finished.
      for (; written < n && done[written]; ++written)
        if (sink) sink(written, results[written]);
    }
  };
  unsigned jobs = settings.jobs ? settings.jobs : std::max(1u, std::thread::hardware_concurrency());
  jobs = static_cast<unsigned>(std::min<size_t>(jobs, n));
  std::vector<YAML::Node> bases;
  for (unsigned j = 0; j < jobs; ++j) bases.push_back(YAML::Clone(base));
  std::vector<std::thread> threads;
  for (unsigned j = 1; j < jobs; ++j) {
    try {
      threads.emplace_back(worker, bases[j]);
    } catch (const std::system_error& e) {
      // The system would not give more threads (a process or memory limit): run on those there
      // are, and say so.
      if (settings.on_warning)
        settings.on_warning("could start only " + std::to_string(j) + " of " +
                            std::to_string(jobs) + " sweep threads (" + e.what() +
                            "); running on those");
      break;
    }
  }
  worker(bases[0]);
  for (std::thread& t : threads) t.join();
  // Interrupted: the finished cases after an unfinished one go out too, still in case order.
  for (size_t i = written; i < n; ++i)
    if (done[i] && sink) sink(i, results[i]);
  for (size_t i = 0; i < n; ++i)
    if (!done[i]) results[i].status = "interrupted";
  return results;
}

void writeSweepCsvHeader(std::ostream& out, const SweepPlan& plan) {
  out << "case";
  for (const std::string& key : plan.keys) out << ',' << key;
  out << ",status,t,q1,q2,u1,u2,max_abs_q1,max_abs_q2,ledger_error,motor_work,dissipated_energy,"
         "contact_impacts,slider_crossings,steps,wall_time\n";
}

void writeSweepCsvRow(std::ostream& out, const SweepPlan& plan, size_t index,
                      const SweepResult& r) {
  out << index;
  for (double v : plan.cases[index]) {
    out << ',';
    writeCsvNumber(out, v);
  }
  out << ',' << r.status;
  if (r.status == "config_refused") {     // nothing ran: empty fields, not zeros that read as data
    out << std::string(14, ',') << '\n';  // the 14 result columns
    return;
  }
  for (double v : {r.time, r.final_state.q1, r.final_state.q2, r.final_state.u1, r.final_state.u2,
                   r.max_abs_q1, r.max_abs_q2, r.ledger_error, r.motor_work, r.dissipated_energy}) {
    out << ',';
    writeCsvNumber(out, v);
  }
  out << ',' << r.contact_impacts << ',' << r.slider_crossings << ',' << r.steps << ',';
  writeCsvNumber(out, r.wall_time);
  out << '\n';
}

}  // namespace kane_sim
