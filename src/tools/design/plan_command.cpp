// design plan: the optimal move from a start to the crank held at rest at --to, by direct
// collocation (plan/collocation.h), sampled on the controller's grid with its time-varying LQR
// gains; --out writes the plan CSV (design/plan_file.h). Progress on stderr; Ctrl-C stops IPOPT.
#include <atomic>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "design/design_cli.h"
#include "kane_sim/cli/tool_config.h"
#include "kane_sim/design/plan_file.h"
#include "kane_sim/design/riccati.h"
#include "kane_sim/format_number.h"
#include "kane_sim/plan/plan_design.h"

namespace kane_sim {
namespace design_cli {
namespace {

std::atomic<int> stop_signal{0};  // SIGINT or SIGTERM once asked to stop
void onStopSignal(int signal) { stop_signal = signal; }

// --from: "initial" (the config's initial state, where the simulator starts) or a crank angle to
// start held at rest from.
State startState(const boost::program_options::variables_map& vm, const Config& config,
                 const MechanismModel& model) {
  const std::string from = vm.count("from") ? vm["from"].as<std::string>() : "initial";
  if (from == "initial") return config.initial_state;
  return equilibriumAt(model, angle(from, "--from")).state;
}

CollocationProblem problemFrom(const boost::program_options::variables_map& vm,
                               const Config& config, const MechanismModel& model) {
  CollocationProblem p;
  if (!vm.count("to")) throw UsageError("--to is required: the crank angle to end held at [rad]");
  const double to = angle(vm["to"].as<std::string>(), "--to");
  const std::string objective = vm["objective"].as<std::string>();
  if (objective != "effort" && objective != "time")
    throw UsageError("--objective must be effort or time, got '" + objective + "'");
  p.objective = objective == "time" ? PlanObjective::kTime : PlanObjective::kEffort;
  p.duration = number(vm["duration"].as<std::string>(), "--duration");
  if (vm.count("max-duration"))
    p.max_duration = number(vm["max-duration"].as<std::string>(), "--max-duration");
  p.intervals = vm["intervals"].as<int>();
  p.max_iterations = vm["max-iterations"].as<int>();
  p.torque_limit = vm.count("torque-limit")
                       ? number(vm["torque-limit"].as<std::string>(), "--torque-limit")
                       : config.command.torque_limit;
  if (p.torque_limit > config.command.torque_limit)
    throw UsageError("--torque-limit " + formatNumber(p.torque_limit) +
                     " N m is beyond the drive's command.torque_limit " +
                     formatNumber(config.command.torque_limit) + " N m");
  if (vm.count("q2-range")) {
    const auto [lo, hi] = numberPair(vm["q2-range"].as<std::string>(), "--q2-range");
    p.q2_min = lo;
    p.q2_max = hi;
  }
  if (vm.count("gap"))
    p.gap = number(vm["gap"].as<std::string>(), "--gap");
  else if (config.mechanism.contact.enabled)
    p.gap = config.mechanism.contact.gap;
  p.start = startState(vm, config, model);
  p.goal = equilibriumAt(model, to).state;
  try {
    checkCollocationProblem(p);
  } catch (const PlanningError& e) {
    throw UsageError(e.what());
  }
  return p;
}

// Where --out FILE goes while the plan is made: FILE.partial, opened before IPOPT runs (a path
// that cannot be written is said at once) and renamed to FILE when the plan is whole.
struct PartialOut {
  std::string path, partial;
  std::ofstream out;
  ~PartialOut() {
    if (!partial.empty()) std::remove(partial.c_str());
  }
  void finish() {
    out.close();
    if (std::rename(partial.c_str(), path.c_str()) != 0)
      throw std::runtime_error(std::strerror(errno));
    partial.clear();
  }
};

void printPlan(const PlanDesign& d, double torque_limit) {
  const CollocationSolution& s = d.solution;
  double peak = 0.0;
  for (double torque : s.torque) peak = std::max(peak, std::abs(torque));
  const auto& a = s.x.front();
  const auto& b = s.x.back();
  std::printf("Plan: from q1 = %.9g rad, q2 = %.9g m, u1 = %.9g rad/s, u2 = %.9g m/s\n", a[0] + 0.0,
              a[1] + 0.0, a[2] + 0.0, a[3] + 0.0);
  std::printf("  to the crank held at q1 = %.9g rad, q2 = %.9g m, by M_eq = %.9g N m\n", b[0] + 0.0,
              b[1] + 0.0, d.goal_lqr.equilibrium.torque + 0.0);
  std::printf("IPOPT: %s in %d iterations (from a first guess of %d swings)\n", s.status.c_str(),
              s.iterations, s.guess_swings);
  std::printf("  duration %.9g s, %zu intervals (Hermite-Simpson), largest defect %.2e\n",
              s.duration, (s.time.size() - 1) / 2, s.max_defect);
  std::printf(
      "  effort (integral of M_m^2) %.9g N^2 m^2 s, peak |M_m| %.6g N m of %.6g\n",
      [&] {
        double sum = 0.0;
        const double h = s.duration / ((s.time.size() - 1) / 2);
        for (size_t i = 0; i + 2 < s.torque.size(); i += 2)
          sum += h / 6 *
                 (s.torque[i] * s.torque[i] + 4 * s.torque[i + 1] * s.torque[i + 1] +
                  s.torque[i + 2] * s.torque[i + 2]);
        return sum;
      }(),
      peak, torque_limit);
  std::printf("Rows: %zu, every %.6g s; then the goal's LQR K = [%.6g %.6g %.6g %.6g]\n",
              d.plan.points.size(), d.plan.step, d.goal_lqr.feedback.K[0], d.goal_lqr.feedback.K[1],
              d.goal_lqr.feedback.K[2], d.goal_lqr.feedback.K[3]);
}

std::string commandLine(const boost::program_options::variables_map& vm) {
  std::ostringstream out;
  out << "kane_sim plan: design plan";
  for (const char* flag : {"config", "from", "to", "objective", "duration", "max-duration",
                           "intervals", "torque-limit", "q2-range", "gap", "rate", "Q", "R"})
    if (vm.count(flag) && !vm[flag].defaulted()) {
      out << " --" << flag << " ";
      const auto& value = vm[flag].value();
      if (value.type() == typeid(int))
        out << vm[flag].as<int>();
      else
        out << vm[flag].as<std::string>();
    }
  return out.str();
}

}  // namespace

int runPlan(const boost::program_options::variables_map& vm) {
  const cli::ToolConfig tool = cli::loadToolConfig(
      "design", vm.count("config") ? std::optional(vm["config"].as<std::string>()) : std::nullopt);
  const Config& config = tool.loaded.config;
  const MechanismModel model = mechanismModel(config);
  const double rate = vm.count("rate") ? number(vm["rate"].as<std::string>(), "--rate")
                                       : config.simulation.physics_rate;
  std::signal(SIGINT, onStopSignal);
  std::signal(SIGTERM, onStopSignal);
  const auto stopped = [] {
    std::cerr << "design: stopped by " << (stop_signal == SIGTERM ? "SIGTERM" : "Ctrl-C (SIGINT)")
              << ": no plan written\n";
    return stop_signal == SIGTERM ? kExitTerminated : kExitInterrupted;
  };
  PlanDesign design;
  try {
    const CollocationProblem problem = problemFrom(vm, config, model);
    const LqrWeights weights = weightsFrom(vm, config, model);
    const std::string rate_problem = planRateProblem(problem, rate);
    if (!rate_problem.empty()) throw UsageError(rate_problem);
    PartialOut file;
    if (vm.count("out") && vm["out"].as<std::string>() != "-") {
      file.path = vm["out"].as<std::string>();
      std::error_code same_error;
      if (std::filesystem::equivalent(file.path, tool.path, same_error))
        throw UsageError("--out " + file.path + " is the config itself: name another file");
      file.partial = file.path + ".partial";
      file.out.open(file.partial);
      if (!file.out) {
        std::cerr << "design: cannot write --out '" << file.path << "' (" << file.partial
                  << "): " << std::strerror(errno) << "\n";
        file.partial.clear();
        return kExitOutput;
      }
    }
    design = designPlan(
        model, problem, rate, weights,
        [](const CollocationProgress& p) {
          if (p.iteration % 25 == 0)
            std::fprintf(stderr,
                         "design plan: guess of %d swings: iteration %d, objective %.6g, "
                         "infeasibility %.2e\n",
                         p.swings, p.iteration, p.objective, p.infeasibility);
        },
        [] { return stop_signal.load() != 0; });
    if (stop_signal) return stopped();  // asked while the rows and gains were made
    const bool csv_to_stdout = vm.count("out") && vm["out"].as<std::string>() == "-";
    if (!csv_to_stdout) printPlan(design, problem.torque_limit);
    const std::vector<std::string> notes = {
        commandLine(vm), "mechanism: " + tool.path,
        "columns: t [s], the state q1 [rad], q2 [m], u1 [rad/s], u2 [m/s], the torque M_m [N m] "
        "held to the next row, the gain K of M_m = M_m(t) - K (x - x(t))"};
    if (csv_to_stdout) writePlanCsv(std::cout, design.plan, config, notes);
    if (!file.partial.empty()) {
      writePlanCsv(file.out, design.plan, config, notes);
      if (stop_signal) return stopped();
      file.out.flush();
      if (!file.out) {
        std::cerr << "design: cannot write --out '" << file.path << "': " << std::strerror(errno)
                  << "\n";
        return kExitOutput;
      }
      try {
        file.finish();
      } catch (const std::runtime_error& e) {
        std::cerr << "design: cannot rename " << file.partial << " to " << file.path << ": "
                  << e.what() << "\n";
        return kExitOutput;
      }
      std::printf("\nWrote the plan to %s\n", file.path.c_str());
    }
  } catch (const PlanningError& e) {
    if (stop_signal) return stopped();
    std::cerr << "design: no plan: " << e.what() << "\n";
    return kExitNoDesign;
  } catch (const AnalysisError& e) {
    std::cerr << "design: " << e.what() << "\n";
    return kExitNoDesign;
  } catch (const RiccatiError& e) {
    std::cerr << "design: the plan's LQR: " << e.what() << "\n";
    return kExitNoDesign;
  }
  return flushStdout();
}

}  // namespace design_cli
}  // namespace kane_sim
