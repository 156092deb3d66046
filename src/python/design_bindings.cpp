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
#include "kane_sim/design/riccati.h"
#include "kane_sim/format_number.h"
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
py::dict lqr(const PythonConfig& config, double q1, const std::optional<Eigen::MatrixXd>& Q,
             const std::optional<double>& R) {
  const MechanismModel model = mechanismModel(config.config());
  LqrWeights weights = defaultLqrWeights(config.config(), model);
  if (Q) {
    if (Q->size() == 4 && (Q->rows() == 1 || Q->cols() == 1))
      weights.Q = Eigen::Vector4d(Q->data()).asDiagonal();
    else if (Q->rows() == 4 && Q->cols() == 4)
      weights.Q = *Q;
    else
      throw py::value_error(
          "lqr: Q must be 4 numbers (the diagonal on q1, q2, u1, u2) or a 4 x 4 "
          "matrix, got " +
          std::to_string(Q->rows()) + " x " + std::to_string(Q->cols()));
  }
  if (R) {
    if (!(std::isfinite(*R) && *R > 0))
      throw py::value_error("lqr: R must be a finite number > 0, got " + formatNumber(*R));
    weights.R = *R;
  }
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

}  // namespace

void bindDesign(py::module_& m) {
  m.def("design_lqr", &lqr, py::arg("config"), py::arg("q1"), py::arg("Q") = py::none(),
        py::arg("R") = py::none());
}

}  // namespace python
}  // namespace kane_sim
