// simulate's command line: the options, their parsing and checks (a bad flag is a UsageError
// naming it and the value). One grammar for every tool that takes simulate's flags: simulate
// itself and scripts/sweep (through kane_sim._core.simulate_options).
#ifndef KANE_SIM_CLI_SIMULATE_OPTIONS_H
#define KANE_SIM_CLI_SIMULATE_OPTIONS_H

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <boost/program_options.hpp>

#include "kane_sim/sim/sweep.h"
#include "kane_sim/sim/torque_profile.h"

namespace kane_sim {
namespace cli {

struct UsageError : std::runtime_error {
  // show_usage false: the mistake is not in the flags (an environment variable), so the usage
  // text would bury the message.
  explicit UsageError(const std::string& what, bool show_usage = true)
      : std::runtime_error(what), show_usage(show_usage) {}
  bool show_usage;
};

struct Options {
  std::string config_path;
  double duration = 0.0;
  double output_rate = 100.0;
  std::optional<kane_sim::TorqueProfile> profile;  // resolved after parsing
  bool profile_given = false;  // a --torque* flag was given (else constant 0 N m)
  std::string torque_csv;      // --torque-csv's file ("" without it)
  std::string integrator;      // empty: the config's
  std::string csv_path;        // empty: stdout (unless only a bag is asked for)
  std::string bag_path;
  // Sweep mode: many cases, one summary row each (kane_sim/sim/sweep.h).
  std::vector<std::string> sweep_axes;  // --sweep KEY=START:STOP:COUNT, repeatable (a grid)
  std::string sweep_file;               // --sweep-file CSV of parameter sets
  unsigned jobs = 0;                    // --jobs, 0 = one per core
  std::string simd = "auto";            // --simd
  bool vector_trig = false;             // --vector-trig
  bool default_config = false;          // no --config: the package's config/mechanism.yaml
  std::string replay_bag;               // --replay BAG: re-run the inputs logged in a bag
  double replay_tolerance = 0.0;        // --tolerance: largest difference that counts as equal
  bool replay_accept_gaps = false;      // --accept-gaps: inputs missing from the bag exit 0
  bool sweep() const { return !sweep_axes.empty() || !sweep_file.empty(); }
};

// The --help text.
boost::program_options::options_description describeOptions();
// Fills `options` from the command line; false after --help (printed). Throws UsageError.
bool parseOptions(int argc, char** argv, Options* options);
// The same for arguments without the program's name (argv[1:]); --help is a UsageError naming
// it (a caller with its own help text prints that).
Options parseArguments(const std::vector<std::string>& arguments);
// A sweep's cases from --sweep axes or --sweep-file, every key checked against the schema
// (a typo would sweep the base config). Throws UsageError naming the flag.
kane_sim::SweepPlan sweepPlan(const Options& options);
// Numbers in simulate's messages: shortest exact-enough form (1e+12, 0.5, 300).
std::string num(double value);

}  // namespace cli
}  // namespace kane_sim

#endif  // KANE_SIM_CLI_SIMULATE_OPTIONS_H
