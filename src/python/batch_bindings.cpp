// kane_sim._core.BatchSimulator: the C++ BatchSimulator (sim/batch_simulator.h) with NumPy
// arrays in and out; a step releases the GIL (its threads and lanes run without Python).
#include <atomic>
#include <chrono>
#include <cstdint>
#include <exception>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "kane_sim/sim/batch_simulator.h"
#include "python_layer.h"

namespace kane_sim {
namespace python {
namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
using Mask = py::array_t<bool, py::array::c_style | py::array::forcecast>;

std::vector<bool> maskOf(const BatchSimulator& batch, const Mask& mask, const char* call) {
  if (mask.ndim() != 1 || static_cast<std::size_t>(mask.shape(0)) != batch.size())
    throw py::value_error(std::string(call) + ": mask must hold one bool per mechanism (" +
                          std::to_string(batch.size()) + ")");
  return std::vector<bool>(mask.data(), mask.data() + mask.shape(0));
}

Array states(const BatchSimulator& batch) {
  const py::ssize_t n = static_cast<py::ssize_t>(batch.size());
  Array out({n, py::ssize_t{4}});
  double* o = out.mutable_data();
  for (std::size_t i = 0; i < batch.size(); ++i) {
    const State x = batch.state(i);
    o[4 * i] = x.q1, o[4 * i + 1] = x.q2, o[4 * i + 2] = x.u1, o[4 * i + 3] = x.u2;
  }
  return out;
}

// (n, 4) of the last readings' positions or velocities (joint_states' order).
Array readings(const BatchSimulator& batch, bool velocity) {
  const py::ssize_t n = static_cast<py::ssize_t>(batch.size());
  Array out({n, py::ssize_t{kNumJoints}});
  double* o = out.mutable_data();
  for (std::size_t i = 0; i < batch.size(); ++i) {
    const JointValues& r = batch.reading(i);
    for (int j = 0; j < kNumJoints; ++j)
      o[kNumJoints * i + j] = velocity ? r.velocity[j] : r.position[j];
  }
  return out;
}

}  // namespace

void bindBatch(py::module_& m) {
  m.def(
      "lane_arch_available",
      [](const std::string& name) {
        for (LaneArch a : {LaneArch::kScalar, LaneArch::kSse2, LaneArch::kAvx2, LaneArch::kAvx512})
          if (name == laneArchName(a)) return laneArchAvailable(a);
        throw py::value_error("'" + name + "' is not one of scalar, sse2, avx2, avx512");
      },
      py::arg("name"), "Whether this CPU (and build) runs SIMD lanes of that instruction set.");
  py::class_<BatchSimulator>(m, "BatchSimulator")
      .def(py::init([](const std::vector<const PythonConfig*>& configs, const std::string& simd,
                       bool vector_trig, int threads) {
             std::vector<Config> lanes;
             lanes.reserve(configs.size());
             for (const PythonConfig* c : configs) lanes.push_back(c->config());
             try {
               return new BatchSimulator(std::move(lanes),
                                         BatchSettings{simd, vector_trig, threads});
             } catch (const std::invalid_argument& e) {
               throw py::value_error(e.what());
             }
           }),
           py::arg("configs"), py::arg("simd") = "auto", py::arg("vector_trig") = false,
           py::arg("threads") = 1)
      .def_property_readonly("size", &BatchSimulator::size)
      .def_property_readonly("path", &BatchSimulator::path)
      .def_property_readonly("on_lanes", &BatchSimulator::onLanes)
      .def_property_readonly("sensors", &BatchSimulator::sensorsEnabled)
      .def(
          "step",
          [](BatchSimulator& b, const Array& actions, long steps, const py::object& mask) {
            if (actions.ndim() != 1 || static_cast<std::size_t>(actions.shape(0)) != b.size())
              throw py::value_error("step: actions must hold one value per mechanism (" +
                                    std::to_string(b.size()) + ")");
            std::vector<bool> active;
            if (!mask.is_none()) active = maskOf(b, mask.cast<Mask>(), "step");
            // The step on a thread of its own; this one, without the GIL, looks at Python's
            // signals every 20 ms: Ctrl-C stops every lane where it is (KeyboardInterrupt).
            std::atomic<bool> stop{false};
            std::unique_ptr<py::error_already_set> raised;
            try {
              raised = runStoppable(
                  stop,
                  [&] { b.step(actions.data(), steps, mask.is_none() ? nullptr : &active, &stop); },
                  std::chrono::milliseconds(20));
            } catch (const std::invalid_argument& e) {
              throw py::value_error(std::string("step: ") + e.what());
            }
            if (raised) throw *raised;
            return states(b);
          },
          py::arg("actions"), py::arg("steps") = 1, py::arg("mask") = py::none())
      .def(
          "reset",
          [](BatchSimulator& b, const Mask& mask) {
            b.reset(maskOf(b, mask, "reset"));
            return states(b);
          },
          py::arg("mask"))
      .def(
          "reseed",
          [](BatchSimulator& b, const Mask& mask, std::uint64_t seed) {
            b.reseed(maskOf(b, mask, "reset"), seed);
            return states(b);
          },
          py::arg("mask"), py::arg("seed"))
      .def_property_readonly("states", &states)
      .def_property_readonly("times",
                             [](const BatchSimulator& b) {
                               Array out(static_cast<py::ssize_t>(b.size()));
                               for (std::size_t i = 0; i < b.size(); ++i)
                                 out.mutable_data()[i] = b.time(i);
                               return out;
                             })
      .def_property_readonly("terminated",
                             [](const BatchSimulator& b) {
                               Mask out(static_cast<py::ssize_t>(b.size()));
                               for (std::size_t i = 0; i < b.size(); ++i)
                                 out.mutable_data()[i] = b.terminated(i);
                               return out;
                             })
      .def_property_readonly("reasons",
                             [](const BatchSimulator& b) {
                               std::vector<std::string> out;
                               for (std::size_t i = 0; i < b.size(); ++i)
                                 out.push_back(b.reason(i));
                               return out;
                             })
      .def_property_readonly("reading_positions",
                             [](const BatchSimulator& b) { return readings(b, false); })
      .def_property_readonly("reading_velocities",
                             [](const BatchSimulator& b) { return readings(b, true); });
}

}  // namespace python
}  // namespace kane_sim
