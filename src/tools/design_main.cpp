// `design`: controllers designed from the mechanism's model (no ROS master).
//   design lqr  --config FILE --q1 RAD [--Q Q1,Q2,Q3,Q4] [--R R] [--out FILE]
//   design plan --config FILE --to RAD [--from initial|RAD] [--objective effort|time] ...
// lqr: the law that holds the crank at rest at q1 (design/lqr.h); plan: the optimal move to the
// crank held at --to and the time-varying LQR along it (plan/plan_design.h).
// Exit codes: 0 ok, 1 bad config, 2 bad command line, 3 no design (no equilibrium, no gain, no
// plan), 4 the output cannot be written, 130 / 143 stopped by SIGINT / SIGTERM.
#include <iostream>
#include <set>
#include <string>

#include <boost/program_options.hpp>

#include "design/design_cli.h"
#include "kane_sim/cli/tool_config.h"

namespace po = boost::program_options;
using namespace kane_sim::design_cli;

int main(int argc, char** argv) {
  po::options_description desc(
      "Usage: design lqr  [--config FILE] --q1 RAD [--Q Q1,Q2,Q3,Q4] [--R R] [--out FILE]\n"
      "       design plan [--config FILE] --to RAD [--from initial|RAD] [--objective effort|time]\n"
      "                   [--duration S] [--intervals N] [--torque-limit NM] [--q2-range A,B]\n"
      "                   [--gap M] [--rate HZ] [--Q ..] [--R ..] [--out FILE]\n\n"
      "Controllers designed from the textbook example's mechanism.\n"
      "lqr: the crank held at rest at q1 (pi: upright, unstable) by its holding moment, the\n"
      "exact linearization there, and the LQR gain K of M_m = M_eq - K (x - x_eq),\n"
      "x = (q1, q2, u1, u2). Default weights by Bryson's rule: 1/0.1^2, 1/0.01^2, 1, 1/0.1^2 on\n"
      "the state; 1/torque_limit^2 on M_m.\n"
      "plan: the optimal move from --from (default: the config's initial state) to the crank\n"
      "held at rest at --to, by Hermite-Simpson collocation solved by IPOPT: minimum effort in\n"
      "--duration, or minimum time; |M_m| <= --torque-limit, slider 4 within --q2-range, the\n"
      "sliders --gap apart (default: contact.gap when contact is on). The plan CSV (--out) holds\n"
      "a row every 1/--rate s (default: the physics rate): t, the state, M_m and the\n"
      "time-varying LQR gain (weights --Q, --R) that a tracking controller follows;\n"
      "`simulate --torque-csv` plays its M_m.\n\n"
      "Options");
  desc.add_options()("help,h", "print this help and exit")(
      "config", po::value<std::string>(),
      "mechanism YAML (default: the package's config/mechanism.yaml)")(
      "q1", po::value<std::string>(), "lqr: crank angle to hold [rad] (a number, pi or -pi)")(
      "to", po::value<std::string>(), "plan: crank angle to end held at rest [rad]")(
      "from", po::value<std::string>(), "plan: 'initial' (default) or a crank angle held at rest")(
      "objective", po::value<std::string>()->default_value("effort"), "plan: effort or time")(
      "duration", po::value<std::string>()->default_value("3"),
      "plan: the move's duration [s] (time: the first guess)")(
      "max-duration", po::value<std::string>(), "plan, time: the longest [s] (10 x --duration)")(
      "intervals", po::value<int>()->default_value(100), "plan: collocation intervals")(
      "max-iterations", po::value<int>()->default_value(3000), "plan: IPOPT's iteration limit")(
      "torque-limit", po::value<std::string>(),
      "plan: |M_m| bound [N m] (default: command.torque_limit; below it leaves the feedback room)")(
      "q2-range", po::value<std::string>(), "plan: slider 4's travel MIN,MAX [m]")(
      "gap", po::value<std::string>(), "plan: the sliders at least this far apart [m]")(
      "rate", po::value<std::string>(), "plan: rows per second (default: physics_rate)")(
      "Q", po::value<std::string>(), "state weights, the diagonal on q1, q2, u1, u2")(
      "R", po::value<std::string>(), "torque weight (> 0)")(
      "out", po::value<std::string>(), "write the law or the plan to FILE (- for stdout)");
  po::positional_options_description positional;
  positional.add("method", 1);
  po::options_description hidden;
  hidden.add_options()("method", po::value<std::string>());
  po::options_description all;
  all.add(desc).add(hidden);
  po::variables_map vm;
  try {
    // No guessing of abbreviations: --objectiv is a typo, not --objective.
    po::store(
        po::command_line_parser(argc, argv)
            .options(all)
            .positional(positional)
            .style(po::command_line_style::default_style & ~po::command_line_style::allow_guessing)
            .run(),
        vm);
    po::notify(vm);
  } catch (const po::error& e) {
    std::cerr << "design: " << e.what() << "\n" << desc << "\n";
    return kExitUsage;
  }
  if (vm.count("help")) {
    std::cout << desc << "\n";
    return 0;
  }
  try {
    if (!vm.count("method")) throw UsageError("name the method: design lqr ... or design plan ...");
    const std::string method = vm["method"].as<std::string>();
    if (method != "lqr" && method != "plan")
      throw UsageError("the method must be lqr or plan, got '" + method + "'");
    // A flag of the other method is a mistake worth naming, not something to ignore.
    const std::set<std::string> lqr_only = {"q1"};
    const std::set<std::string> plan_only = {
        "to",        "from",           "objective",    "duration", "max-duration",
        "intervals", "max-iterations", "torque-limit", "q2-range", "gap",
        "rate"};
    for (const auto& [flag, value] : vm) {
      const bool wrong =
          method == "lqr" ? plan_only.count(flag) && !value.defaulted() : lqr_only.count(flag) > 0;
      if (wrong) throw UsageError("--" + flag + " is not a flag of design " + method);
    }
    return method == "lqr" ? runLqr(vm) : runPlan(vm);
  } catch (const UsageError& e) {
    std::cerr << "design: " << e.what() << "\n" << desc << "\n";
    return kExitUsage;
  } catch (const kane_sim::cli::ToolConfigError& e) {
    std::cerr << e.what() << "\n";
    return kExitConfig;
  }
}
