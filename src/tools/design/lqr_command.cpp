// design lqr: the crank held at rest at q1 by its holding moment, the exact linearization there,
// the LQR gain, the eigenvalues; --out writes the law as YAML (design/lqr_file.h).
#include <cmath>
#include <complex>
#include <cstdio>
#include <iostream>
#include <vector>

#include "design/design_cli.h"
#include "kane_sim/cli/tool_config.h"
#include "kane_sim/design/lqr_file.h"
#include "kane_sim/design/riccati.h"

namespace kane_sim {
namespace design_cli {
namespace {

void printComplex(const char* title, const std::vector<std::complex<double>>& values) {
  std::printf("%s\n", title);
  for (const auto& v : values) std::printf("  % .9e %+.9e i\n", v.real(), v.imag());
}

void printDesign(const LqrDesign& d) {
  const State& x = d.equilibrium.state;
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

int runLqr(const boost::program_options::variables_map& vm) {
  if (!vm.count("q1")) throw UsageError("--q1 is required: the crank angle to hold [rad]");
  const double q1 = angle(vm["q1"].as<std::string>(), "--q1");
  const cli::ToolConfig config = cli::loadToolConfig(
      "design", vm.count("config") ? std::optional(vm["config"].as<std::string>()) : std::nullopt);
  try {
    const MechanismModel model = mechanismModel(config.loaded.config);
    const LqrWeights weights = weightsFrom(vm, config.loaded.config, model);
    const LqrDesign design = designLqr(model, q1, weights);
    const bool yaml_to_stdout = vm.count("out") && vm["out"].as<std::string>() == "-";
    if (!yaml_to_stdout) printDesign(design);
    if (vm.count("out")) {
      const int code = writeOut(vm, config.path, "the law",
                                [&](std::ostream& out) { writeLqrYaml(out, design, config.path); });
      if (code != 0) return code;
    }
  } catch (const AnalysisError& e) {
    std::cerr << "design: " << e.what() << "\n";
    return kExitNoDesign;
  } catch (const RiccatiError& e) {
    std::cerr << "design: LQR at q1 = " << q1 << " rad: " << e.what() << "\n";
    return kExitNoDesign;
  }
  return flushStdout();
}

}  // namespace design_cli
}  // namespace kane_sim
