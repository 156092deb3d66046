// Many simulations in one process (`simulate --sweep`, `--sweep-file`): a grid or a list of
// parameter sets over one base config, each case built by the one config loader and run by the
// one driver (SimDriver) that the node and `simulate` use, the cases spread over threads. A
// parameter study or a Monte-Carlo run then costs what its physics costs, not a process and a
// config file per case.
#ifndef KANE_SIM_SIM_SWEEP_H
#define KANE_SIM_SIM_SWEEP_H

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "kane_sim/config/config.h"
#include "kane_sim/config/parameter_schema.h"
#include "kane_sim/model/state.h"
#include "kane_sim/sim/torque_profile.h"

namespace kane_sim {

// The parameter sets: `keys` name config entries as "section.key" (mechanism.spring_stiffness,
// initial_state.q1, damping.crank_joint, ...); each case gives one value per key.
struct SweepPlan {
  std::vector<std::string> keys;
  std::vector<std::vector<double>> cases;
};

// "section.key=start:stop:count" -> count values evenly from start to stop (both included;
// count 1 gives start). Throws std::invalid_argument naming the part that is wrong.
struct SweepAxis {
  std::string key;
  std::vector<double> values;
};
SweepAxis parseSweepAxis(const std::string& spec);

// The grid of several axes: every combination, the last axis varying fastest.
SweepPlan sweepGrid(const std::vector<SweepAxis>& axes);

// A CSV of parameter sets: a header of keys, then one row of numbers per case. Throws
// std::invalid_argument naming the line.
SweepPlan sweepFromCsv(std::istream& in);

// The config of one case: `base` with the case's values set, through loadConfig (so a value the
// loader refuses is refused here, by key). A key the loader does not know is refused too (a
// typo would otherwise sweep nothing). Throws ConfigError.
Config sweepCaseConfig(const YAML::Node& base, const SweepPlan& plan, size_t index);

// Each case's config as sweepCaseConfig gives it, the fast way when it can: when every key is a
// number of the physics or the initial state (takenDirectly) and the base loads, the base is
// loaded once and each case's numbers stored into it by the loader's rules
// (numbers_into_configs.h: the same config, the same refusals; a case's YAML round trip was
// ~40 % of a short case's time). Otherwise sweepCaseConfig on the worker's own base.
class SweepCaseConfigs {
 public:
  SweepCaseConfigs(const YAML::Node& base, const SweepPlan& plan);
  // Throws ConfigError as sweepCaseConfig.
  Config at(const YAML::Node& own_base, size_t index) const;

 private:
  const SweepPlan& plan_;
  bool direct_ = false;
  bool inertia_from_mass_ = false;
  Config base_;
  std::vector<const ParameterSpec*> specs_;
};

// Every key of `plan` is one the loader reads (a typo, or an unknown section, would sweep
// nothing): throws std::invalid_argument naming the first that is not.
void checkSweepKeys(const SweepPlan& plan);

// The most sweep threads: 4 per core (SweepSettings::jobs; more only adds switching).
unsigned maxSweepJobs();

struct SweepSettings {
  double duration = 10.0;  // [s] simulated per case
  // The command stream; none: every case holds its start (profileOrHold: 0 N m, or a servo's
  // initial setpoint), as a single run without a profile does.
  std::optional<TorqueProfile> torque;
  // The ledger E + D - W is checked at this rate [Hz] of sim time (a snapshot each time);
  // max |q| and the final state use every step.
  double ledger_rate = 10.0;
  unsigned jobs = 0;  // threads; 0 = one per core
  // The cases a SIMD lane runs as their single run would (rk4, free motion, effort mode: see
  // src/sim/lane_sweep.h) step W at a time on this instruction set: "auto" (the widest the CPU
  // has), "avx512", "avx2", "sse2", "scalar" (lanes of one double: the single run's bits), or
  // "off" (every case alone, through the driver). runSweep throws std::invalid_argument naming
  // a value that is none of these or an instruction set the CPU lacks.
  std::string simd = "auto";
  // Lanes on xsimd's vector sin and cos instead of the equations' own (model/math_functions.h):
  // no longer the single run's bits, and no faster since those are vector-wide too (batch/lanes.h).
  bool vector_trig = false;
  // Set (from a signal handler, say) to stop: running cases end unfinished, no new one starts.
  const std::atomic<bool>* stop = nullptr;
  std::function<void(const std::string&)> on_warning;  // e.g. fewer threads than asked for
};

struct SweepResult {
  // "ok"; "step_refused" (the rest is up to that step); "config_refused" (nothing ran);
  // "interrupted" (stopped before it finished: no row is written for it)
  std::string status = "config_refused";
  std::string error;  // why, when not ok
  State final_state;
  double time = 0.0;               // [s] simulated
  double max_abs_q1 = 0.0;         // [rad]
  double max_abs_q2 = 0.0;         // [m]
  double ledger_error = 0.0;       // [J] max |(E + D - W)(t) - (E + D - W)(0)| at the samples
  double motor_work = 0.0;         // [J] W
  double dissipated_energy = 0.0;  // [J] D
  std::uint64_t contact_impacts = 0;
  std::uint64_t slider_crossings = 0;
  std::uint64_t steps = 0;
  double wall_time = 0.0;  // [s] this case, on its thread
};

// Runs one case (also what a single `simulate` run of that config would do, step for step).
SweepResult runSweepCase(const Config& config, const SweepSettings& settings);

// Receives each finished case, in case order, as soon as every case before it has finished
// (after a stop, the remaining finished ones, still in order). Called under a lock.
using SweepSink = std::function<void(size_t index, const SweepResult& result)>;

// Runs every case of `plan` over `base`, in parallel; results in case order. If the system gives
// fewer threads than asked for, runs on those (settings.on_warning says so).
std::vector<SweepResult> runSweep(const YAML::Node& base, const SweepPlan& plan,
                                  const SweepSettings& settings, const SweepSink& sink = {});

// The result columns of a sweep row, each named once beside its value; counts print as integers.
// The CSV and the Python module's kane_sim.sweep use this one table.
struct SweepColumn {
  const char* name;
  double (*value)(const SweepResult&);
  bool count;
};
const SweepColumn* sweepColumnsBegin();
const SweepColumn* sweepColumnsEnd();

// One CSV row per case: case, the swept keys, then the result columns. first_case: the number
// of plan's case 0 in the whole sweep (a chunk of it run elsewhere: a cluster's task).
void writeSweepCsvHeader(std::ostream& out, const SweepPlan& plan);
void writeSweepCsvRow(std::ostream& out, const SweepPlan& plan, size_t index,
                      const SweepResult& result, size_t first_case = 0);

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_SWEEP_H
