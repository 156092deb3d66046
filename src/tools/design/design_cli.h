// What `design lqr` and `design plan` share: exit codes, the command line's numbers and weights,
// the LQR weights from the config and the flags, and writing the result to --out.
#ifndef KANE_SIM_TOOLS_DESIGN_DESIGN_CLI_H
#define KANE_SIM_TOOLS_DESIGN_DESIGN_CLI_H

#include <functional>
#include <ostream>
#include <stdexcept>
#include <string>

#include <Eigen/Core>
#include <boost/program_options.hpp>

#include "kane_sim/design/lqr.h"

namespace kane_sim {
namespace design_cli {

constexpr int kExitConfig = 1;
constexpr int kExitUsage = 2;
constexpr int kExitNoDesign = 3;
constexpr int kExitOutput = 4;
constexpr int kExitInterrupted = 130;  // SIGINT
constexpr int kExitTerminated = 143;   // SIGTERM

struct UsageError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// A finite number (cli/number_argument.h), refused as a UsageError naming the flag.
double number(const std::string& text, const std::string& flag);
// An angle: a number, pi or -pi.
double angle(const std::string& text, const std::string& flag);
// "A,B" as two numbers.
std::pair<double, double> numberPair(const std::string& text, const std::string& flag);

// Bryson's defaults (defaultLqrWeights), the diagonal of --Q and --R over them when given.
LqrWeights weightsFrom(const boost::program_options::variables_map& vm, const Config& config,
                       const MechanismModel& model);

// --out FILE (or - for stdout) gets `write`; refuses the config itself. Returns 0 or an exit code
// (its reason said on stderr). `what` names the result ("the law", "the plan").
int writeOut(const boost::program_options::variables_map& vm, const std::string& config_path,
             const std::string& what, const std::function<void(std::ostream&)>& write);

// Flush stdout; kExitOutput (said) when it cannot be written.
int flushStdout();

int runLqr(const boost::program_options::variables_map& vm);
int runPlan(const boost::program_options::variables_map& vm);

}  // namespace design_cli
}  // namespace kane_sim

#endif  // KANE_SIM_TOOLS_DESIGN_DESIGN_CLI_H
