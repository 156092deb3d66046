// `analyze`: linear analysis of the mechanism a config describes (no ROS master).
//   analyze --config FILE [--torque NM | --q1 RAD] [--equilibria] [--json]
// The static equilibrium under a constant crank torque (or the crank held at q1 by its holding
// moment), the state-space model about it (x = (q1, q2, u1, u2): x' = A x + B M_m, exact
// derivatives), its eigenvalues, natural frequencies, damping ratios and mode shapes, or
// (--equilibria) every equilibrium around the turn under the torque, stable or not.
// Exit codes: 0 ok, 1 bad config, 2 bad command line, 3 no equilibrium, 4 stdout unwritable.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <boost/program_options.hpp>

#include "kane_sim/analysis/analysis_json.h"
#include "kane_sim/analysis/linear_analysis.h"
#include "kane_sim/cli/number_argument.h"
#include "kane_sim/cli/tool_config.h"
#include "kane_sim/config/load_config.h"
#include "kane_sim/format_number.h"

namespace po = boost::program_options;

namespace {

constexpr int kExitConfig = 1;
constexpr int kExitUsage = 2;
constexpr int kExitNoEquilibrium = 3;
constexpr int kExitOutput = 4;

struct Analysis {
  kane_sim::LinearModel linear;
  kane_sim::ModalAnalysis modal;
};

void printJson(const Analysis& a) { std::cout << kane_sim::analysisJson(a.linear, a.modal); }

// --equilibria: one line each (text) or one JSON array.
void printEquilibria(const std::vector<kane_sim::Equilibrium>& found, double torque, bool json) {
  if (json) {
    std::cout << "[";
    for (size_t i = 0; i < found.size(); ++i)
      std::cout << (i ? ",\n " : "") << "{\"q1\": " << kane_sim::formatNumber(found[i].state.q1)
                << ", \"q2\": " << kane_sim::formatNumber(found[i].state.q2)
                << ", \"stability\": \"" << found[i].stability
                << "\", \"largest_real_eigenvalue\": "
                << kane_sim::formatNumber(found[i].largest_real_eigenvalue) << "}";
    std::cout << "]\n";
    return;
  }
  std::printf("Equilibria under M_m = %g N m (u = 0), q1 in (-pi, pi]:\n", torque);
  if (found.empty()) std::printf("  none found: the torque turns the crank over\n");
  for (const kane_sim::Equilibrium& e : found)
    std::printf(
        "  q1 = % .12g rad (% .6g deg), q2 = %.12g m: %s (largest real part of A's "
        "eigenvalues % .6g 1/s)\n",
        e.state.q1 + 0.0, e.state.q1 * 180 / M_PI + 0.0, e.state.q2 + 0.0, e.stability.c_str(),
        e.largest_real_eigenvalue + 0.0);
}

void printText(const Analysis& a) {
  const kane_sim::LinearModel& l = a.linear;
  std::printf("Static equilibrium under M_m = %g N m (u = 0), %s:\n", l.torque,
              a.modal.stability.c_str());
  std::printf("  q1 = %.12g rad (%.6g deg), q2 = %.12g m\n\n", l.operating_point.q1 + 0.0,
              l.operating_point.q1 * 180 / M_PI + 0.0, l.operating_point.q2 + 0.0);
  std::printf("Linear model x' = A x + B M_m, x = (q1, q2, u1, u2):\n");
  for (int r = 0; r < 4; ++r)
    std::printf("  A[%d] = [% .9e % .9e % .9e % .9e]   B[%d] = % .9e\n", r, l.A(r, 0), l.A(r, 1),
                l.A(r, 2), l.A(r, 3), r, l.B[r]);
  std::printf("\nEigenvalues of A [1/s]:\n");
  for (const auto& lambda : a.modal.eigenvalues)
    std::printf("  % .9e %+.9e i\n", lambda.real(), lambda.imag());
  if (a.modal.stability == "unstable")
    std::printf(
        "\nUnstable: an eigenvalue of A has a positive real part; no natural frequencies.\n");
  else
    std::printf("\nModes (undamped natural frequency; damping ratio; shape (q1 rad, q2 m)):\n");
  for (size_t i = 0; i < a.modal.modes.size(); ++i) {
    const kane_sim::Mode& m = a.modal.modes[i];
    if (m.neutral) {
      std::printf(
          "  %zu: neutral (no restoring stiffness along this shape: frequency 0, no damping "
          "ratio), shape (% .6g, % .6g)\n",
          i + 1, m.shape[0], m.shape[1]);
      continue;
    }
    char zeta[64] = "undefined";
    if (std::isfinite(m.damping_ratio)) std::snprintf(zeta, sizeof zeta, "%.6g", m.damping_ratio);
    std::printf("  %zu: %.9g Hz (%.9g rad/s), zeta %s, shape (% .6g, % .6g)\n", i + 1,
                m.natural_frequency_hz, 2 * M_PI * m.natural_frequency_hz, zeta, m.shape[0],
                m.shape[1]);
  }
  // What the linear model leaves out (the JSON's "notes" too).
  for (const std::string& note : l.notes) std::printf("\nNote: %s.\n", note.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  po::options_description desc(
      "Usage: analyze [--config FILE] [--torque NM | --q1 RAD] [--equilibria] [--json]\n\n"
      "Linear analysis of the textbook example's mechanism: the stable static equilibrium under a\n"
      "constant crank torque M_m (|q1| < pi/2), or the crank held at any angle q1 by the moment\n"
      "that holds it (--q1 pi: upright, unstable), the state-space model about it (x = (q1, q2,\n"
      "u1, u2), x' = A x + B M_m), its eigenvalues, undamped natural frequencies, damping ratios\n"
      "and mode shapes. --equilibria lists every equilibrium around the turn under the torque,\n"
      "stable or not. Derivatives: exact (the generated equations differentiated symbolically).\n"
      "\nOptions");
  desc.add_options()("help,h", "print this help and exit")(
      "config", po::value<std::string>(),
      "mechanism YAML (default: the package's config/mechanism.yaml)")(
      "torque", po::value<double>()->default_value(0.0), "constant crank torque M_m [N m]")(
      "q1", po::value<std::string>(),
      "hold the crank at this angle [rad] (a number, pi or -pi; instead of --torque)")(
      "equilibria", "list every equilibrium under --torque, stable or not")(
      "json", "print one JSON object instead of text");
  po::variables_map vm;
  try {
    // No positional arguments: a stray word is an error, not ignored.
    po::store(po::command_line_parser(argc, argv)
                  .options(desc)
                  .positional(po::positional_options_description())
                  .run(),
              vm);
    po::notify(vm);
  } catch (const po::error& e) {
    std::cerr << "analyze: " << e.what() << "\n" << desc << "\n";
    return kExitUsage;
  }
  if (vm.count("help")) {
    std::cout << desc << "\n";
    return 0;
  }
  const double torque = vm["torque"].as<double>();
  if (!std::isfinite(torque)) {
    std::cerr << "analyze: --torque must be finite, got " << torque << "\n";
    return kExitUsage;
  }
  const bool held = vm.count("q1") > 0;
  double q1 = 0.0;
  try {
    if (held) q1 = kane_sim::angleArgument(vm["q1"].as<std::string>(), "--q1");
  } catch (const std::invalid_argument& e) {
    std::cerr << "analyze: " << e.what() << "\n";
    return kExitUsage;
  }
  if (held && (!vm["torque"].defaulted() || vm.count("equilibria"))) {
    std::cerr << "analyze: --q1 holds the crank by its own moment: give --torque or --equilibria "
                 "without it\n";
    return kExitUsage;
  }
  kane_sim::cli::ToolConfig loaded;
  try {
    loaded = kane_sim::cli::loadToolConfig(
        "analyze",
        vm.count("config") ? std::optional(vm["config"].as<std::string>()) : std::nullopt);
  } catch (const kane_sim::cli::ToolConfigError& e) {
    std::cerr << e.what() << "\n";
    return kExitConfig;
  }
  try {
    const kane_sim::MechanismModel model = kane_sim::mechanismModel(loaded.loaded.config);
    if (vm.count("equilibria")) {
      printEquilibria(kane_sim::equilibria(model, torque), torque, vm.count("json") > 0);
    } else {
      Analysis a;
      if (held) {
        const kane_sim::HeldEquilibrium at = kane_sim::equilibriumAt(model, q1);
        a.linear = kane_sim::linearize(model, at.state, at.torque);
      } else {
        a.linear = kane_sim::linearize(model, kane_sim::staticEquilibrium(model, torque), torque);
      }
      a.modal = kane_sim::modalAnalysis(a.linear);
      vm.count("json") ? printJson(a) : printText(a);
    }
  } catch (const kane_sim::AnalysisError& e) {
    std::cerr << "analyze: " << e.what() << "\n";
    return kExitNoEquilibrium;
  }
  std::cout.flush();
  if (!std::cout || std::fflush(stdout) != 0) {
    std::cerr << "analyze: cannot write to stdout: " << std::strerror(errno) << "\n";
    return kExitOutput;
  }
  return 0;
}
