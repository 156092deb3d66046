#include "kane_sim/cli/simulate_options.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "kane_sim/batch/lanes.h"
#include "kane_sim/config/input_file.h"
#include "kane_sim/config/load_config.h"
#include "kane_sim/sim/output_grid.h"
#include "kane_sim/sim/sweep.h"

namespace po = boost::program_options;

namespace kane_sim {
namespace cli {

po::options_description describeOptions() {
  po::options_description desc(
      "Usage: simulate [--config FILE] --duration SECONDS [options]\n\n"
      "Simulates the textbook example's mechanism (Kane equations - Example 1) offline (no ROS "
      "master). Writes a CSV with the\n"
      "header t,q1,q2,u1,u2,total_energy,... (rows every 1/output-rate s from t = 0 to the "
      "duration)\n"
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
      "  --jobs N                    threads, 1 to 4 per core (default: one per core)\n"
      "  --simd SET                  auto (default: the CPU's widest), avx512, avx2, sse2,\n"
      "                              scalar (lanes of one double: the single run's bits), off\n"
      "                              (every case alone); rk4 effort-mode cases without contact\n"
      "                              or motor line step W per instruction, the rest alone;\n"
      "                              every lane equals its single run bit for bit; the\n"
      "                              environment's KANE_SIM_SIMD_MAX=SET caps the sets allowed\n"
      "  --vector-trig               lanes on xsimd's vector sin/cos (no faster than the default\n"
      "                              since it is vector-wide too), equal to the single runs\n"
      "                              only to rounding grown by the motion\n\n"
      "Replay (a bag recorded from kane_sim_node with its ~input_log and mechanism_state):\n"
      "  --replay BAG [--tolerance X]  feed the bag's inputs to the driver at their physics\n"
      "                              ticks; print the largest difference from the bag's states;\n"
      "                              exit 6 when it exceeds X (default 0: bit for bit). --config\n"
      "                              must be the node's config. Inputs missing from the bag are\n"
      "                              named, compared up to, and exit 6 unless --accept-gaps.\n\n"
      "Files are written under FILE.partial and renamed when complete; SIGINT or SIGTERM stops\n"
      "the run and keeps what was simulated (every finished sweep case), exit 128 + signal.\n\n"
      "Options");
  desc.add_options()("help,h", "print this help and exit")(
      "config", po::value<std::string>(),
      "mechanism YAML (default: the package's config/mechanism.yaml)")(
      "duration", po::value<double>(), "simulated time [s], >= 0 (required but with --replay)")(
      "replay", po::value<std::string>(),
      "re-run the inputs a bag's ~input_log holds, compare with its mechanism_state")(
      "tolerance", po::value<double>(),
      "--replay: largest |difference| in q, u counted as equal (default 0: bit for bit)")(
      "accept-gaps",
      "--replay: exit 0 when inputs are missing from the bag (each gap is still named, and the "
      "states it left uncompared counted)")("torque", po::value<double>(),
                                            "constant driver moment M_m [N m]")(
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
      "jobs", po::value<long long>(), "sweep threads, 1 to 4 per core (default: one per core)")(
      "simd", po::value<std::string>(), "sweep lanes: auto | avx512 | avx2 | sse2 | scalar | off")(
      "vector-trig", "sweep lanes on xsimd's vector sin/cos (not the single runs' bits)");
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

kane_sim::TorqueProfile parseProfile(const po::variables_map& vm) {
  int given = 0;
  for (const char* flag : {"torque", "torque-step", "torque-sine", "torque-csv"})
    given += static_cast<int>(vm.count(flag));
  if (given > 1)
    throw UsageError("give at most one of --torque, --torque-step, --torque-sine, --torque-csv");
  for (const char* flag : {"torque-step", "torque-sine", "torque-csv"}) {
    if (!vm.count(flag)) continue;
    try {
      return kane_sim::TorqueProfile::fromFlag(flag, vm[flag].as<std::string>());
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
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
    // No abbreviations: --dur would be --duration, and a typo of one flag another's.
    const int style =
        po::command_line_style::default_style & ~po::command_line_style::allow_guessing;
    // No positional arguments either: a forgotten --sweep before a second axis must not vanish.
    const po::positional_options_description none;
    po::store(po::command_line_parser(argc, argv).options(desc).style(style).positional(none).run(),
              vm);
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
  if (vm.count("replay")) {
    options->replay_bag = vm["replay"].as<std::string>();
    for (const char* flag : {"duration", "torque", "torque-step", "torque-sine", "torque-csv",
                             "sweep", "sweep-file", "bag", "csv", "output-rate", "integrator"})
      if (vm.count(flag) && !vm[flag].defaulted())
        throw UsageError(std::string("--replay takes the bag's inputs and times: no --") + flag);
    if (vm.count("tolerance")) {
      options->replay_tolerance = requireFinite("tolerance", vm["tolerance"].as<double>());
      if (options->replay_tolerance < 0)
        throw UsageError("--tolerance must be >= 0, got " + num(options->replay_tolerance));
    }
    options->replay_accept_gaps = vm.count("accept-gaps") > 0;
  } else if (vm.count("tolerance") || vm.count("accept-gaps")) {
    throw UsageError(std::string(vm.count("tolerance") ? "--tolerance" : "--accept-gaps") +
                     " is for --replay");
  } else if (!vm.count("duration")) {
    throw UsageError("the option '--duration' is required but missing");
  }
  options->duration =
      vm.count("duration") ? requireFinite("duration", vm["duration"].as<double>()) : 0.0;
  options->output_rate = requireFinite("output-rate", vm["output-rate"].as<double>());
  options->profile = parseProfile(vm);
  if (vm.count("torque-csv")) options->torque_csv = vm["torque-csv"].as<std::string>();
  for (const char* flag : {"torque", "torque-step", "torque-sine", "torque-csv"})
    options->profile_given |= vm.count(flag) > 0;
  if (vm.count("integrator")) {
    options->integrator = vm["integrator"].as<std::string>();
    if (options->integrator != kane_sim::integratorName(kane_sim::IntegratorType::kRk4) &&
        options->integrator != kane_sim::integratorName(kane_sim::IntegratorType::kDopri5))
      throw UsageError("--integrator must be rk4 or dopri5, got '" + options->integrator + "'");
  }
  if (vm.count("sweep")) options->sweep_axes = vm["sweep"].as<std::vector<std::string>>();
  if (vm.count("sweep-file")) {
    options->sweep_file = vm["sweep-file"].as<std::string>();
    if (options->sweep_file.empty()) throw UsageError("--sweep-file needs a file name, got ''");
  }
  if (vm.count("jobs")) {
    const long long jobs = vm["jobs"].as<long long>();
    const long long most = kane_sim::maxSweepJobs();
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
  if (vm.count("vector-trig")) {
    if (!options->sweep()) throw UsageError("--vector-trig is for --sweep");
    options->vector_trig = true;
  }
  if (vm.count("simd")) {
    if (!options->sweep()) throw UsageError("--simd is for --sweep");
    options->simd = vm["simd"].as<std::string>();
  }
  try {  // a bad KANE_SIM_SIMD_MAX, named before any run whatever the run
    kane_sim::checkLaneEnvironment();
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what(), false);
  }
  if (options->sweep() && options->simd != "off") {
    try {  // a typo, or a set this CPU (or the cap) lacks, named before any run
      kane_sim::parseLaneArch(options->simd);
    } catch (const std::invalid_argument& e) {
      throw UsageError(std::string("--") + e.what());
    }
  }
  if (vm.count("csv")) options->csv_path = vm["csv"].as<std::string>();
  if (vm.count("bag")) options->bag_path = vm["bag"].as<std::string>();
  for (const char* flag : {"csv", "bag"}) {
    if (!vm.count(flag)) continue;
    const std::string& path = vm[flag].as<std::string>();
    if (path.empty()) throw UsageError(std::string("--") + flag + " needs a file name, got ''");
    std::error_code error;
    if (std::filesystem::is_directory(path, error))
      throw UsageError(std::string("--") + flag + " " + path + " is a folder: give a file name");
  }
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
  try {
    kane_sim::checkRunDuration(options->duration, "--duration");
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  if (!(options->output_rate > 0))
    throw UsageError("--output-rate must be > 0, got " + num(options->output_rate));
  return true;
}

Options parseArguments(const std::vector<std::string>& arguments) {
  for (const std::string& argument : arguments)
    if (argument == "--help" || argument == "-h")
      throw UsageError(argument + " is the caller's: simulate's options take no --help here");
  std::vector<std::string> storage{"simulate"};
  storage.insert(storage.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (std::string& text : storage) argv.push_back(text.data());
  Options options;
  parseOptions(static_cast<int>(argv.size()), argv.data(), &options);
  return options;
}

kane_sim::SweepPlan sweepPlan(const Options& options) {
  kane_sim::SweepPlan plan;
  try {
    if (!options.sweep_file.empty()) {
      std::ifstream in =
          kane_sim::openInputFile(options.sweep_file, "sweep file", kane_sim::kMaxTableBytes);
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
    kane_sim::checkSweepKeys(plan);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
  return plan;
}

}  // namespace cli
}  // namespace kane_sim
