// simulate's command line and staged CSV for the Python tools (scripts/sweep): the same grammar,
// checks and messages as `simulate`, not a second copy of them.
#include <cerrno>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "kane_sim/cli/simulate_options.h"
#include "kane_sim/cli/staged_output.h"
#include "python_layer.h"

namespace kane_sim {
namespace python {
namespace {

// simulate's options from `arguments` (argv without the program), and a sweep's cases when the
// arguments ask for a sweep. A bad flag is a ValueError with simulate's message.
py::dict simulateOptions(const std::vector<std::string>& arguments) {
  cli::Options o;
  SweepPlan plan;
  try {
    o = cli::parseArguments(arguments);
    if (o.sweep()) plan = cli::sweepPlan(o);
  } catch (const cli::UsageError& e) {
    throw py::value_error(e.what());
  }
  py::dict out;
  out["config"] = o.config_path;
  out["default_config"] = o.default_config;
  out["duration"] = o.duration;
  out["output_rate"] = o.output_rate;
  out["torque"] = o.profile_given ? py::cast(*o.profile) : py::none();
  out["integrator"] = o.integrator.empty() ? py::none() : py::cast(o.integrator);
  out["csv"] = o.csv_path;
  out["bag"] = o.bag_path;
  out["replay"] = o.replay_bag;
  out["sweep"] = o.sweep();
  out["sweep_keys"] = plan.keys;
  out["sweep_cases"] = plan.cases;
  out["jobs"] = o.jobs;
  out["simd"] = o.simd;
  out["vector_trig"] = o.vector_trig;
  return out;
}

// A failed open or write as Python's OSError: BrokenPipeError when the reader went away
// (| head; OSError picks the subclass from errno), else OSError with simulate's message.
[[noreturn]] void raiseOsError(const std::string& what) {
  if (errno == EPIPE)
    PyErr_SetFromErrno(PyExc_OSError);
  else
    PyErr_SetString(PyExc_OSError, what.c_str());
  throw py::error_already_set();
}

}  // namespace

void bindCli(py::module_& m) {
  m.def("simulate_options", &simulateOptions, py::arg("arguments"),
        "simulate's options from argv[1:] (its grammar and messages); ValueError for a bad flag");
  py::class_<cli::CsvOutput>(m, "CsvOutput",
                             "simulate's CSV output: FILE.partial renamed at finish(), a device, "
                             "pipe or link written in place, stdout for ''")
      .def(py::init([](const std::string& path) {
             try {
               return std::make_unique<cli::CsvOutput>(path);
             } catch (const cli::OutputError& e) {
               raiseOsError(e.what());
             }
           }),
           py::arg("path"))
      .def(
          "write",
          [](cli::CsvOutput& out, const std::string& text) {
            errno = 0;
            out.stream() << text;
            out.stream().flush();
            if (!out.stream()) raiseOsError("writing the CSV failed (disk full?)");
          },
          py::arg("text"))
      .def("finish", [](cli::CsvOutput& out) {
        errno = 0;
        try {
          out.finish();
        } catch (const cli::OutputError& e) {
          raiseOsError(e.what());
        }
      });
}

}  // namespace python
}  // namespace kane_sim
