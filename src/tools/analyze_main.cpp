// `analyze`: linear analysis of the mechanism a config describes (no ROS master).
//   analyze --config FILE [--torque NM] [--json]
// The static equilibrium under a constant crank torque, the state-space model about it
// (x = (q1, q2, u1, u2): x' = A x + B M_m), its eigenvalues, natural frequencies, damping
// ratios and mode shapes. Exit codes: 0 ok, 1 bad config, 2 bad command line, 3 no equilibrium.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

#include <boost/program_options.hpp>

#include "kane_sim/analysis/analysis_json.h"
#include "kane_sim/analysis/linear_analysis.h"
#include "kane_sim/config/load_config.h"

namespace po = boost::program_options;

namespace {

constexpr int kExitConfig = 1;
constexpr int kExitUsage = 2;
constexpr int kExitNoEquilibrium = 3;

struct Analysis {
  kane_sim::LinearModel linear;
  kane_sim::ModalAnalysis modal;
};

void printJson(const Analysis& a) { std::cout << kane_sim::analysisJson(a.linear, a.modal); }

void printText(const Analysis& a) {
  const kane_sim::LinearModel& l = a.linear;
  std::printf("Static equilibrium under M_m = %g N m (u = 0):\n", l.torque);
  std::printf("  q1 = %.12g rad (%.6g deg), q2 = %.12g m\n\n", l.operating_point.q1,
              l.operating_point.q1 * 180 / M_PI, l.operating_point.q2);
  std::printf("Linear model x' = A x + B M_m, x = (q1, q2, u1, u2):\n");
  for (int r = 0; r < 4; ++r)
    std::printf("  A[%d] = [% .9e % .9e % .9e % .9e]   B[%d] = % .9e\n", r, l.A(r, 0), l.A(r, 1),
                l.A(r, 2), l.A(r, 3), r, l.B[r]);
  std::printf("\nEigenvalues of A [1/s]:\n");
  for (const auto& lambda : a.modal.eigenvalues)
    std::printf("  % .9e %+.9e i\n", lambda.real(), lambda.imag());
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
      "Usage: analyze [--config FILE] [--torque NM] [--json]\n\n"
      "Linear analysis of the textbook example's mechanism: the stable static equilibrium under a\n"
      "constant crank torque M_m (|q1| < pi/2), the state-space model about it (x = (q1, q2, u1,\n"
      "u2), x' = A x + B M_m), its eigenvalues, undamped natural frequencies, damping ratios and\n"
      "mode shapes. Derivatives: 4th-order central differences of the simulator's own Kane\n"
      "equations (~1e-10 relative).\n\nOptions");
  desc.add_options()("help,h", "print this help and exit")(
      "config", po::value<std::string>(),
      "mechanism YAML (default: the package's config/mechanism.yaml)")(
      "torque", po::value<double>()->default_value(0.0), "constant crank torque M_m [N m]")(
      "json", "print one JSON object instead of text");
  po::variables_map vm;
  try {
    po::store(po::parse_command_line(argc, argv, desc), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    std::cerr << "analyze: " << e.what() << "\n" << desc << "\n";
    return kExitUsage;
  }
  if (vm.count("help")) {
    std::cout << desc << "\n";
    return 0;
  }
  std::string config_path;
  if (vm.count("config")) {
    config_path = vm["config"].as<std::string>();
  } else {
    try {
      config_path = kane_sim::defaultConfigFile();
    } catch (const kane_sim::ConfigError& e) {
      std::cerr << "analyze: no --config given and " << e.what() << "\n";
      return kExitConfig;
    }
    std::cerr << "analyze: no --config given: using the package's default " << config_path << "\n";
  }
  const double torque = vm["torque"].as<double>();
  if (!std::isfinite(torque)) {
    std::cerr << "analyze: --torque must be finite, got " << torque << "\n";
    return kExitUsage;
  }
  kane_sim::LoadedConfig loaded;
  try {
    loaded = kane_sim::loadConfigFile(config_path);
  } catch (const kane_sim::ConfigError& e) {
    std::cerr << "analyze: bad config: " << e.what() << "\n";
    return kExitConfig;
  }
  for (const std::string& warning : loaded.warnings) std::cerr << "analyze: " << warning << "\n";
  try {
    const kane_sim::MechanismModel model = kane_sim::mechanismModel(loaded.config);
    Analysis a;
    a.linear = kane_sim::linearize(model, kane_sim::staticEquilibrium(model, torque), torque);
    a.modal = kane_sim::modalAnalysis(a.linear);
    vm.count("json") ? printJson(a) : printText(a);
  } catch (const kane_sim::AnalysisError& e) {
    std::cerr << "analyze: " << e.what() << "\n";
    return kExitNoEquilibrium;
  }
  return 0;
}
