// `simulate`: runs the mechanism offline (no ROS master) and writes a CSV and/or a bag.
//
// Exit codes: 0 ok, 1 bad config, 2 bad command line, 3 the simulation refused a step (a sweep:
// a case was not ok), 4 the output could not be written, 5 an unexpected internal failure,
// 6 --replay differs from the bag beyond --tolerance (or cannot replay it),
// 130 / 143 interrupted by SIGINT / SIGTERM (what was simulated until then is written).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "kane_sim/cli/progress.h"
#include "kane_sim/cli/simulate_options.h"
#include "kane_sim/config/input_file.h"
#include "kane_sim/config/load_config.h"
#include "kane_sim/design/plan_file.h"
#include "kane_sim/format_number.h"
#include "kane_sim/sim/config_check.h"
#include "kane_sim/sim/csv_format.h"
#include "kane_sim/sim/output_grid.h"
#include "kane_sim/sim/profile_commands.h"
#include "kane_sim/sim/sim_driver.h"
#include "kane_sim/sim/sweep.h"
#include "kane_sim/sim/torque_profile.h"
#include "simulate/bag_module.h"
#include "simulate/outputs.h"

using kane_sim::ConfigError;
using kane_sim::cli::CsvOutput;
using kane_sim::cli::describeOptions;
using kane_sim::cli::num;
using kane_sim::cli::Options;
using kane_sim::cli::OutputError;
using kane_sim::cli::parseOptions;
using kane_sim::cli::UsageError;
using simulate::Outputs;

namespace {

constexpr int kExitConfig = 1;
constexpr int kExitUsage = 2;
constexpr int kExitStepRefused = 3;
constexpr int kExitOutput = 4;
constexpr int kExitInternal = 5;       // a bug: please report the message
constexpr int kExitReplayDiffers = 6;  // --replay: the states differ beyond --tolerance
constexpr int kExitSignalBase = 128;   // + the signal's number, as a shell reports it

// Set by SIGINT / SIGTERM: the run stops at the next row, writes what it has and exits
// 128 + the signal. (A lock-free atomic store is async-signal-safe.)
std::atomic<bool> g_stop{false};
std::atomic<int> g_signal{0};
static_assert(std::atomic<bool>::is_always_lock_free, "stored from a signal handler");
extern "C" void onStopSignal(int signal) {
  g_signal.store(signal);
  g_stop.store(true);
}

// Sweep mode: every case through the library's runSweep, one row each, in case order.
int runSweepMode(const Options& options, const YAML::Node& base) {
  const kane_sim::SweepPlan plan = kane_sim::cli::sweepPlan(options);
  kane_sim::SweepSettings settings;
  settings.duration = options.duration;
  if (options.profile_given) settings.torque = options.profile;
  settings.jobs = options.jobs;
  settings.simd = options.simd;
  settings.vector_trig = options.vector_trig;
  settings.stop = &g_stop;
  settings.on_warning = [](const std::string& text) { std::cerr << "warning: " << text << "\n"; };
  CsvOutput csv(options.csv_path);
  std::ostream* out = &csv.stream();
  kane_sim::writeSweepCsvHeader(*out, plan);
  std::uint64_t steps = 0;
  size_t failed = 0, written = 0;
  bool write_failed = false;
  kane_sim::cli::Progress progress("sweep", static_cast<double>(plan.cases.size()), "cases");
  // Each row as its case finishes (in case order), flushed: a crash keeps them in FILE.partial.
  const auto sink = [&](size_t i, const kane_sim::SweepResult& r) {
    kane_sim::writeSweepCsvRow(*out, plan, i, r);
    out->flush();  // a crash keeps the finished rows
    write_failed = write_failed || !*out;
    ++written;
    steps += r.steps;
    if (r.status != "ok" && failed++ < 5) {
      progress.clear();
      std::cerr << "warning: case " << i << ": " << r.error << "\n";
    }
    progress.update(static_cast<double>(written));
  };
  const auto wall_start = std::chrono::steady_clock::now();
  kane_sim::runSweep(base, plan, settings, sink);
  progress.finish();
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  if (write_failed) throw OutputError("writing the CSV failed (disk full?)");
  csv.finish();
  std::cerr << "swept " << written << " of " << plan.cases.size() << " cases (" << failed
            << " not ok) of " << options.duration << " s each, torque "
            << options.profile->describe() << ": " << steps << " physics steps, wall time " << wall
            << " s, " << (wall > 0 ? written / wall : 0.0) << " cases/s, "
            << (wall > 0 ? steps / wall : 0.0) << " steps/s\n";
  if (g_stop) {
    std::cerr << "interrupted: kept the " << written << " finished cases\n";
    return kExitSignalBase + g_signal.load();
  }
  return failed ? kExitStepRefused : 0;
}

int runReplay(const Options& options, const kane_sim::Config& config) {
  simulate::ReplayResult r;
  try {
    r = simulate::bagModule().replay(options.replay_bag, config, &g_stop);
  } catch (const simulate::ReplayError& e) {
    std::cerr << "error: --replay: " << e.what() << "\n";
    return kExitReplayDiffers;
  }
  if (!r.checkpoint_topic.empty()) {
    std::cout << "started at the checkpoint of tick " << r.start_tick << " on "
              << r.checkpoint_topic << " (its config), re-synchronised at " << r.resynchronised
              << " later ones"
              << (r.checkpoints_passed_over > 0
                      ? " (passed over " + std::to_string(r.checkpoints_passed_over) +
                            " earlier ones: inputs after them were not recorded)"
                      : std::string())
              << "\n";
    if (!options.default_config)
      std::cerr << "note: the bag's checkpoints carry the node's config; --config "
                << options.config_path << " is not used\n";
  }
  if (r.interrupted) {
    std::cerr << "interrupted at t = " << kane_sim::formatTime(r.interrupted_at) << " s: compared "
              << r.compared << " states of " << r.state_topic << " up to there, largest difference "
              << num(r.largest) << "\n";
    return kExitSignalBase + g_signal.load();
  }
  std::cout << "replayed " << r.inputs << " inputs of " << r.input_topic << "; compared "
            << r.compared << " states of " << r.state_topic << " (" << r.skipped
            << " skipped at a reset or set_state"
            << (r.uncompared > 0 ? ", " + std::to_string(r.uncompared) + " not compared: gaps"
                                 : std::string())
            << "); largest difference " << num(r.largest);
  if (r.largest > 0)
    std::cout << " (" << r.largest_of << " at t = " << kane_sim::formatTime(r.largest_at) << " s)";
  std::cout << "\n";
  if (r.inputs_after_last_state > 0)
    std::cerr << "note: " << r.inputs_after_last_state << " inputs arrived after the bag's last "
              << "state and were not replayed (nothing to compare them with)\n";
  if (r.parameter_changes > 0 && r.checkpoint_topic.empty())
    std::cerr << "warning: the bag's run was reconfigured " << r.parameter_changes
              << " times at run time; the replay runs the config as given\n";
  for (const std::string& gap : r.gaps)
    std::cerr << (options.replay_accept_gaps ? "warning" : "error") << ": --replay: " << gap
              << "\n";
  if (r.compared == 0) {
    std::cerr << "error: --replay: no state to compare\n";
    return kExitReplayDiffers;
  }
  if (!r.gaps.empty() && !options.replay_accept_gaps) {
    std::cerr << "error: --replay: " << r.uncompared << " of the bag's states were not compared "
              << "(inputs missing); --accept-gaps takes the comparison as it is\n";
    return kExitReplayDiffers;
  }
  return r.largest <= options.replay_tolerance ? 0 : kExitReplayDiffers;
}

int run(const Options& options) {
  // --integrator goes into the tree before validation, so the stability check judges the
  // integrator that will run.
  YAML::Node root = kane_sim::loadYamlFile(options.config_path);
  if (!options.integrator.empty() && root.IsMap())
    kane_sim::setConfigValue(root, "simulation", "integrator", YAML::Node(options.integrator));
  if (options.default_config)
    std::cerr << "no --config given: using the package's default " << options.config_path << "\n";
  kane_sim::LoadedConfig loaded = kane_sim::loadSimulationConfig(root);
  for (const std::string& warning : loaded.warnings) std::cerr << "warning: " << warning << "\n";
  if (options.sweep()) return runSweepMode(options, root);
  const kane_sim::Config& config = loaded.config;
  if (!options.replay_bag.empty()) return runReplay(options, config);
  // A plan of `design plan` plays its torques on the mechanism it was designed for, from its start.
  if (!options.torque_csv.empty() && kane_sim::isPlanCsv(options.torque_csv)) {
    std::string mismatch;
    try {
      mismatch = kane_sim::planMismatch(kane_sim::readPlanCsv(options.torque_csv), config);
    } catch (const kane_sim::PlanError& e) {
      throw UsageError(std::string("--torque-csv: ") + e.what());
    }
    if (!mismatch.empty())
      throw UsageError("--torque-csv " + options.torque_csv +
                       " is a plan for another mechanism or "
                       "start than --config " +
                       options.config_path + ": " + mismatch +
                       " (design the plan for this config, or play a t,torque CSV)");
  }

  // The table's header says what its values are; the config's mode, what they drive.
  if (!options.torque_csv.empty() && !kane_sim::isPlanCsv(options.torque_csv) && options.profile) {
    try {
      options.profile->checkPlaysAs(config.command.mode != kane_sim::CommandMode::kEffort);
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--torque-csv in command.mode ") +
                           kane_sim::commandModeName(config.command.mode) + ": " + e.what(),
                       false);
    }
  }

  kane_sim::OutputGrid grid;
  try {
    grid = kane_sim::outputGrid(config.simulation.physics_rate, options.duration,
                                options.output_rate, "--duration", "--output-rate");
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }

  // The same driver as the node: the profile is a stream of commands, clamped alike; each
  // kind of event is printed once.
  std::set<kane_sim::SimEvent::Kind> reported;
  kane_sim::cli::Progress progress("simulate", options.duration, "s");
  kane_sim::SimDriver driver(config, [&reported, &progress](const kane_sim::SimEvent& event) {
    if (event.kind == kane_sim::SimEvent::Kind::kStepRefused) {
      progress.clear();
      std::cerr << "error: " << event.message << "\n";
    } else if (reported.insert(event.kind).second) {
      progress.clear();
      std::cerr << "warning: " << event.message << " (at t = " << kane_sim::formatTime(event.time)
                << " s)\n";
    }
  });

  Outputs out(options, config);
  // Every input on the bag's input log, as the node logs them: identify then knows the torque
  // (or the servo's setpoint) between the readings.
  driver.setInputHandler(
      [&out, &driver](const kane_sim::DriverInput& input) { out.logInput(input, driver.time()); });
  const auto wall_start = std::chrono::steady_clock::now();
  // A servo (command.mode velocity | position) takes the profile as its setpoint; without one it
  // holds its initial setpoint (the starting angle, or standing still), as every sweep case does.
  const kane_sim::TorqueProfile profile =
      kane_sim::profileOrHold(driver, options.profile_given ? options.profile : std::nullopt);
  const std::string unit = config.command.mode == kane_sim::CommandMode::kPosition   ? "rad"
                           : config.command.mode == kane_sim::CommandMode::kVelocity ? "rad/s"
                                                                                     : "N m";
  if (driver.servoMode())
    std::cerr << "command.mode " << kane_sim::commandModeName(config.command.mode)
              << ": the profile's values are the servo's setpoint [" << unit << "]\n";
  const bool sensors = driver.sensorsEnabled();
  long outputs = 0;
  const kane_sim::RunEnd end = kane_sim::runOnGrid(
      driver, profile, grid, &g_stop,
      [&](const kane_sim::SimDriver&) {
        if (sensors) out.writeDueSensorReadings(driver);
      },
      [&](const kane_sim::SimDriver& d) {
        out.write(d.snapshot());
        ++outputs;
        progress.update(d.time());
      });
  progress.finish();
  if (end != kane_sim::RunEnd::kFinished) {
    out.finish();  // what was simulated up to the refusal or the signal stays readable
    if (end == kane_sim::RunEnd::kStepRefused) return kExitStepRefused;
    std::cerr << "interrupted at t = " << kane_sim::formatTime(driver.time()) << " s: kept the "
              << outputs << " outputs simulated until then\n";
    return kExitSignalBase + g_signal.load();
  }
  out.finish();
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  std::cerr << "simulated " << driver.time() << " s in " << driver.ticks() << " physics steps ("
            << kane_sim::integratorName(config.simulation.integrator) << " at "
            << config.simulation.physics_rate << " Hz on the "
            << kane_sim::equationsName(config.simulation.equations) << " equations, "
            << (driver.servoMode() ? "setpoint " : "torque ") << profile.describe(unit) << "), "
            << grid.rows + 1 << " outputs, wall time " << wall << " s, "
            << (wall > 0 ? static_cast<double>(driver.ticks()) / wall : 0.0) << " steps/s\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // Past a file-size limit (ulimit -f) a write should fail (exit 4), not kill the process.
  std::signal(SIGXFSZ, SIG_IGN);
  std::signal(SIGINT, onStopSignal);
  std::signal(SIGTERM, onStopSignal);
  Options options;
  try {
    if (!parseOptions(argc, argv, &options)) return 0;
    return run(options);
  } catch (const UsageError& e) {
    std::cerr << "error: " << e.what() << "\n";
    if (e.show_usage) std::cerr << "\n" << describeOptions() << "\n";
    return kExitUsage;
  } catch (const OutputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitOutput;
  } catch (const ConfigError& e) {
    std::cerr << "error: " << options.config_path << ": " << e.what() << "\n";
    return kExitConfig;
  } catch (const std::exception& e) {  // nothing above should let one through; never abort
    std::cerr << "error: unexpected failure: " << e.what() << "\n";
    return kExitInternal;
  }
}
