// kane_sim._core's analysis, sweeps and torque profiles: the libraries `analyze` and
// `simulate --sweep` run, results as JSON text (parsed in Python) and NumPy arrays.
#include <atomic>
#include <chrono>
#include <exception>
#include <fstream>
#include <future>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "kane_sim/analysis/analysis_json.h"
#include "kane_sim/analysis/linear_analysis.h"
#include "kane_sim/batch/lanes.h"
#include "kane_sim/config/input_file.h"
#include "kane_sim/format_number.h"
#include "kane_sim/sim/output_grid.h"
#include "kane_sim/sim/sweep.h"
#include "kane_sim/sim/torque_profile.h"
#include "python_layer.h"

namespace kane_sim {
namespace python {
namespace {

// analyze --json's object, as text (kane_sim.analyze parses it): under `torque`, or with the
// crank held at q1 by its holding moment (analyze --q1). AnalysisError (no equilibrium) is a
// ValueError with analyze's message.
std::string analyze(const PythonConfig& config, double torque, const std::optional<double>& q1) {
  if (!std::isfinite(torque))
    throw py::value_error("analyze: torque must be finite, got " + formatNumber(torque));
  py::gil_scoped_release release;
  try {
    const MechanismModel model = mechanismModel(config.config());
    LinearModel linear;
    if (q1) {
      const HeldEquilibrium at = equilibriumAt(model, *q1);
      linear = linearize(model, at.state, at.torque);
    } else {
      linear = linearize(model, staticEquilibrium(model, torque), torque);
    }
    return analysisJson(linear, modalAnalysis(linear));
  } catch (const AnalysisError& e) {
    py::gil_scoped_acquire acquire;
    throw py::value_error(std::string("analyze: ") + e.what());
  }
}

// analyze --equilibria: (q1, q2, stability, largest real eigenvalue) of each, ascending q1.
std::vector<py::tuple> equilibriaOf(const PythonConfig& config, double torque) {
  std::vector<Equilibrium> found;
  try {
    py::gil_scoped_release release;
    found = equilibria(mechanismModel(config.config()), torque);
  } catch (const AnalysisError& e) {
    throw py::value_error(std::string("equilibria: ") + e.what());
  }
  std::vector<py::tuple> out;
  for (const Equilibrium& e : found)
    out.push_back(py::make_tuple(e.state.q1, e.state.q2, e.stability, e.largest_real_eigenvalue));
  return out;
}

// runSweep on a thread of its own while this one, without the GIL, looks at Python's signals
// every 50 ms: a handler that raises (Ctrl-C) stops the running cases and starts no new one;
// that exception is handed back in `raised`.
std::vector<SweepResult> runSweepStoppable(const PythonConfig& config, const SweepPlan& plan,
                                           SweepSettings settings,
                                           std::unique_ptr<py::error_already_set>* raised) {
  std::atomic<bool> stop{false};
  settings.stop = &stop;
  std::vector<SweepResult> results;
  *raised = runStoppable(
      stop, [&] { results = runSweep(config.tree(), plan, settings); },
      std::chrono::milliseconds(50));
  return results;
}

// The sweep of `keys` over `cases` (one row of values per case) from `config`, as columns:
// the keys' values, status and error per case, and sweep CSV's result columns. torque: none
// holds each case's start (0 N m, a servo's initial setpoint). Ctrl-C: the exception raised
// carries the finished cases as `result` (unfinished ones "interrupted", NaN).
py::dict sweep(const PythonConfig& config, const std::vector<std::string>& keys,
               const std::vector<std::vector<double>>& cases, double duration,
               const std::optional<TorqueProfile>& torque, long long jobs, const std::string& simd,
               bool vector_trig, long long csv_first_case) {
  SweepPlan plan{keys, cases};
  for (size_t i = 0; i < cases.size(); ++i)
    if (cases[i].size() != keys.size())
      throw py::value_error("sweep: case " + std::to_string(i) + " has " +
                            std::to_string(cases[i].size()) + " values for " +
                            std::to_string(keys.size()) + " keys");
  if (jobs < 0 || jobs > static_cast<long long>(maxSweepJobs()))
    throw py::value_error("sweep: jobs must be in [0, " + std::to_string(maxSweepJobs()) +
                          "] (0: one thread per core; at most 4 per core), got " +
                          std::to_string(jobs));
  try {
    checkRunDuration(duration, "duration");
    checkSweepKeys(plan);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(std::string("sweep: ") + e.what());
  }
  SweepSettings settings;
  settings.duration = duration;
  settings.torque = torque;
  settings.jobs = static_cast<unsigned>(jobs);
  settings.simd = simd;
  settings.vector_trig = vector_trig;
  try {
    checkLaneEnvironment();  // a bad KANE_SIM_SIMD_MAX, whatever `simd` says
    if (simd != "off")
      parseLaneArch(simd);  // a typo, or an instruction set this CPU lacks, named before any run
  } catch (const std::invalid_argument& e) {
    throw py::value_error(std::string("sweep: ") + e.what());
  }
  std::unique_ptr<py::error_already_set> raised;
  const std::vector<SweepResult> results = runSweepStoppable(config, plan, settings, &raised);
  py::dict out;
  for (size_t k = 0; k < keys.size(); ++k) {
    std::vector<double> values;
    for (const auto& c : cases) values.push_back(c[k]);
    out[keys[k].c_str()] = py::array_t<double>(values.size(), values.data());
  }
  std::vector<std::string> status, error;
  for (const SweepResult& r : results) {
    status.push_back(r.status);
    error.push_back(r.error);
  }
  out["status"] = status;
  out["error"] = error;
  for (const SweepColumn* c = sweepColumnsBegin(); c != sweepColumnsEnd(); ++c) {
    std::vector<double> values;
    for (const SweepResult& r : results)
      values.push_back(r.status == "config_refused" || r.status == "interrupted" ? std::nan("")
                                                                                 : c->value(r));
    out[c->name] = py::array_t<double>(values.size(), values.data());
  }
  if (csv_first_case >= 0) {
    // The rows as `simulate --sweep` writes them (case numbers from csv_first_case on; none for
    // an interrupted case): a chunk of a sweep run elsewhere joins the others' text unchanged.
    std::ostringstream rows;
    for (size_t i = 0; i < results.size(); ++i)
      if (results[i].status != "interrupted")
        writeSweepCsvRow(rows, plan, i, results[i], static_cast<size_t>(csv_first_case));
    out["csv_rows"] = rows.str();
  }
  if (raised) {
    raised->value().attr("result") = out;
    throw *raised;
  }
  return out;
}

std::string sweepCsvHeader(const std::vector<std::string>& keys) {
  std::ostringstream out;
  writeSweepCsvHeader(out, SweepPlan{keys, {}});
  return out.str();
}

// simulate's --sweep-file: the keys and the cases (std::invalid_argument -> ValueError).
std::pair<std::vector<std::string>, std::vector<std::vector<double>>> planFromCsv(
    const std::string& path) {
  try {
    std::ifstream in = openInputFile(path, "sweep file", kMaxTableBytes);
    const SweepPlan plan = sweepFromCsv(in);
    return {plan.keys, plan.cases};
  } catch (const std::invalid_argument& e) {
    throw py::value_error(std::string("--sweep-file: ") + e.what());
  }
}

// O, A, B, C, C1, C2 (x, y) in frame (0) for each (q1, q2): the model's geometry, for drawing.
py::dict mechanismPoints(double rod_half_length, const py::array_t<double>& q1_in,
                         const py::array_t<double>& q2_in) {
  const auto q1 = q1_in.unchecked<1>();
  const auto q2 = q2_in.unchecked<1>();
  if (q1.shape(0) != q2.shape(0))
    throw py::value_error("mechanism_points: q1 and q2 differ in length");
  const py::ssize_t n = q1.shape(0);
  const char* names[] = {"O", "A", "B", "C", "C1", "C2"};
  std::vector<py::array_t<double>> points;
  for (int i = 0; i < 6; ++i) points.emplace_back(std::vector<py::ssize_t>{n, 2});
  for (py::ssize_t k = 0; k < n; ++k) {
    const MechanismGeometry g = mechanismGeometry(rod_half_length, q1(k), q2(k));
    const Eigen::Vector3d* at[] = {&g.pivot_o, &g.pin_a,       &g.pin_b,
                                   &g.point_c, &g.rod1_center, &g.rod2_center};
    for (int i = 0; i < 6; ++i) {
      auto p = points[static_cast<size_t>(i)].mutable_unchecked<2>();
      p(k, 0) = at[i]->x();
      p(k, 1) = at[i]->y();
    }
  }
  py::dict out;
  for (int i = 0; i < 6; ++i) out[names[i]] = points[static_cast<size_t>(i)];
  return out;
}

double finite(const char* name, double v) {
  if (!std::isfinite(v))
    throw py::value_error(std::string(name) + " must be finite, got " + formatNumber(v));
  return v;
}

// The grid of several axes (simulate's --sweep): every combination, the last varying fastest.
// simulate's --sweep KEY=START:STOP:COUNT (std::invalid_argument -> ValueError).
std::pair<std::string, std::vector<double>> axis(const std::string& spec) {
  try {
    const SweepAxis a = parseSweepAxis(spec);
    return {a.key, a.values};
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
}

std::pair<std::vector<std::string>, std::vector<std::vector<double>>> grid(
    const std::vector<std::pair<std::string, std::vector<double>>>& axes) {
  std::vector<SweepAxis> sweep_axes;
  for (const auto& [key, values] : axes) sweep_axes.push_back(SweepAxis{key, values});
  const SweepPlan plan = sweepGrid(sweep_axes);
  return {plan.keys, plan.cases};
}

// Profiles refuse what TorqueProfile refuses (std::invalid_argument -> ValueError).
template <typename F>
TorqueProfile checked(F make) {
  try {
    return make();
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
}

}  // namespace

void bindAnalysis(py::module_& m) {
  py::class_<TorqueProfile>(m, "TorqueProfile",
                            "A torque over time, as simulate's --torque* options give it.")
      .def_static(
          "constant", [](double v) { return TorqueProfile::constant(finite("torque", v)); },
          py::arg("torque"))
      .def_static(
          "step",
          [](double t, double before, double after) {
            return TorqueProfile::step(finite("time", t), finite("before", before),
                                       finite("after", after));
          },
          py::arg("time"), py::arg("before"), py::arg("after"))
      .def_static(
          "sine",
          [](double amplitude, double frequency, double offset) {
            return TorqueProfile::sine(finite("amplitude", amplitude),
                                       finite("frequency", frequency), finite("offset", offset));
          },
          py::arg("amplitude"), py::arg("frequency"), py::arg("offset") = 0.0)
      .def_static(
          "table",
          [](std::vector<std::pair<double, double>> points) {
            return checked([&] { return TorqueProfile::table(std::move(points)); });
          },
          py::arg("points"))
      .def_static(
          "from_csv",
          [](const std::string& path) {
            return checked([&] { return TorqueProfile::fromCsvFile(path); });
          },
          py::arg("path"))
      .def_static(
          "from_flag",
          [](const std::string& flag, const std::string& text) {
            return checked([&] { return TorqueProfile::fromFlag(flag, text); });
          },
          py::arg("flag"), py::arg("text"))
      .def("at", &TorqueProfile::at, py::arg("t"))
      .def(py::pickle(
          [](const TorqueProfile& p) {  // to a cluster's worker and back
            const TorqueProfile::Parts parts = p.parts();
            return py::make_tuple(parts.kind, parts.a, parts.b, parts.c, parts.points, parts.named,
                                  parts.header);
          },
          [](const py::tuple& t) {
            if (t.size() != 7) throw py::value_error("TorqueProfile: a pickle of 7 fields");
            TorqueProfile::Parts parts;
            parts.kind = t[0].cast<int>();
            parts.a = t[1].cast<double>(), parts.b = t[2].cast<double>();
            parts.c = t[3].cast<double>();
            parts.points = t[4].cast<std::vector<std::pair<double, double>>>();
            parts.named = t[5].cast<int>();
            parts.header = t[6].cast<std::string>();
            return checked([&] { return TorqueProfile::fromParts(parts); });
          }))
      .def("__repr__",
           [](const TorqueProfile& p) { return "TorqueProfile(" + p.describe() + ")"; });
  m.def("sweep_grid", &grid, py::arg("axes"));
  m.def("sweep_axis", &axis, py::arg("spec"));
  m.def("sweep_plan_from_csv", &planFromCsv, py::arg("path"));
  m.def("sweep_csv_header", &sweepCsvHeader, py::arg("keys"));
  m.def("mechanism_points", &mechanismPoints, py::arg("rod_half_length"), py::arg("q1"),
        py::arg("q2"));
  m.def("analyze_json", &analyze, py::arg("config"), py::arg("torque") = 0.0,
        py::arg("q1") = py::none());
  m.def("equilibria", &equilibriaOf, py::arg("config"), py::arg("torque") = 0.0);
  m.def("sweep", &sweep, py::arg("config"), py::arg("keys"), py::arg("cases"), py::arg("duration"),
        py::arg("torque") = py::none(), py::arg("jobs") = 0, py::arg("simd") = "auto",
        py::arg("vector_trig") = false, py::arg("csv_first_case") = -1);
}

}  // namespace python
}  // namespace kane_sim
