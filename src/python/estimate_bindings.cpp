// kane_sim._core's estimator (estimate/): the Kalman filter reading by reading, and a recording
// replayed through it (runEstimator, `observer --bag`'s loop) as NumPy columns named as the
// CSV's. kane_sim.Estimator wraps it.
#include <optional>
#include <string>
#include <vector>

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "kane_sim/estimate/estimate_run.h"
#include "kane_sim/estimate/estimate_table.h"
#include "kane_sim/estimate/mechanism_estimator.h"
#include "kane_sim/sim/config_check.h"
#include "python_layer.h"

namespace kane_sim {
namespace python {
namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

const char* eventName(EstimatorEvent event) {
  switch (event) {
    case EstimatorEvent::kUpdated:
      return "updated";
    case EstimatorEvent::kStarted:
      return "started";
    case EstimatorEvent::kRestarted:
      return "restarted";
    default:
      return "refused";
  }
}

py::dict alarmDict(const AlarmReport& a) {
  py::dict d;
  d["level"] = alarmLevelName(a.level);
  d["text"] = a.text();
  d["since"] = a.since;
  d["coordinate"] = a.level == AlarmLevel::kOk ? "" : measuredCoordinateName(a.coordinate);
  d["nis"] = a.nis;
  d["dof"] = a.dof;
  d["p_value"] = a.p_value;
  d["windows"] = a.windows;
  // The parameters whose change explains the window, most likely first.
  py::list suspects;
  for (const AlarmReport::Suspect& s : a.suspects) {
    py::dict one;
    one["name"] = s.name;
    one["unit"] = s.unit;
    one["change"] = s.change;
    one["sigma"] = s.sigma;
    one["over"] = s.over;
    suspects.append(one);
  }
  d["suspects"] = suspects;
  return d;
}

// The filter, reading by reading, with the virtual sensors of its estimate.
class PythonEstimator {
 public:
  explicit PythonEstimator(const PythonConfig& config)
      : config_(checked(config.config())), estimator_(config_), sensors_(config_) {}

  py::tuple update(double t, double q1, double q2, double effort, std::optional<double> u1,
                   std::optional<double> u2) {
    if (u1.has_value() != u2.has_value())
      throw py::value_error("Estimator.update: give both u1 and u2, or neither");
    RigReading r;
    r.stamp = t;
    r.q1 = q1;
    r.q2 = q2;
    r.torque = effort;
    r.has_velocity = u1.has_value();
    if (r.has_velocity) {
      r.u1 = *u1;
      r.u2 = *u2;
    }
    const EstimatorStep step = estimator_.update(r);
    if (step.event == EstimatorEvent::kStarted || step.event == EstimatorEvent::kRestarted)
      first_stamp_ = t;
    if (step.event != EstimatorEvent::kRefused) {
      std::string why;
      has_row_ = estimateRow(estimator_, &sensors_, first_stamp_, &row_, &why);
      if (!has_row_) return py::make_tuple("refused", why);
    }
    return py::make_tuple(eventName(step.event), step.reason);
  }

  void restart() {
    estimator_.restart();
    has_row_ = false;
  }

  // The last row as the CSV's columns, with the covariance (4 x 4) of (q1, q2, u1, u2).
  py::object estimate() const {
    if (!has_row_) return py::none();
    py::dict d;
    for (const EstimateColumn& c : estimateColumns()) d[c.name.c_str()] = c.value(row_);
    d["covariance"] = Eigen::Matrix4d(row_.estimate.covariance.topLeftCorner<4, 4>());
    return d;
  }
  py::dict alarm() const { return alarmDict(estimator_.alarm().report()); }

 private:
  static const Config& checked(const Config& config) {
    checkSimulatable(config);
    return config;
  }
  Config config_;
  MechanismEstimator estimator_;
  VirtualSensors sensors_;
  EstimateRow row_;
  bool has_row_ = false;
  double first_stamp_ = 0.0;
};

std::vector<double> column(const char* name, const Array& a, std::size_t n) {
  if (a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != n)
    throw py::value_error(std::string("estimate: ") + name + " must be 1-D with one value per t (" +
                          std::to_string(n) + "), got shape " + shapeText(a));
  return std::vector<double>(a.data(), a.data() + n);
}

// A recording through runEstimator: ({column: array}, summary).
py::tuple estimateRun(
    const PythonConfig& config, const Array& t, const Array& q1, const Array& q2,
    const Array& effort, std::optional<Array> u1, std::optional<Array> u2,
    std::optional<py::array_t<bool, py::array::c_style | py::array::forcecast>> velocity_rows) {
  checkSimulatable(config.config());
  if (t.ndim() != 1) throw py::value_error("estimate: t must be 1-D, got shape " + shapeText(t));
  const auto n = static_cast<std::size_t>(t.shape(0));
  if (u1.has_value() != u2.has_value())
    throw py::value_error("estimate: give both u1 and u2, or neither");
  ReadingColumns columns;
  columns.t = column("t", t, n);
  columns.q1 = column("q1", q1, n);
  columns.q2 = column("q2", q2, n);
  columns.effort = column("effort", effort, n);
  if (u1) {
    columns.u1 = column("u1", *u1, n);
    columns.u2 = column("u2", *u2, n);
  }
  if (velocity_rows) {
    if (velocity_rows->ndim() != 1 || static_cast<std::size_t>(velocity_rows->shape(0)) != n)
      throw py::value_error("estimate: velocity_rows must be 1-D with one value per t (" +
                            std::to_string(n) + ")");
    columns.velocity_rows.assign(velocity_rows->data(), velocity_rows->data() + n);
  }
  const std::string problem = columns.problem();
  if (!problem.empty()) throw py::value_error("estimate: " + problem);
  const std::vector<EstimateColumn>& names = estimateColumns();
  std::vector<std::vector<double>> values(names.size());
  std::atomic<bool> stop{false};
  EstimateRunSummary summary;
  const std::unique_ptr<py::error_already_set> raised = runStoppable(
      stop,
      [&] {
        summary = runEstimator(
            config.config(), columns,
            [&](const EstimateRow& row) {
              for (std::size_t i = 0; i < names.size(); ++i)
                values[i].push_back(names[i].value(row));
            },
            [&] { return stop.load(); });
      },
      std::chrono::milliseconds(50));
  if (raised) throw *raised;
  py::dict out;
  for (std::size_t i = 0; i < names.size(); ++i)
    out[names[i].name.c_str()] =
        py::array_t<double>(static_cast<py::ssize_t>(values[i].size()), values[i].data());
  py::dict s;
  s["rows"] = summary.rows;
  s["refused"] = summary.refused;
  s["restarts"] = summary.restarts;
  s["notes"] = summary.notes;
  s["alarm"] = alarmDict(summary.alarm);
  return py::make_tuple(out, s);
}

}  // namespace

void bindEstimate(py::module_& m) {
  py::class_<PythonEstimator>(m, "Estimator")
      .def(py::init<const PythonConfig&>(), py::arg("config"))
      .def("update", &PythonEstimator::update, py::arg("t"), py::arg("q1"), py::arg("q2"),
           py::arg("effort"), py::arg("u1") = py::none(), py::arg("u2") = py::none())
      .def("restart", &PythonEstimator::restart)
      .def_property_readonly("estimate", &PythonEstimator::estimate)
      .def_property_readonly("alarm", &PythonEstimator::alarm);
  m.def("estimate_run", &estimateRun, py::arg("config"), py::arg("t"), py::arg("q1"), py::arg("q2"),
        py::arg("effort"), py::arg("u1") = py::none(), py::arg("u2") = py::none(),
        py::arg("velocity_rows") = py::none());
}

}  // namespace python
}  // namespace kane_sim
