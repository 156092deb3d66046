// kane_sim._core's controller design (`design lqr`'s library): the gain and what it was made
// from, as NumPy arrays (kane_sim.control wraps it).
#include <complex>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "kane_sim/design/lqr.h"
#include "kane_sim/design/lqr_file.h"
#include "kane_sim/design/plan_file.h"
#include "kane_sim/design/plan_follower.h"
#include "kane_sim/design/riccati.h"
#include "kane_sim/format_number.h"
#include "kane_sim/plan/plan_design.h"
#include "kane_sim/sim/closed_loop.h"
#include "python_layer.h"

namespace kane_sim {
namespace python {
namespace {

Eigen::MatrixXd eigenvalueRows(const std::vector<std::complex<double>>& values) {
  Eigen::MatrixXd rows(static_cast<Eigen::Index>(values.size()), 2);
  for (size_t i = 0; i < values.size(); ++i)
    rows.row(static_cast<Eigen::Index>(i)) << values[i].real(), values[i].imag();
  return rows;
}

// Q: None (Bryson's rule), 4 numbers (the diagonal) or a 4 x 4 matrix; R: None or a number.
LqrWeights weightsFrom(const char* what, const Config& config, const MechanismModel& model,
                       const std::optional<Eigen::MatrixXd>& Q, const std::optional<double>& R) {
  LqrWeights weights = defaultLqrWeights(config, model);
  if (Q) {
    if (Q->size() == 4 && (Q->rows() == 1 || Q->cols() == 1))
      weights.Q = Eigen::Vector4d(Q->data()).asDiagonal();
    else if (Q->rows() == 4 && Q->cols() == 4)
      weights.Q = *Q;
    else
      throw py::value_error(std::string(what) +
                            ": Q must be 4 numbers (the diagonal on q1, q2, u1, u2) or a 4 x 4 "
                            "matrix, got " +
                            std::to_string(Q->rows()) + " x " + std::to_string(Q->cols()));
  }
  if (R) {
    if (!(std::isfinite(*R) && *R > 0))
      throw py::value_error(std::string(what) + ": R must be a finite number > 0, got " +
                            formatNumber(*R));
    weights.R = *R;
  }
  return weights;
}

py::dict lqr(const PythonConfig& config, double q1, const std::optional<Eigen::MatrixXd>& Q,
             const std::optional<double>& R) {
  const MechanismModel model = mechanismModel(config.config());
  const LqrWeights weights = weightsFrom("lqr", config.config(), model, Q, R);
  LqrDesign d;
  try {
    py::gil_scoped_release release;
    d = designLqr(model, q1, weights);
  } catch (const AnalysisError& e) {
    throw py::value_error(std::string("lqr: ") + e.what());
  } catch (const RiccatiError& e) {
    throw py::value_error(std::string("lqr: ") + e.what());
  }
  py::dict out;
  out["K"] = Eigen::RowVector4d(d.feedback.K);
  out["state"] = Eigen::Vector4d(d.feedback.state);
  out["torque"] = d.feedback.torque;
  out["periodic"] = d.feedback.periodic;
  out["Q"] = Eigen::Matrix4d(d.weights.Q);
  out["R"] = d.weights.R;
  out["A"] = Eigen::Matrix4d(d.A);
  out["B"] = Eigen::Vector4d(d.B);
  out["P"] = Eigen::Matrix4d(d.P);
  out["open_loop"] = eigenvalueRows(d.open_loop);
  out["closed_loop"] = eigenvalueRows(d.closed_loop);
  out["riccati_residual"] = d.riccati_residual;
  out["controllable_basis"] = d.controllable_basis;
  out["notes"] = d.notes;
  out["sample_rate_needed"] = d.sample_rate_needed;
  std::ostringstream yaml;
  writeLqrYaml(yaml, d, config.source());
  out["yaml"] = yaml.str();
  return out;
}

// The plan's rows as arrays: t (N), x (N x 4), torque (N), K (N x 4).
void planArrays(const Plan& plan, py::dict* out) {
  const Eigen::Index n = static_cast<Eigen::Index>(plan.points.size());
  Eigen::VectorXd t(n), torque(n);
  Eigen::MatrixXd x(n, 4), K(n, 4);
  for (Eigen::Index i = 0; i < n; ++i) {
    const PlanPoint& p = plan.points[static_cast<size_t>(i)];
    t[i] = p.t;
    x.row(i) = p.x.transpose();
    torque[i] = p.torque;
    K.row(i) = p.K;
  }
  (*out)["t"] = t;
  (*out)["x"] = x;
  (*out)["torque"] = torque;
  (*out)["K"] = K;
  (*out)["step"] = plan.step;
  (*out)["periodic"] = plan.periodic;
}

// design plan's work (plan/plan_design.h): the same problem from the same arguments.
py::dict plan(const PythonConfig& config, double to, const std::optional<double>& from,
              const std::string& objective, double duration, double max_duration, int intervals,
              const std::optional<double>& torque_limit,
              const std::optional<Eigen::Vector2d>& q2_range, const std::optional<double>& gap,
              const std::optional<double>& rate, const std::optional<Eigen::MatrixXd>& Q,
              const std::optional<double>& R, int max_iterations) {
  const Config& c = config.config();
  const MechanismModel model = mechanismModel(c);
  const LqrWeights weights = weightsFrom("plan", c, model, Q, R);
  if (objective != "effort" && objective != "time")
    throw py::value_error("plan: objective must be 'effort' or 'time', got '" + objective + "'");
  CollocationProblem p;
  p.objective = objective == "time" ? PlanObjective::kTime : PlanObjective::kEffort;
  p.duration = duration;
  p.max_duration = max_duration;
  p.intervals = intervals;
  p.max_iterations = max_iterations;
  p.torque_limit = torque_limit ? *torque_limit : c.command.torque_limit;
  if (p.torque_limit > c.command.torque_limit)
    throw py::value_error("plan: torque_limit " + formatNumber(p.torque_limit) +
                          " N m is beyond the drive's command.torque_limit " +
                          formatNumber(c.command.torque_limit) + " N m");
  if (q2_range) {
    p.q2_min = (*q2_range)[0];
    p.q2_max = (*q2_range)[1];
  }
  if (gap)
    p.gap = *gap;
  else if (c.mechanism.contact.enabled)
    p.gap = c.mechanism.contact.gap;
  const std::string rate_problem = planRateProblem(p, rate ? *rate : c.simulation.physics_rate);
  if (!rate_problem.empty()) throw py::value_error("plan: " + rate_problem);
  PlanDesign d;
  try {
    p.start = from ? equilibriumAt(model, *from).state : c.initial_state;
    p.goal = equilibriumAt(model, to).state;
    py::gil_scoped_release release;
    d = designPlan(model, p, rate ? *rate : c.simulation.physics_rate, weights, {}, [] {
      py::gil_scoped_acquire acquire;
      return PyErr_CheckSignals() != 0;  // Ctrl-C stops IPOPT
    });
  } catch (const PlanningError& e) {
    if (PyErr_Occurred()) throw py::error_already_set();
    throw py::value_error(std::string("plan: ") + e.what());
  } catch (const AnalysisError& e) {
    throw py::value_error(std::string("plan: ") + e.what());
  } catch (const RiccatiError& e) {
    throw py::value_error(std::string("plan: ") + e.what());
  }
  py::dict out;
  planArrays(d.plan, &out);
  const CollocationSolution& s = d.solution;
  out["duration"] = s.duration;
  out["effort"] = [&] {
    double sum = 0.0;
    const double h = s.duration / static_cast<double>((s.time.size() - 1) / 2);
    for (size_t i = 0; i + 2 < s.torque.size(); i += 2)
      sum += h / 6 *
             (s.torque[i] * s.torque[i] + 4 * s.torque[i + 1] * s.torque[i + 1] +
              s.torque[i + 2] * s.torque[i + 2]);
    return sum;
  }();
  out["status"] = s.status;
  out["iterations"] = s.iterations;
  out["max_defect"] = s.max_defect;
  out["guess_swings"] = s.guess_swings;
  out["goal_K"] = Eigen::RowVector4d(d.goal_lqr.feedback.K);
  std::ostringstream csv;
  writePlanCsv(csv, d.plan, c,
               {"kane_sim plan: kane_sim.control.plan", "mechanism: " + config.source()});
  out["csv"] = csv.str();
  return out;
}

// The plan file followed in the loop (sim/closed_loop.h), as the tracking controller in lockstep
// runs it: the true state after every physics step.
py::dict follow(const PythonConfig& config, const std::string& plan_path, double duration,
                const std::optional<double>& torque_limit) {
  PlanFile file;
  try {
    file = readPlanCsv(plan_path);
  } catch (const PlanError& e) {
    throw py::value_error(std::string("follow: ") + e.what());
  }
  const Config& c = config.config();
  const std::string mismatch = planMismatch(file, c);
  if (!mismatch.empty())
    throw py::value_error("follow: the plan " + plan_path + " is not for this config: " + mismatch);
  // Every step is kept (48 bytes): at most 10 million of them (480 MB).
  const double longest = 1e7 / c.simulation.physics_rate;
  if (!(std::isfinite(duration) && duration > 0 && duration <= longest))
    throw py::value_error("follow: duration must be in (0, " + formatNumber(longest) +
                          "] s (10 million physics steps, each kept), got " +
                          formatNumber(duration));
  const double limit = torque_limit ? *torque_limit : c.command.torque_limit;
  if (!(limit > 0))
    throw py::value_error("follow: torque_limit must be > 0, got " + formatNumber(limit));
  SimDriver driver(c, {});
  PlanFollower follower(file.plan, limit);
  const size_t steps = static_cast<size_t>(std::llround(duration * c.simulation.physics_rate));
  Eigen::VectorXd t(static_cast<Eigen::Index>(steps + 1)), torque(t.size());
  Eigen::MatrixXd x(t.size(), 4);
  Eigen::Index row = 0;
  const auto record = [&](const SimDriver& d) {
    if (row >= t.size()) return false;
    const State& s = d.simulator().state();
    t[row] = d.time();
    x.row(row) << s.q1, s.q2, s.u1, s.u2;
    torque[row++] = d.simulator().torque();
    return true;
  };
  record(driver);
  {
    py::gil_scoped_release release;
    runClosedLoop(
        driver, duration,
        [&](std::int64_t stamp, const JointValues& reading) {
          return follower.command(stamp, stateFromJoints(reading));
        },
        [&](const SimDriver& d) {
          if (d.ticks() % 65536 == 0) {  // Ctrl-C: stop, raise KeyboardInterrupt
            py::gil_scoped_acquire acquire;
            if (PyErr_CheckSignals() != 0) return false;
          }
          return record(d);
        });
  }
  if (PyErr_Occurred()) throw py::error_already_set();
  py::dict out;
  out["t"] = t.head(row).eval();
  out["x"] = x.topRows(row).eval();
  out["torque"] = torque.head(row).eval();
  return out;
}

}  // namespace

void bindDesign(py::module_& m) {
  m.def("design_lqr", &lqr, py::arg("config"), py::arg("q1"), py::arg("Q") = py::none(),
        py::arg("R") = py::none());
  m.def("design_plan", &plan, py::arg("config"), py::arg("to"), py::arg("from_q1"),
        py::arg("objective"), py::arg("duration"), py::arg("max_duration"), py::arg("intervals"),
        py::arg("torque_limit"), py::arg("q2_range"), py::arg("gap"), py::arg("rate"), py::arg("Q"),
        py::arg("R"), py::arg("max_iterations"));
  m.def("follow_plan", &follow, py::arg("config"), py::arg("plan"), py::arg("duration"),
        py::arg("torque_limit") = py::none());
}

}  // namespace python
}  // namespace kane_sim
