// `simulate`: runs the mechanism offline (no ROS master) and writes a CSV and/or a bag.
//
// Exit codes: 0 ok, 1 bad config, 2 bad command line, 3 the simulation refused a step (a sweep:
// a case was not ok), 4 the output could not be written, 5 an unexpected internal failure,
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

#include <boost/program_options.hpp>

#include "kane_sim/config/load_config.h"
#include "kane_sim/ros/bag_writer.h"
#include "kane_sim/sim/csv_format.h"
#include "kane_sim/sim/profile_commands.h"
#include "kane_sim/sim/sim_driver.h"
#include "kane_sim/sim/sweep.h"
#include "kane_sim/sim/torque_profile.h"

namespace po = boost::program_options;
using kane_sim::ConfigError;

namespace {

constexpr int kExitConfig = 1;
constexpr int kExitUsage = 2;
constexpr int kExitStepRefused = 3;
constexpr int kExitOutput = 4;
constexpr int kExitInternal = 5;      // a bug: please report the message
constexpr int kExitSignalBase = 128;  // + the signal's number, as a shell reports it
constexpr double kMaxDuration = 1e7;  // [s] ~4 months of sim time; beyond that is a typo
// More physics steps than this between two rows is no output grid (and would overflow a long).
constexpr double kMaxStepsPerRow = 1e12;

// Set by SIGINT / SIGTERM: the run stops at the next row, writes what it has and exits
// 128 + the signal. (A lock-free atomic store is async-signal-safe.)
std::atomic<bool> g_stop{false};
std::atomic<int> g_signal{0};
static_assert(std::atomic<bool>::is_always_lock_free, "stored from a signal handler");
extern "C" void onStopSignal(int signal) {
  g_signal.store(signal);
  g_stop.store(true);
}

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};
struct OutputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Options {
  std::string config_path;
  double duration = 0.0;
  double output_rate = 100.0;
  std::optional<kane_sim::TorqueProfile> profile;  // resolved after parsing
  std::string integrator;                          // empty: the config's
  std::string csv_path;                            // empty: stdout (unless only a bag is asked for)
  std::string bag_path;
  // Sweep mode: many cases, one summary row each (kane_sim/sim/sweep.h).
  std::vector<std::string> sweep_axes;  // --sweep KEY=START:STOP:COUNT, repeatable (a grid)
  std::string sweep_file;               // --sweep-file CSV of parameter sets
  unsigned jobs = 0;                    // --jobs, 0 = one per core
  bool default_config = false;          // no --config: the package's config/mechanism.yaml
  bool sweep() const { return !sweep_axes.empty() || !sweep_file.empty(); }
};

po::options_description describeOptions() {
  po::options_description desc(
      "Usage: simulate [--config FILE] --duration SECONDS [options]\n\n"
      "Simulates the textbook example's mechanism (Kane equations - Example 1) offline (no ROS "
      "master). Writes a CSV with the\n"
      "header t,q1,q2,u1,u2,energy,... (rows every 1/output-rate s from t = 0 to the duration)\n"
      "to stdout or --csv FILE, and/or a bag (--bag FILE) with the topics the node publishes,\n"
      "stamped in sim time from 1000000000 s. With --bag and no --csv, no CSV is written.\n\n"
      "Torque (at most one; default 0; clamped to command.torque_limit like the node):\n"
      "  --torque NM                 constant\n"
      "  --torque-step T,BEFORE,AFTER  BEFORE N m until T s, then AFTER N m\n"
      "  --torque-sine AMP,FREQ[,OFFSET]  OFFSET + AMP sin(2 pi FREQ t)\n"
      "  --torque-csv FILE           lines 't,torque' (optional header), each value held from\n"
      "                              its time on, 0 before the first; times non-decreasing\n\n"
      "Sweeps (many cases in one process, spread over the cores; one CSV row per case with the\n"
      "final state, max |q1|, max |q2|, the ledger error max|E + D - W - (E + D - W)(0)| at 10 "
      "Hz,\n"
      "W, D, impacts, crossings, steps and wall time; the same torque for every case):\n"
      "  --sweep KEY=START:STOP:COUNT  COUNT values of a config key (section.key, e.g.\n"
      "                              mechanism.spring_stiffness) from START to STOP; repeat for\n"
      "                              a grid (the last varies fastest)\n"
      "  --sweep-file FILE           a CSV: a header of keys, one row of values per case\n"
      "  --jobs N                    threads, 1 to 4 per core (default: one per core)\n\n"
      "Files are written under FILE.partial and renamed when complete; SIGINT or SIGTERM stops\n"
      "the run and keeps what was simulated (every finished sweep case), exit 128 + signal.\n\n"
      "Options");
  desc.add_options()("help,h", "print this help and exit")(
      "config", po::value<std::string>(),
      "mechanism YAML (default: the package's config/mechanism.yaml)")(
      "duration", po::value<double>()->required(), "simulated time [s], >= 0")(
      "torque", po::value<double>(), "constant driver moment M_m [N m]")(
      "torque-step", po::value<std::string>(), "T,BEFORE,AFTER")(
      "torque-sine", po::value<std::string>(), "AMP,FREQ[,OFFSET]")(
      "torque-csv", po::value<std::string>(), "FILE of t,torque lines")(
      "output-rate", po::value<double>()->default_value(100.0),
      "rows / bag messages per simulated second [Hz]; must divide simulation.physics_rate")(
      "integrator", po::value<std::string>(), "rk4 | dopri5 (default: the config's)")(
      "csv", po::value<std::string>(), "write the CSV to this file instead of stdout")(
      "bag", po::value<std::string>(), "also write a bag of the node's topics to this file")(
      "sweep", po::value<std::vector<std::string>>()->composing(), "KEY=START:STOP:COUNT")(
      "sweep-file", po::value<std::string>(), "CSV of parameter sets")(
      "jobs", po::value<long long>(), "sweep threads, 1 to 4 per core (default: one per core)");
  return desc;
}

std::string num(double value) {  // shortest exact-enough form for messages: 1e+12, 0.5, 300
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.15g", value);
  return buffer;
}

double requireFinite(const std::string& flag, double value) {
  if (!std::isfinite(value)) throw UsageError("--" + flag + " must be finite, got " + num(value));
  return value;
}

std::vector<double> parseList(const std::string& flag, const std::string& text, size_t min_count,
                              size_t max_count) {
  std::vector<double> values;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    try {
      size_t used = 0;
      values.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw UsageError("--" + flag + ": '" + item + "' is not a number");
    }
    requireFinite(flag, values.back());
  }
  if (!text.empty() && text.back() == ',')
    throw UsageError("--" + flag + ": '" + text + "' ends with a comma (a value is missing)");
  if (values.size() < min_count || values.size() > max_count)
    throw UsageError("--" + flag + " takes " + std::to_string(min_count) +
                     (max_count > min_count ? " to " + std::to_string(max_count) : "") +
                     " comma-separated numbers, got '" + text + "'");
  return values;
}

kane_sim::TorqueProfile parseProfile(const po::variables_map& vm) {
  int given = 0;
  for (const char* flag : {"torque", "torque-step", "torque-sine", "torque-csv"})
    given += static_cast<int>(vm.count(flag));
  if (given > 1)
    throw UsageError("give at most one of --torque, --torque-step, --torque-sine, --torque-csv");
  if (vm.count("torque-step")) {
    const auto v = parseList("torque-step", vm["torque-step"].as<std::string>(), 3, 3);
    return kane_sim::TorqueProfile::step(v[0], v[1], v[2]);
  }
  if (vm.count("torque-sine")) {
    const auto v = parseList("torque-sine", vm["torque-sine"].as<std::string>(), 2, 3);
    return kane_sim::TorqueProfile::sine(v[0], v[1], v.size() > 2 ? v[2] : 0.0);
  }
  if (vm.count("torque-csv")) {
    try {
      return kane_sim::TorqueProfile::fromCsvFile(vm["torque-csv"].as<std::string>());
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--torque-csv: ") + e.what());
    }
  }
  const double torque =
      vm.count("torque") ? requireFinite("torque", vm["torque"].as<double>()) : 0.0;
  return kane_sim::TorqueProfile::constant(torque);
}

// Returns false when --help was asked for.
bool parseOptions(int argc, char** argv, Options* options) {
  const po::options_description desc = describeOptions();
  po::variables_map vm;
  try {
    po::store(po::parse_command_line(argc, argv, desc), vm);
    if (vm.count("help")) {
      std::cout << desc << "\n";
      return false;
    }
    po::notify(vm);
  } catch (const po::error& e) {
    throw UsageError(e.what());
  }
  if (vm.count("config")) {
    options->config_path = vm["config"].as<std::string>();
  } else {
    options->config_path = kane_sim::defaultConfigFile();
    options->default_config = true;
  }
  options->duration = requireFinite("duration", vm["duration"].as<double>());
  options->output_rate = requireFinite("output-rate", vm["output-rate"].as<double>());
  options->profile = parseProfile(vm);
  if (vm.count("integrator")) {
    options->integrator = vm["integrator"].as<std::string>();
    if (options->integrator != kane_sim::integratorName(kane_sim::IntegratorType::kRk4) &&
        options->integrator != kane_sim::integratorName(kane_sim::IntegratorType::kDopri5))
      throw UsageError("--integrator must be rk4 or dopri5, got '" + options->integrator + "'");
  }
  if (vm.count("sweep")) options->sweep_axes = vm["sweep"].as<std::vector<std::string>>();
  if (vm.count("sweep-file")) options->sweep_file = vm["sweep-file"].as<std::string>();
  if (vm.count("jobs")) {
    const long long jobs = vm["jobs"].as<long long>();
    const long long most = 4LL * std::max(1u, std::thread::hardware_concurrency());
    if (jobs < 1 || jobs > most)
      throw UsageError("--jobs must be in [1, " + std::to_string(most) + "] (4 per core), got " +
                       std::to_string(jobs));
    options->jobs = static_cast<unsigned>(jobs);
  }
  if (!options->sweep_axes.empty() && !options->sweep_file.empty())
    throw UsageError("give --sweep or --sweep-file, not both");
  if (options->sweep() && vm.count("bag"))
    throw UsageError("--bag writes one run's topics; a sweep writes one summary row per case");
  if (vm.count("jobs") && !options->sweep()) throw UsageError("--jobs is for --sweep");
  if (vm.count("csv")) options->csv_path = vm["csv"].as<std::string>();
  if (vm.count("bag")) options->bag_path = vm["bag"].as<std::string>();
  for (const char* flag : {"csv", "bag"})
    if (vm.count(flag) && vm[flag].as<std::string>().empty())
      throw UsageError(std::string("--") + flag + " needs a file name, got ''");
  // Two outputs, or an output and the config, in one file would destroy each other.
  const auto same = [](const std::string& a, const std::string& b) {
    std::error_code error;
    return !a.empty() && !b.empty() &&
           (a == b || std::filesystem::weakly_canonical(a, error) ==
                          std::filesystem::weakly_canonical(b, error));
  };
  if (same(options->csv_path, options->config_path) ||
      same(options->bag_path, options->config_path))
    throw UsageError("--csv and --bag must not name the --config file '" + options->config_path +
                     "'");
  if (same(options->csv_path, options->bag_path))
    throw UsageError("--csv and --bag must name different files, got '" + options->csv_path +
                     "' for both");
  if (options->duration < 0 || options->duration > kMaxDuration)
    throw UsageError("--duration must be in [0, " + num(kMaxDuration) + "] s, got " +
                     num(options->duration));
  if (!(options->output_rate > 0))
    throw UsageError("--output-rate must be > 0, got " + num(options->output_rate));
  return true;
}

// Physics steps per output row; the output grid must sit on the physics grid.
long stepsPerRow(double physics_rate, double output_rate) {
  const double ratio = physics_rate / output_rate;
  const double whole = std::round(ratio);
  if (!(whole >= 1 && whole <= kMaxStepsPerRow) || std::abs(ratio - whole) > 1e-9 * ratio)
    throw UsageError("--output-rate " + num(output_rate) +
                     " Hz must divide simulation.physics_rate " + num(physics_rate) +
                     " Hz into a whole number of physics steps");
  return static_cast<long>(whole);
}

// An output written under FILE.partial and renamed to FILE when complete (also when the run is
// interrupted or refused a step: what was simulated is kept): an existing FILE is replaced only
// by a finished one, and an interrupted run never leaves a truncated FILE behind. A FILE that
// exists and is not a regular file (/dev/stdout, a pipe) is written directly.
class StagedPath {
 public:
  explicit StagedPath(std::string path) : path_(std::move(path)), staging_(path_ + ".partial") {
    std::error_code error;
    if (std::filesystem::exists(path_, error) && !std::filesystem::is_regular_file(path_, error)) {
      staging_ = path_;
      published_ = true;
    }
  }
  StagedPath(const StagedPath&) = delete;
  StagedPath& operator=(const StagedPath&) = delete;
  ~StagedPath() {
    std::error_code error;
    if (!published_) std::filesystem::remove(staging_, error);  // an output error: no debris
  }
  const std::string& staging() const { return staging_; }
  void publish() {
    if (staging_ == path_) return;
    std::error_code error;
    std::filesystem::rename(staging_, path_, error);
    if (error)
      throw OutputError("cannot rename '" + staging_ + "' to '" + path_ + "': " + error.message());
    published_ = true;
  }

 private:
  std::string path_, staging_;
  bool published_ = false;
};

// The CSV: --csv FILE (staged, see StagedPath) or stdout.
class CsvOutput {
 public:
  explicit CsvOutput(const std::string& path) {
    if (path.empty()) return;
    staged_ = std::make_unique<StagedPath>(path);
    file_.open(staged_->staging());
    if (!file_) throw OutputError("cannot write --csv '" + path + "'");
  }
  std::ostream& stream() { return staged_ ? static_cast<std::ostream&>(file_) : std::cout; }
  // Flushed: what was written survives a crash (in FILE.partial).
  void flush() {
    stream().flush();
    if (!stream()) throw OutputError("writing the CSV failed (disk full?)");
  }
  // The last bytes out and the file in place.
  void finish() {
    flush();
    if (!staged_) return;
    file_.close();
    staged_->publish();
  }

 private:
  std::unique_ptr<StagedPath> staged_;
  std::ofstream file_;
};

// Where the rows go: a CSV stream and/or a bag, both fed from the same snapshots.
class Outputs {
 public:
  Outputs(const Options& options, const kane_sim::Config& config)
      : robot_(kane_sim::describeRobot(config)) {
    // With a bag and no --csv, no CSV.
    if (!options.csv_path.empty() || options.bag_path.empty())
      csv_ = std::make_unique<CsvOutput>(options.csv_path);
    if (!options.bag_path.empty()) {
      bag_path_ = options.bag_path;
      bag_file_ = std::make_unique<StagedPath>(options.bag_path);
      try {
        bag_ = std::make_unique<kane_sim::BagWriter>(bag_file_->staging());
      } catch (const std::exception& e) {
        throw OutputError("cannot write --bag '" + options.bag_path + "': " + e.what());
      }
      bag_->writeStatic(kane_sim::staticTransforms(robot_, kane_sim::simStamp(0)));
    }
    if (csv_) kane_sim::writeCsvHeader(csv_->stream());
  }

  void write(const kane_sim::Snapshot& snapshot) {
    if (csv_) {
      kane_sim::writeCsvRow(csv_->stream(), snapshot);
      if (!csv_->stream()) throw OutputError("writing the CSV failed (disk full?)");
    }
    if (bag_) {
      const ros::Time stamp = kane_sim::simStamp(snapshot.time);
      try {
        // real_time_factor 0: offline, not paced against any wall clock.
        bag_->write(kane_sim::buildMessages(snapshot, robot_, 0.0, stamp), stamp);
      } catch (const std::exception& e) {
        throw OutputError("writing --bag '" + bag_path_ + "' failed (disk full?): " + e.what());
      }
    }
  }

  // Completes the outputs (the bag's index, the CSV's last bytes) and puts them in place.
  void finish() {
    if (bag_) {
      try {
        bag_->close();
      } catch (const std::exception& e) {
        throw OutputError("closing --bag '" + bag_path_ + "' failed (disk full?): " + e.what());
      }
      bag_file_->publish();
    }
    if (csv_) csv_->finish();
  }

 private:
  kane_sim::RobotDescription robot_;  // the node's tf tree, the same in the bag
  std::unique_ptr<StagedPath> bag_file_;
  std::string bag_path_;
  std::unique_ptr<CsvOutput> csv_;
  std::unique_ptr<kane_sim::BagWriter> bag_;
};

// The row count of a run; a duration off the output grid is refused rather than cut short.
long rowCount(double duration, double output_rate) {
  const double periods = duration * output_rate;
  const double whole = std::round(periods);
  if (std::abs(periods - whole) > 1e-9 * std::max(1.0, periods))
    throw UsageError("--duration " + num(duration) +
                     " s is not a whole number of output periods (" + num(1.0 / output_rate) +
                     " s at --output-rate " + num(output_rate) + " Hz): use " +
                     num(std::floor(periods) / output_rate) + " or " +
                     num(std::ceil(periods) / output_rate) + " s");
  return static_cast<long>(whole);
}

// Sweep mode: every case through the library's runSweep, one row each, in case order.
int runSweepMode(const Options& options, const YAML::Node& base) {
  kane_sim::SweepPlan plan;
  try {
    if (!options.sweep_file.empty()) {
      std::ifstream in(options.sweep_file);
      if (!in) throw UsageError("cannot read --sweep-file '" + options.sweep_file + "'");
      plan = kane_sim::sweepFromCsv(in);
    } else {
      std::vector<kane_sim::SweepAxis> axes;
      for (const std::string& spec : options.sweep_axes)
        axes.push_back(kane_sim::parseSweepAxis(spec));
      plan = kane_sim::sweepGrid(axes);
    }
  } catch (const std::invalid_argument& e) {
    throw UsageError((options.sweep_file.empty() ? "" : "--sweep-file: ") + std::string(e.what()));
  }
  // Every key is checked before anything runs: a typo (or an unknown section) would otherwise
  // sweep the base config. A value the loader refuses is that case's row (config_refused).
  try {
    kane_sim::checkSweepKeys(base, plan);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  kane_sim::SweepSettings settings;
  settings.duration = options.duration;
  settings.torque = *options.profile;
  settings.jobs = options.jobs;
  settings.stop = &g_stop;
  settings.on_warning = [](const std::string& text) { std::cerr << "warning: " << text << "\n"; };
  CsvOutput csv(options.csv_path);
  std::ostream* out = &csv.stream();
  kane_sim::writeSweepCsvHeader(*out, plan);
  std::uint64_t steps = 0;
  size_t failed = 0, written = 0;
  bool write_failed = false;
  // Each row as its case finishes (in case order), flushed: a crash keeps them in FILE.partial.
  const auto sink = [&](size_t i, const kane_sim::SweepResult& r) {
    kane_sim::writeSweepCsvRow(*out, plan, i, r);
    out->flush();  // a crash keeps the finished rows
    write_failed = write_failed || !*out;
    ++written;
    steps += r.steps;
    if (r.status != "ok" && failed++ < 5)
      std::cerr << "warning: case " << i << ": " << r.error << "\n";
  };
  const auto wall_start = std::chrono::steady_clock::now();
  kane_sim::runSweep(base, plan, settings, sink);
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

int run(const Options& options) {
  // --integrator goes into the tree before validation, so the stability check judges the
  // integrator that will run.
  YAML::Node root = kane_sim::loadYamlFile(options.config_path);
  if (!options.integrator.empty() && root.IsMap()) {
    if (!root["simulation"] || root["simulation"].IsNull())
      root["simulation"] = YAML::Node(YAML::NodeType::Map);
    if (root["simulation"].IsMap()) root["simulation"]["integrator"] = options.integrator;
  }
  if (options.default_config)
    std::cerr << "no --config given: using the package's default " << options.config_path << "\n";
  kane_sim::LoadedConfig loaded = kane_sim::loadConfig(root);
  for (const std::string& warning : loaded.warnings) std::cerr << "warning: " << warning << "\n";
  if (options.sweep()) return runSweepMode(options, root);
  const kane_sim::Config& config = loaded.config;

  const long steps_per_row = stepsPerRow(config.simulation.physics_rate, options.output_rate);
  const long rows = rowCount(options.duration, options.output_rate);

  // The same driver as the node: the profile is a stream of commands, clamped alike; each
  // kind of event is printed once.
  std::set<kane_sim::SimEvent::Kind> reported;
  kane_sim::SimDriver driver(config, [&reported](const kane_sim::SimEvent& event) {
    if (event.kind == kane_sim::SimEvent::Kind::kStepRefused)
      std::cerr << "error: " << event.message << "\n";
    else if (reported.insert(event.kind).second)
      std::cerr << "warning: " << event.message << " (at t = " << event.time << " s)\n";
  });

  Outputs out(options, config);
  const auto wall_start = std::chrono::steady_clock::now();
  kane_sim::ProfileCommands commands(*options.profile, config.command.timeout);
  commands.update(driver);
  out.write(driver.snapshot());
  for (long row = 1; row <= rows; ++row) {
    if (g_stop) {
      out.finish();
      std::cerr << "interrupted at t = " << driver.time() << " s: kept the " << row
                << " outputs simulated until then\n";
      return kExitSignalBase + g_signal.load();
    }
    for (long i = 0; i < steps_per_row; ++i) {
      if (!driver.step()) {
        out.finish();  // what was simulated up to the refusal stays readable
        return kExitStepRefused;
      }
      commands.update(driver);
    }
    out.write(driver.snapshot());
  }
  out.finish();
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  std::cerr << "simulated " << driver.time() << " s in " << driver.ticks() << " physics steps ("
            << kane_sim::integratorName(config.simulation.integrator) << " at "
            << config.simulation.physics_rate << " Hz on the "
            << kane_sim::equationsName(config.simulation.equations) << " equations, torque "
            << options.profile->describe() << "), " << rows + 1 << " outputs, wall time " << wall
            << " s, " << (wall > 0 ? static_cast<double>(driver.ticks()) / wall : 0.0)
            << " steps/s\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  ros::Time::init();  // ros::Time without a master, for the bag writer
  // Past a file-size limit (ulimit -f) a write should fail (exit 4), not kill the process.
  std::signal(SIGXFSZ, SIG_IGN);
  std::signal(SIGINT, onStopSignal);
  std::signal(SIGTERM, onStopSignal);
  Options options;
  try {
    if (!parseOptions(argc, argv, &options)) return 0;
    return run(options);
  } catch (const UsageError& e) {
    std::cerr << "error: " << e.what() << "\n\n" << describeOptions() << "\n";
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
