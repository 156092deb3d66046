// The Python module kane_sim._core: a translation layer over the same libraries as the node and
// `simulate` (the config loader, SimDriver, the analysis), like the ROS layer. Python-side
// conveniences (dicts, Result, plots) live in python/kane_sim/.
#ifndef KANE_SIM_PYTHON_PYTHON_LAYER_H
#define KANE_SIM_PYTHON_PYTHON_LAYER_H

#include <atomic>
#include <chrono>
#include <exception>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <yaml-cpp/yaml.h>

#include "kane_sim/config/load_config.h"

namespace kane_sim {
namespace python {

namespace py = pybind11;

// A config as the user gave it (a file or YAML text) and as the loader validated it. Values are
// read and written by their config names ("mechanism.rod_mass"); every change goes through the
// loader again, so a refused one (ConfigError, the loader's message) changes nothing.
class PythonConfig {
 public:
  // "" loads the package's config/mechanism.yaml.
  static PythonConfig fromFile(const std::string& path);
  static PythonConfig fromYaml(const std::string& text);

  const Config& config() const { return loaded_.config; }
  const std::vector<std::string>& warnings() const { return loaded_.warnings; }
  const std::string& source() const { return source_; }
  // The YAML tree with every value set so far, as text (a config file for `simulate`).
  std::string yaml() const;
  const YAML::Node& tree() const { return tree_; }

  py::object get(const std::string& name) const;
  // A copy with `name` set to the YAML scalar `value_yaml` (Python's yaml.safe_dump of it).
  PythonConfig with(const std::string& name, const std::string& value_yaml) const;
  // A copy with every (name, YAML scalar) set, validated together (the order does not matter).
  PythonConfig with(const std::vector<std::pair<std::string, std::string>>& values) const;
  static std::vector<std::string> names();
  static bool reconfigurable(const std::string& name);
  // The parameter's role in the schema ("inertial", "dissipative", ...: ParameterRole).
  static std::string role(const std::string& name);
  // The law of the load the parameter is the coefficient of ("viscous", "coulomb", "elastic"),
  // or "" (lawOfCoefficient).
  static std::string law(const std::string& name);

 private:
  PythonConfig(YAML::Node tree, std::string source);
  YAML::Node tree_;
  LoadedConfig loaded_;
  std::string source_;
};

// "mechanism.rod_mass" -> its schema entry; ConfigError naming the name otherwise.
const ParameterSpec& specOf(const std::string& name);

// "(3, 4)", "(5,)": an array's shape as refusals name it (NumPy's way).
inline std::string shapeText(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// Runs work() (C++ that checks `stop`) on a thread of its own while this one, without the GIL,
// looks at Python's signals every `poll`: a handler that raises (Ctrl-C) sets `stop`, and that
// exception is returned (null when none was raised). work()'s own exception is rethrown here.
template <class Work>
std::unique_ptr<py::error_already_set> runStoppable(std::atomic<bool>& stop, Work work,
                                                    std::chrono::milliseconds poll) {
  std::unique_ptr<py::error_already_set> raised;
  std::exception_ptr failure;
  {
    py::gil_scoped_release release;
    std::future<void> done = std::async(std::launch::async, [&] {
      try {
        work();
      } catch (...) {
        failure = std::current_exception();
      }
    });
    while (done.wait_for(poll) != std::future_status::ready) {
      if (stop) continue;
      py::gil_scoped_acquire acquire;
      if (PyErr_CheckSignals() != 0) {
        raised = std::make_unique<py::error_already_set>();
        stop = true;
      }
    }
  }
  if (failure) std::rethrow_exception(failure);
  return raised;
}

void bindConfig(py::module_& m);
void bindSimulator(py::module_& m);
void bindAnalysis(py::module_& m);
void bindDesign(py::module_& m);
void bindEstimate(py::module_& m);
void bindIdentify(py::module_& m);
void bindBatch(py::module_& m);
void bindCli(py::module_& m);

}  // namespace python
}  // namespace kane_sim

#endif  // KANE_SIM_PYTHON_PYTHON_LAYER_H
