// kane_sim._core: the mechanism's C++ core for Python (import it as kane_sim; python/kane_sim/
// wraps it). Errors keep the loader's and the driver's words: ConfigError (a ValueError) for a
// config, ValueError for a refused input, StepRefused (a RuntimeError) for a refused step.
#include "python_layer.h"

PYBIND11_MODULE(_core, m) {
  namespace py = pybind11;
  m.doc() = "kane_sim's C++ core: the textbook example's mechanism, simulated by Kane's method";
  py::register_exception<kane_sim::ConfigError>(m, "ConfigError", PyExc_ValueError);
  kane_sim::python::bindConfig(m);
  kane_sim::python::bindSimulator(m);
  kane_sim::python::bindAnalysis(m);
  kane_sim::python::bindDesign(m);
  kane_sim::python::bindEstimate(m);
  kane_sim::python::bindIdentify(m);
  kane_sim::python::bindBatch(m);
  kane_sim::python::bindCli(m);
}
