// `simulate`: runs the mechanism offline (no ROS master) and writes a CSV.
//
// Exit codes: 0 ok, 1 bad config, 2 bad command line, 3 the simulation refused a step,
// 4 the output could not be written.
#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <string>

#include <boost/program_options.hpp>

#include "kane_sim/csv_format.h"
#include "kane_sim/load_config.h"
#include "kane_sim/simulator.h"

namespace po = boost::program_options;
using kane_sim::ConfigError;

namespace {

constexpr int kExitConfig = 1;
constexpr int kExitUsage = 2;
constexpr int kExitStepRefused = 3;
constexpr int kExitOutput = 4;

struct Options {
  std::string config_path;
  double duration = 0.0;
  double torque = 0.0;
  double output_rate = 100.0;
  std::string integrator;  // empty: the config's
  std::string csv_path;    // empty: stdout
};

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

po::options_description describeOptions() {
  po::options_description desc(
      "Usage: simulate --config FILE --duration SECONDS [options]\n\n"
      "Simulates the Kane example-1 mechanism offline and writes a CSV with the header\n"
      "t,q1,q2,u1,u2,energy,... (rows every 1/output-rate s from t = 0 to the duration).\n\n"
      "Options");
  desc.add_options()("help,h", "print this help and exit")(
      "config", po::value<std::string>()->required(), "mechanism YAML (config/mechanism.yaml)")(
      "duration", po::value<double>()->required(), "simulated time [s], >= 0")(
      "torque", po::value<double>()->default_value(0.0), "constant driver moment M_m [N m]")(
      "output-rate", po::value<double>()->default_value(100.0),
      "CSV rows per simulated second [Hz]; must divide simulation.physics_rate")(
      "integrator", po::value<std::string>(), "rk4 | dopri5 (default: the config's)")(
      "csv", po::value<std::string>(), "write the CSV to this file instead of stdout");
  return desc;
}

double requireFinite(const std::string& flag, double value) {
  if (!std::isfinite(value))
    throw UsageError("--" + flag + " must be finite, got " + std::to_string(value));
  return value;
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
  options->config_path = vm["config"].as<std::string>();
  options->duration = requireFinite("duration", vm["duration"].as<double>());
  options->torque = requireFinite("torque", vm["torque"].as<double>());
  options->output_rate = requireFinite("output-rate", vm["output-rate"].as<double>());
  if (vm.count("integrator")) options->integrator = vm["integrator"].as<std::string>();
  if (vm.count("csv")) options->csv_path = vm["csv"].as<std::string>();
  if (options->duration < 0)
    throw UsageError("--duration must be >= 0, got " + std::to_string(options->duration));
  if (!(options->output_rate > 0))
    throw UsageError("--output-rate must be > 0, got " + std::to_string(options->output_rate));
  return true;
}

// Physics steps per CSV row; the output grid must sit on the physics grid.
long stepsPerRow(double physics_rate, double output_rate) {
  const double ratio = physics_rate / output_rate;
  const double whole = std::round(ratio);
  if (whole < 1 || std::abs(ratio - whole) > 1e-9 * ratio)
    throw UsageError("--output-rate " + std::to_string(output_rate) +
                     " Hz must divide simulation.physics_rate " + std::to_string(physics_rate) +
                     " Hz into a whole number of physics steps");
  return static_cast<long>(whole);
}

int run(const Options& options) {
  kane_sim::LoadedConfig loaded = kane_sim::loadConfigFile(options.config_path);
  for (const std::string& warning : loaded.warnings) std::cerr << "warning: " << warning << "\n";
  kane_sim::Config& config = loaded.config;
  if (!options.integrator.empty())
    config.simulation.integrator =
        kane_sim::parseIntegratorName(options.integrator, "--integrator");

  const long steps_per_row = stepsPerRow(config.simulation.physics_rate, options.output_rate);
  const long rows = static_cast<long>(std::floor(options.duration * options.output_rate + 1e-9));

  std::ofstream file;
  if (!options.csv_path.empty()) {
    file.open(options.csv_path);
    if (!file) {
      std::cerr << "error: cannot write --csv '" << options.csv_path << "'\n";
      return kExitOutput;
    }
  }
  std::ostream& out = options.csv_path.empty() ? std::cout : file;

  kane_sim::Simulator sim(config);
  sim.setTorque(options.torque);
  const auto wall_start = std::chrono::steady_clock::now();
  kane_sim::writeCsvHeader(out);
  kane_sim::writeCsvRow(out, sim.snapshot());
  for (long row = 1; row <= rows; ++row) {
    for (long i = 0; i < steps_per_row; ++i) {
      const kane_sim::StepResult result = sim.step();
      if (!result.ok) {
        std::cerr << "error: " << result.error << "\n";
        return kExitStepRefused;
      }
    }
    kane_sim::writeCsvRow(out, sim.snapshot());
  }
  out.flush();
  if (!out) {
    std::cerr << "error: writing the CSV failed\n";
    return kExitOutput;
  }
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  std::cerr << "simulated " << sim.time() << " s in " << sim.ticks() << " physics steps ("
            << kane_sim::integratorName(config.simulation.integrator) << " at "
            << config.simulation.physics_rate << " Hz), wall time " << wall << " s, "
            << (wall > 0 ? static_cast<double>(sim.ticks()) / wall : 0.0) << " steps/s\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  try {
    if (!parseOptions(argc, argv, &options)) return 0;
    return run(options);
  } catch (const UsageError& e) {
    std::cerr << "error: " << e.what() << "\n\n" << describeOptions() << "\n";
    return kExitUsage;
  } catch (const ConfigError& e) {
    if (e.key() == "--integrator") {
      std::cerr << "error: " << e.what() << "\n\n" << describeOptions() << "\n";
      return kExitUsage;
    }
    std::cerr << "error: " << options.config_path << ": " << e.what() << "\n";
    return kExitConfig;
  }
}
