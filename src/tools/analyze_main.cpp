// `analyze`: linear analysis of the mechanism a config describes (no ROS master).
//   analyze --config FILE [--torque NM] [--json]
// The static equilibrium under a constant crank torque, the state-space model about it
// (x = (q1, q2, u1, u2): x' = A x + B M_m), its eigenvalues, natural frequencies, damping
// ratios and mode shapes. Exit codes: 0 ok, 1 bad config, 2 bad command line, 3 no equilibrium.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <boost/program_options.hpp>

#include "kane_sim/analysis/linear_analysis.h"
#include "kane_sim/config/load_config.h"
#include "kane_sim/format_number.h"

namespace po = boost::program_options;

namespace {

constexpr int kExitConfig = 1;
constexpr int kExitUsage = 2;
constexpr int kExitNoEquilibrium = 3;

struct Analysis {
  kane_sim::LinearModel linear;
  kane_sim::ModalAnalysis modal;
};

// JSON numbers: the shortest exact form; JSON has no NaN or infinity, so a non-finite value is
// null and `notes` says which and why.
class JsonNumbers {
 public:
  std::string operator()(double value, const std::string& what) {
    if (!std::isfinite(value)) {
      notes_.push_back(what + " is " + (std::isnan(value) ? "undefined" : "infinite") + " (null)");
      return "null";
    }
    return kane_sim::formatNumber(value);
  }
  std::string row(const Eigen::VectorXd& v, const std::string& what) {
    std::string out = "[";
    for (Eigen::Index i = 0; i < v.size(); ++i)
      out += (i ? ", " : "") + (*this)(v[i], what + "[" + std::to_string(i) + "]");
    return out + "]";
  }
  void note(const std::string& text) { notes_.push_back(text); }
  std::string notes() const {
    std::string out = "[";
    for (size_t i = 0; i < notes_.size(); ++i) out += (i ? ", \"" : "\"") + notes_[i] + "\"";
    return out + "]";
  }

 private:
  std::vector<std::string> notes_;  // plain text: no quotes or backslashes are written into them
};

void printJson(const Analysis& a) {
  const kane_sim::LinearModel& l = a.linear;
  JsonNumbers number;
  const auto jsonRow = [&number](const Eigen::VectorXd& v, const std::string& what) {
    return number.row(v, what);
  };
  std::ostringstream out;
  out << "{\n  \"torque\": " << number(l.torque, "torque") << ",\n";
  out << "  \"equilibrium\": {\"q1\": " << number(l.operating_point.q1, "equilibrium q1")
      << ", \"q2\": " << number(l.operating_point.q2, "equilibrium q2") << "},\n";
  out << "  \"state\": [\"q1\", \"q2\", \"u1\", \"u2\"],\n  \"A\": [";
  for (int r = 0; r < 4; ++r)
    out << (r ? ",\n        " : "")
        << jsonRow(l.A.row(r).transpose(), "A[" + std::to_string(r) + "]");
  out << "],\n  \"B\": " << jsonRow(l.B, "B") << ",\n  \"eigenvalues\": [";
  for (size_t i = 0; i < a.modal.eigenvalues.size(); ++i)
    out << (i ? ", " : "") << "[" << number(a.modal.eigenvalues[i].real(), "an eigenvalue") << ", "
        << number(a.modal.eigenvalues[i].imag(), "an eigenvalue") << "]";
  std::string frequencies, ratios, shapes, neutral;
  for (size_t i = 0; i < a.modal.modes.size(); ++i) {
    const kane_sim::Mode& m = a.modal.modes[i];
    const std::string sep = i ? ", " : "";
    const std::string name = "mode " + std::to_string(i + 1);
    frequencies += sep + number(m.natural_frequency_hz, name + "'s frequency");
    if (m.neutral) {
      number.note(name +
                  " is neutral: no restoring stiffness along its shape, frequency 0, no "
                  "damping ratio");
      ratios += sep + "null";
    } else {
      ratios += sep + number(m.damping_ratio, name + "'s damping ratio");
    }
    shapes += sep + jsonRow(m.shape, name + "'s shape");
    neutral += sep + (m.neutral ? "true" : "false");
  }
  out << "],\n  \"natural_frequencies_hz\": [" << frequencies << "],\n  \"damping_ratios\": ["
      << ratios << "],\n  \"neutral\": [" << neutral << "],\n  \"mode_shapes\": [" << shapes
      << "],\n  \"notes\": " << number.notes() << "\n}\n";
  std::cout << out.str();
}

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
