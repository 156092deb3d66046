#include "observer/observer_bag.h"

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <system_error>

#include <boost/program_options.hpp>

#include "kane_sim/cli/staged_output.h"
#include "kane_sim/cli/tool_config.h"
#include "kane_sim/estimate/estimate_run.h"
#include "kane_sim/model/joint_names.h"
#include "kane_sim/ros/joint_state_bag.h"
#include "kane_sim/sim/config_check.h"

namespace po = boost::program_options;

namespace kane_sim {
namespace {

constexpr int kExitConfig = 1, kExitUsage = 2, kExitBag = 3, kExitOutput = 4;
std::atomic<int> g_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "stored from a signal handler");
extern "C" void onStopSignal(int signal) { g_signal.store(signal); }

constexpr const char* kUsage =
    "Usage: observer --bag BAG [--topic joint_states] [--config FILE] [--csv FILE]\n\n"
    "The rig's joint_states in BAG (crank_joint and slider4_joint positions, crank_joint's\n"
    "effort, the velocities when present) through the estimator of the config's mechanism\n"
    "and sensors (an extended Kalman filter on the Kane equations): one CSV row per reading,\n"
    "t from the first reading's stamp, the state at the stamp with its standard deviations,\n"
    "the encoders' biases, the innovations' test and the virtual sensors (reactions, spring\n"
    "force, energies, each load's power). The alarm's verdict and what was refused go to\n"
    "stderr. Without options it runs as a ROS node (observer --help).\n\n"
    "Options";

ReadingColumns readingColumns(const JointStateColumns& bag) {
  ReadingColumns c;
  c.t = bag.t;
  c.q1 = bag.position_a;
  c.q2 = bag.position_b;
  c.effort = bag.effort_a;
  if (bag.anyVelocity()) {
    c.u1 = bag.velocity_a;
    c.u2 = bag.velocity_b;
    c.velocity_rows = bag.velocity_rows;
  }
  return c;
}

}  // namespace

bool wantsBagReplay(int argc, char** argv) {
  // Any option but --help is the offline tool's (the node takes only ROS arguments: name:=,
  // _param:=): an option without --bag is a usage error there, not a node started silently.
  for (int i = 1; i < argc; ++i)
    if (std::strncmp(argv[i], "--", 2) == 0 && std::strcmp(argv[i], "--help") != 0) return true;
  return false;
}

int runBagReplay(int argc, char** argv) {
  po::options_description desc(kUsage);
  desc.add_options()("help,h", "print this help and exit")(
      "bag", po::value<std::string>()->required(), "the rig's recording")(
      "topic", po::value<std::string>()->default_value("joint_states"),
      "its sensor_msgs/JointState topic")(
      "config", po::value<std::string>(),
      "the mechanism and its sensors (default: the package's config/mechanism.yaml)")(
      "csv", po::value<std::string>()->default_value(""), "the rows (default: stdout)");
  po::variables_map vm;
  try {
    const po::positional_options_description none;  // a stray word is an error, not ignored
    po::store(po::command_line_parser(argc, argv).options(desc).positional(none).run(), vm);
    if (vm.count("help")) {
      std::cout << desc << "\n";
      return 0;
    }
    po::notify(vm);
  } catch (const po::error& e) {
    std::cerr << "observer: " << e.what() << "\n" << desc << "\n";
    return kExitUsage;
  }
  std::optional<std::string> config_path;
  if (vm.count("config")) config_path = vm["config"].as<std::string>();
  // The CSV must not replace an input (a typo away: --csv rig.bag).
  const std::string csv = vm["csv"].as<std::string>();
  for (const char* input : {"bag", "config"}) {
    std::error_code error;
    if (!csv.empty() && vm.count(input) &&
        std::filesystem::equivalent(csv, vm[input].as<std::string>(), error)) {
      std::cerr << "observer: --csv " << csv << " is the --" << input
                << " file: it would be overwritten; name another CSV\n";
      return kExitUsage;
    }
  }
  Config config;
  try {
    config = cli::loadToolConfig("observer", config_path).loaded.config;
    checkSimulatable(config);
  } catch (const cli::ToolConfigError& e) {
    std::cerr << e.what() << "\n";
    return kExitConfig;
  } catch (const ConfigError& e) {
    std::cerr << "observer: bad config: " << e.what() << "\n";
    return kExitConfig;
  }
  std::signal(SIGINT, onStopSignal);
  std::signal(SIGTERM, onStopSignal);
  const auto interrupted = [] { return g_signal.load() != 0; };
  const std::string bag = vm["bag"].as<std::string>();
  std::string topic = vm["topic"].as<std::string>();
  if (topic.empty() || topic[0] != '/') topic = "/" + topic;  // a bag's topics are absolute
  ReadingColumns columns;
  std::size_t skipped = 0;
  try {
    const JointStateColumns read =
        readJointStates(bag, topic, kJointNames[kCrankJoint], kJointNames[kSlider4Joint],
                        interrupted, UnusableMessages::kSkip);
    for (const std::string& note : read.skip_notes)
      std::cerr << "observer: skipped: " << note << "\n";
    skipped = read.skipped;
    columns = readingColumns(read);
  } catch (const BagReadError& e) {
    if (g_signal.load()) return 128 + g_signal.load();
    std::cerr << "observer: " << e.what() << "\n";
    return kExitBag;
  }
  try {
    cli::CsvOutput out(csv);
    writeEstimateCsvHeader(out.stream());
    const EstimateRunSummary summary = runEstimator(
        config, columns, [&](const EstimateRow& row) { writeEstimateCsvRow(out.stream(), row); },
        interrupted);
    out.finish();
    for (const std::string& note : summary.notes) std::cerr << "observer: " << note << "\n";
    if (summary.interrupted) std::cerr << "observer: interrupted: the rows so far are written\n";
    const std::size_t without_velocities =
        !columns.hasVelocity()
            ? columns.t.size()
            : static_cast<std::size_t>(
                  std::count(columns.velocity_rows.begin(), columns.velocity_rows.end(), 0));
    std::cerr << "observer: " << summary.rows << " rows from " << columns.t.size()
              << " readings of " << topic << " ("
              << (skipped == 0 ? "" : std::to_string(skipped) + " messages skipped, ")
              << summary.refused << " refused, " << summary.restarts << " restarts"
              << (without_velocities == 0
                      ? ""
                      : ", " + std::to_string(without_velocities) + " without velocities")
              << "); alarm " << summary.alarm.text() << "\n";
    if (summary.interrupted) return 128 + g_signal.load();
  } catch (const cli::OutputError& e) {
    std::cerr << "observer: " << e.what() << "\n";
    return kExitOutput;
  }
  return 0;
}

}  // namespace kane_sim
