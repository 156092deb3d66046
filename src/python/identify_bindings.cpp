// kane_sim._core's identification: the regressor of Kane's equations (identify/regressor.h) over
// arrays of samples. The statistics, the filtering and the data's reading live in Python
// (kane_sim/identify.py, NumPy and SciPy).
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "kane_sim/format_number.h"
#include "kane_sim/identify/regressor.h"
#include "kane_sim/model/joint_names.h"
#include "kane_sim/sim/parallel.h"
#include "python_layer.h"

namespace kane_sim {
namespace python {
namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

// (N, 4) states and (N,) torques (and (N, 2) rates), every value finite: named otherwise.
py::ssize_t checkSamples(const Array& states, const Array& torque, const Array* u_dot) {
  if (states.ndim() != 2 || states.shape(1) != 4)
    throw py::value_error("states must have shape (N, 4), got ndim " +
                          std::to_string(states.ndim()));
  const py::ssize_t n = states.shape(0);
  if (torque.ndim() != 1 || torque.shape(0) != n)
    throw py::value_error("torque must have shape (" + std::to_string(n) + ",)");
  if (u_dot && (u_dot->ndim() != 2 || u_dot->shape(0) != n || u_dot->shape(1) != 2))
    throw py::value_error("u_dot must have shape (" + std::to_string(n) + ", 2)");
  auto finite = [](const Array& a, const char* what) {
    for (py::ssize_t i = 0; i < a.size(); ++i)
      if (!std::isfinite(a.data()[i]))
        throw py::value_error(std::string(what) + " has a non-finite value at flat index " +
                              std::to_string(i) + ": " + formatNumber(a.data()[i]));
  };
  finite(states, "states");
  finite(torque, "torque");
  if (u_dot) finite(*u_dot, "u_dot");
  return n;
}

State stateAt(const double* s) { return State{s[0], s[1], s[2], s[3]}; }

Regressor makeRegressor(const PythonConfig& config, const std::vector<std::string>& names) {
  try {
    return Regressor(config.config(), names);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
}

// Y (N, 2, P) and y0 (N, 2): F*_r + F_r = Y θ + y0 at each sample.
py::tuple equationRows(const PythonConfig& config, const std::vector<std::string>& names,
                       const Array& states, const Array& u_dot, const Array& torque) {
  const py::ssize_t n = checkSamples(states, torque, &u_dot);
  const Regressor regressor = makeRegressor(config, names);
  const py::ssize_t p = regressor.size();
  Array y({n, py::ssize_t{2}, p}), y0({n, py::ssize_t{2}});
  double* yd = y.mutable_data();
  double* y0d = y0.mutable_data();
  {
    py::gil_scoped_release release;
    parallelBlocks(n, coreCount(), [&](long begin, long end) {  // rows apart: any order
      Eigen::Matrix<double, kNumSpeeds, Eigen::Dynamic> block(kNumSpeeds, p);
      SpeedVector known;
      for (long i = begin; i < end; ++i) {
        const SpeedVector rates(u_dot.data()[2 * i], u_dot.data()[2 * i + 1]);
        regressor.equationRows(stateAt(states.data() + 4 * i), rates, torque.data()[i], block,
                               known);
        for (int r = 0; r < kNumSpeeds; ++r) {
          for (py::ssize_t j = 0; j < p; ++j) yd[(i * 2 + r) * p + j] = block(r, j);
          y0d[i * 2 + r] = known[r];
        }
      }
    });
  }
  return py::make_tuple(y, y0);
}

// E (N, P), P (N, P), e0 (N,), p0 (N,): the work-energy form's energies and powers.
py::tuple energyRows(const PythonConfig& config, const std::vector<std::string>& names,
                     const Array& states, const Array& torque) {
  const py::ssize_t n = checkSamples(states, torque, nullptr);
  const Regressor regressor = makeRegressor(config, names);
  const py::ssize_t p = regressor.size();
  Array energy({n, p}), power({n, p}), e0(n), p0(n);
  {
    py::gil_scoped_release release;
    double* energy_out = energy.mutable_data();
    double* power_out = power.mutable_data();
    double* e0_out = e0.mutable_data();
    double* p0_out = p0.mutable_data();
    // ~12 us a sample (2 P + 1 models' energy and loads): an hour at 1 kHz is 40 s on one core,
    // so the samples are cut into one block per core (rows apart: the result is the same).
    parallelBlocks(n, coreCount(), [&](long begin, long end) {
      Eigen::RowVectorXd e(p), w(p);
      for (long i = begin; i < end; ++i) {
        regressor.energyRow(stateAt(states.data() + 4 * i), torque.data()[i], e, w, e0_out + i,
                            p0_out + i);
        for (py::ssize_t j = 0; j < p; ++j) {
          energy_out[i * p + j] = e[j];
          power_out[i * p + j] = w[j];
        }
      }
    });
  }
  return py::make_tuple(energy, power, e0, p0);
}

py::list identifiable() {
  py::list out;
  for (const IdentifiableParameter& p : identifiableParameters()) {
    py::dict d;
    d["name"] = p.name;
    d["unit"] = p.unit;
    d["symbol"] = p.symbol;
    d["by_default"] = p.by_default;
    out.append(d);
  }
  return out;
}

}  // namespace

void bindIdentify(py::module_& m) {
  m.def(
      "joint_names",
      [] { return std::vector<std::string>(kJointNames.begin(), kJointNames.end()); },
      "joint_states' names, in order: crank, coupler, slider 3, slider 4.");
  m.def("identifiable_parameters", &identifiable,
        "What identification can estimate: name, unit, symbol, by_default.");
  m.def("identification_rows", &equationRows, py::arg("config"), py::arg("names"),
        py::arg("states"), py::arg("u_dot"), py::arg("torque"),
        "Kane's equations as Y (N, 2, P) theta + y0 (N, 2) = 0 at each sample.");
  m.def("identification_energy", &energyRows, py::arg("config"), py::arg("names"),
        py::arg("states"), py::arg("torque"),
        "Work-energy form: E (N, P), P (N, P), e0 (N,), p0 (N,) per unit parameter.");
  m.def(
      "identification_base_value",
      [](const PythonConfig& config, const std::string& name) {
        try {
          return identificationBaseValue(config.config(), name);
        } catch (const std::invalid_argument& e) {
          throw py::value_error(e.what());
        }
      },
      py::arg("config"), py::arg("name"));
}

}  // namespace python
}  // namespace kane_sim
