// `design`: controllers designed from the mechanism's model (no ROS master).
//   design lqr --config FILE --q1 RAD [--Q Q1,Q2,Q3,Q4] [--R R] [--out FILE]
// LQR about the crank held at rest at q1 (q1 = pi: upright): the holding moment, the exact
// linearization, the gain K of M_m = M_eq - K (x - x_eq), the open- and closed-loop eigenvalues;
// --out writes the law as YAML for a controller (design/lqr_file.h).
// Exit codes: 0 ok, 1 bad config, 2 bad command line, 3 no design (no equilibrium, no gain),
// 4 the output cannot be written.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <boost/program_options.hpp>

#include "kane_sim/cli/number_argument.h"
#include "kane_sim/config/load_config.h"
#include "kane_sim/design/lqr.h"
#include "kane_sim/design/lqr_file.h"
#include "kane_sim/design/riccati.h"

namespace po = boost::program_options;

namespace {

constexpr int kExitConfig = 1;
constexpr int kExitUsage = 2;
constexpr int kExitNoDesign = 3;
constexpr int kExitOutput = 4;

struct UsageError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

double number(const std::string& text, const std::string& flag) {
  try {
    return kane_sim::numberArgument(text, flag);
  } catch (const std::invalid_argument& e) {
    throw UsageError(e.what());
  }
}

// Every weight named by its place when it is refused.
Eigen::Vector4d parseWeights(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) items.push_back(item);
  if (items.size() != 4 || text.empty() || text.back() == ',')
    throw UsageError("--Q takes 4 weights Q1,Q2,Q3,Q4 (the diagonal on q1, q2, u1, u2), got '" +
                     text + "'");
  Eigen::Vector4d values;
  const char* names[] = {"q1", "q2", "u1", "u2"};
  for (int i = 0; i < 4; ++i) {
    const std::string flag = std::string("--Q's weight on ") + names[i];
    values[i] = number(items[static_cast<size_t>(i)], flag);
    if (values[i] < 0)
      throw UsageError(flag + " must be >= 0, got '" + items[static_cast<size_t>(i)] + "'");
  }
  return values;
}

void printComplex(const char* title, const std::vector<std::complex<double>>& values) {
  std::printf("%s\n", title);
  for (const auto& v : values) std::printf("  % .9e %+.9e i\n", v.real(), v.imag());
}

void printDesign(const kane_sim::LqrDesign& d) {
  const kane_sim::State& x = d.equilibrium.state;
  std::printf("Equilibrium: crank held at q1 = %.12g rad (%.6g deg), slider 4 at q2 = %.12g m,\n",
              x.q1 + 0.0, x.q1 * 180 / M_PI + 0.0, x.q2 + 0.0);
  std::printf("  by the holding moment M_eq = %.12g N m\n\n", d.equilibrium.torque + 0.0);
  std::printf("LQR: M_m = M_eq - K (x - x_eq), x = (q1, q2, u1, u2)\n");
  std::printf("  Q = diag(%g, %g, %g, %g), R = %g\n", d.weights.Q(0, 0), d.weights.Q(1, 1),
              d.weights.Q(2, 2), d.weights.Q(3, 3), d.weights.R);
  std::printf("  K = [% .9e % .9e % .9e % .9e]\n", d.feedback.K[0] + 0.0, d.feedback.K[1] + 0.0,
              d.feedback.K[2] + 0.0, d.feedback.K[3] + 0.0);
  std::printf("  Riccati residual %.2e (relative)\n\n", d.riccati_residual);
  printComplex("Open-loop eigenvalues of A [1/s]:", d.open_loop);
  printComplex("Closed-loop eigenvalues of A - B K [1/s]:", d.closed_loop);
  std::printf(
      "\nSampled, the law needs readings at about %.0f Hz or more (5 x the fastest "
      "|eigenvalue|); for a slower loop raise --R.\n",
      d.sample_rate_needed);
  for (const std::string& note : d.notes) std::printf("\nNote: %s.\n", note.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  po::options_description desc(
      "Usage: design lqr [--config FILE] --q1 RAD [--Q Q1,Q2,Q3,Q4] [--R R] [--out FILE]\n\n"
      "Controllers designed from the textbook example's mechanism. lqr: the crank held at rest\n"
      "at q1 (pi: upright, unstable) by its holding moment, the exact linearization there, and\n"
      "the LQR gain K of M_m = M_eq - K (x - x_eq), x = (q1, q2, u1, u2). Default weights by\n"
      "Bryson's rule: 1/0.1^2, 1/0.01^2, 1, 1/0.1^2 on the state; 1/torque_limit^2 on M_m.\n\n"
      "Options");
  desc.add_options()("help,h", "print this help and exit")(
      "config", po::value<std::string>(),
      "mechanism YAML (default: the package's config/mechanism.yaml)")(
      "q1", po::value<std::string>(), "crank angle to hold [rad] (a number, pi or -pi)")(
      "Q", po::value<std::string>(), "state weights, the diagonal on q1, q2, u1, u2")(
      "R", po::value<std::string>(), "torque weight (> 0)")(
      "out", po::value<std::string>(), "write the law as YAML to FILE (- for stdout)");
  po::positional_options_description positional;
  positional.add("method", 1);
  po::options_description hidden;
  hidden.add_options()("method", po::value<std::string>());
  po::options_description all;
  all.add(desc).add(hidden);
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(argc, argv).options(all).positional(positional).run(), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    std::cerr << "design: " << e.what() << "\n" << desc << "\n";
    return kExitUsage;
  }
  if (vm.count("help")) {
    std::cout << desc << "\n";
    return 0;
  }
  kane_sim::LqrWeights weights;
  double q1 = 0.0;
  std::optional<double> r_weight;
  std::optional<Eigen::Vector4d> q_weights;
  try {
    if (!vm.count("method")) throw UsageError("name the method: design lqr ...");
    if (vm["method"].as<std::string>() != "lqr")
      throw UsageError("the method must be lqr, got '" + vm["method"].as<std::string>() + "'");
    if (!vm.count("q1")) throw UsageError("--q1 is required: the crank angle to hold [rad]");
    try {
      q1 = kane_sim::angleArgument(vm["q1"].as<std::string>(), "--q1");
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
    if (vm.count("Q")) q_weights = parseWeights(vm["Q"].as<std::string>());
    if (vm.count("R")) {
      r_weight = number(vm["R"].as<std::string>(), "--R");
      if (!(*r_weight > 0)) throw UsageError("--R must be > 0, got " + vm["R"].as<std::string>());
    }
  } catch (const UsageError& e) {
    std::cerr << "design: " << e.what() << "\n" << desc << "\n";
    return kExitUsage;
  }
  std::string config_path;
  if (vm.count("config")) {
    config_path = vm["config"].as<std::string>();
  } else {
    try {
      config_path = kane_sim::defaultConfigFile();
    } catch (const kane_sim::ConfigError& e) {
      std::cerr << "design: no --config given and " << e.what() << "\n";
      return kExitConfig;
    }
    std::cerr << "design: no --config given: using the package's default " << config_path << "\n";
  }
  kane_sim::LoadedConfig loaded;
  try {
    loaded = kane_sim::loadConfigFile(config_path);
  } catch (const kane_sim::ConfigError& e) {
    std::cerr << "design: bad config: " << e.what() << "\n";
    return kExitConfig;
  }
  for (const std::string& warning : loaded.warnings) std::cerr << "design: " << warning << "\n";
  try {
    const kane_sim::MechanismModel model = kane_sim::mechanismModel(loaded.config);
    weights = kane_sim::defaultLqrWeights(loaded.config, model);
    if (q_weights) weights.Q = q_weights->asDiagonal();
    if (r_weight) weights.R = *r_weight;
    const kane_sim::LqrDesign design = kane_sim::designLqr(model, q1, weights);
    const bool yaml_to_stdout = vm.count("out") && vm["out"].as<std::string>() == "-";
    if (!yaml_to_stdout) printDesign(design);
    if (yaml_to_stdout) {
      kane_sim::writeLqrYaml(std::cout, design, config_path);
    } else if (vm.count("out")) {
      const std::string path = vm["out"].as<std::string>();
      std::error_code same_error;
      if (!path.empty() && std::filesystem::equivalent(path, config_path, same_error)) {
        std::cerr << "design: --out " << path << " is the config itself: name another file\n";
        return kExitUsage;
      }
      std::ofstream out(path);
      kane_sim::writeLqrYaml(out, design, config_path);
      if (!out.flush()) {
        std::cerr << "design: cannot write --out '" << path << "': " << std::strerror(errno)
                  << "\n";
        return kExitOutput;
      }
      std::printf("\nWrote the law to %s\n", path.c_str());
    }
    std::cout.flush();
    if (!std::cout || std::fflush(stdout) != 0) {
      std::cerr << "design: cannot write to stdout: " << std::strerror(errno) << "\n";
      return kExitOutput;
    }
  } catch (const kane_sim::AnalysisError& e) {
    std::cerr << "design: " << e.what() << "\n";
    return kExitNoDesign;
  } catch (const kane_sim::RiccatiError& e) {
    std::cerr << "design: LQR at q1 = " << q1 << " rad: " << e.what() << "\n";
    return kExitNoDesign;
  }
  return 0;
}
