// kane_sim._core.BatchSimulator: the C++ BatchSimulator (sim/batch_simulator.h) with NumPy
// arrays in and out; a step releases the GIL (its threads and lanes run without Python).
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "kane_sim/format_number.h"
#include "kane_sim/model/mechanism_laws.h"
#include "kane_sim/sim/batch_simulator.h"
#include "kane_sim/sim/numbers_into_configs.h"
#include "kane_sim/sim/parallel.h"
#include "python_layer.h"

namespace kane_sim {
namespace python {
namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
// Mechanism-steps a step() call runs without a watcher thread for Ctrl-C: ~100 ns each on SIMD
// lanes, ~1 us on drivers, so at most ~65 ms before Python sees the signal.
constexpr double kInlineMechanismSteps = 65536.0;
using Mask = py::array_t<bool, py::array::c_style | py::array::forcecast>;

// work(stop) for step and rollout: a short one (at most kInlineMechanismSteps, a few ms) here
// without the GIL -- a learning loop's call of one step would otherwise start a thread each
// time; a long one on a thread of its own while this one, without the GIL, looks at Python's
// signals every 20 ms: Ctrl-C sets `stop` (every lane ends where it is) and its
// KeyboardInterrupt is raised here. std::invalid_argument becomes ValueError("<call>: ...").
template <class Work>
void runBatchWork(const char* call, double mechanism_steps, Work work) {
  std::atomic<bool> stop{false};
  std::unique_ptr<py::error_already_set> raised;
  try {
    if (mechanism_steps <= kInlineMechanismSteps) {
      py::gil_scoped_release release;
      work(stop);
    } else {
      raised = runStoppable(
          stop, [&] { work(stop); }, std::chrono::milliseconds(20));
    }
  } catch (const std::invalid_argument& e) {
    throw py::value_error(std::string(call) + ": " + e.what());
  }
  if (raised) throw *raised;
}

std::vector<bool> maskOf(const BatchSimulator& batch, const Mask& mask, const char* call) {
  if (mask.ndim() != 1 || static_cast<std::size_t>(mask.shape(0)) != batch.size())
    throw py::value_error(std::string(call) + ": mask must hold one bool per mechanism (" +
                          std::to_string(batch.size()) + ")");
  return std::vector<bool>(mask.data(), mask.data() + mask.shape(0));
}

Array states(const BatchSimulator& batch) {
  const py::ssize_t n = static_cast<py::ssize_t>(batch.size());
  Array out({n, py::ssize_t{4}});
  batch.states(out.mutable_data());
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

// kane_sim._core.ConfigError(text), as the loader's refusals reach Python.
[[noreturn]] void raiseConfigError(const std::string& text) {
  PyErr_SetString(py::module_::import("kane_sim._core").attr("ConfigError").ptr(), text.c_str());
  throw py::error_already_set();
}

// The schema rows of `names`, each one a number the batch takes directly (takenDirectly);
// ValueError "<call>: NAME is not ..." otherwise.
std::vector<const ParameterSpec*> directSpecs(const std::vector<std::string>& names,
                                              const char* call) {
  std::vector<const ParameterSpec*> specs;
  for (const std::string& name : names) {
    const ParameterSpec& spec = specOf(name);
    if (!takenDirectly(spec))
      throw py::value_error(std::string(call) + ": " + name +
                            " is not a number of the physics or the initial state");
    specs.push_back(&spec);
  }
  return specs;
}

// Whether a mechanism's rod inertia still follows its m and L: the base's file let it (it sets
// no mechanism.rod_inertia) and the mechanism's value is the derived one.
bool inertiaFollows(const Config& c, bool base_follows) {
  return base_follows && c.mechanism.rod_inertia ==
                             slenderRodInertia(c.mechanism.rod_mass, c.mechanism.rod_half_length);
}

// The batch's reconfigure, starting the mechanisms from `starts` (one per lane) when given;
// std::invalid_argument (nothing changed) becomes ValueError("set_params: ...").
void reconfigureBatch(BatchSimulator& b, const std::vector<std::size_t>& lanes,
                      const std::vector<Config>& configs,
                      const std::optional<std::vector<std::array<double, 4>>>& starts) {
  std::vector<State> from;
  if (starts) {
    if (starts->size() != lanes.size())
      throw py::value_error("set_params: one state per mechanism changed");
    for (const auto& x : *starts) from.push_back(State{x[0], x[1], x[2], x[3]});
  }
  try {
    b.reconfigure(lanes, configs, starts ? &from : nullptr);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(std::string("set_params: ") + e.what());
  }
}

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
      .def_static(
          "from_numbers",
          [](const PythonConfig& base, const std::vector<std::string>& names, const Array& values,
             const std::string& simd, bool vector_trig, int threads) {
            const std::vector<const ParameterSpec*> specs = directSpecs(names, "from_numbers");
            if (values.ndim() != 2 || static_cast<std::size_t>(values.shape(1)) != names.size())
              throw py::value_error("from_numbers: values must have shape (n, " +
                                    std::to_string(names.size()) + "), got " + shapeText(values));
            const std::size_t n = static_cast<std::size_t>(values.shape(0));
            if (n == 0) throw py::value_error("a batch needs at least one mechanism");
            // A base file without mechanism.rod_inertia: the inertia follows m and L per row.
            const bool inertia_from_mass = inertiaFollowsMass(base.tree());
            std::vector<Config> configs;
            std::string refused;
            // On a thread of its own while this one watches for Ctrl-C (10^6 rows take ~9 s).
            std::atomic<bool> stop{false};
            const std::unique_ptr<py::error_already_set> raised = runStoppable(
                stop,
                [&] {
                  try {
                    configs =
                        configsWithNumbers(base.config(), inertia_from_mass, specs, values.data(),
                                           n, static_cast<unsigned>(std::max(threads, 1)), &stop);
                  } catch (const MechanismConfigError& e) {
                    refused = e.what();
                  }
                },
                std::chrono::milliseconds(20));
            if (raised) throw *raised;
            if (!refused.empty()) raiseConfigError(refused);
            try {
              return std::make_unique<BatchSimulator>(std::move(configs),
                                                      BatchSettings{simd, vector_trig, threads});
            } catch (const std::invalid_argument& e) {
              throw py::value_error(e.what());
            }
          },
          py::arg("base"), py::arg("names"), py::arg("values"), py::arg("simd") = "auto",
          py::arg("vector_trig") = false, py::arg("threads") = 1,
          "n mechanisms from a base and a table of numbers (n, len(names)): physics and "
          "initial-state values stored by the loader's rules, no YAML per row")
      .def(
          "differences",
          [](const BatchSimulator& b, std::size_t lane, const PythonConfig& base) {
            if (lane >= b.size())
              throw py::index_error("config: mechanism " + std::to_string(lane) + " of " +
                                    std::to_string(b.size()));
            // What mechanism `lane`'s config holds that the base does not: the batch's own
            // record of it (its row, its changes, its seed), read back as config names.
            const Config& mine = b.config(lane);
            const Config& theirs = base.config();
            const bool derived = inertiaFollows(mine, inertiaFollowsMass(base.tree()));
            py::list out;
            for (const ParameterSpec& spec : parameterSchema()) {
              if (derived && spec.path() == "mechanism.rod_inertia") continue;  // follows m, L
              const ConfigField& f = spec.field;
              if (f.number || f.whole) {
                const double a = numericValue(spec, mine), c = numericValue(spec, theirs);
                if (std::memcmp(&a, &c, sizeof(a)) == 0) continue;
                if (f.whole)
                  out.append(py::make_tuple(spec.path(), static_cast<long long>(a)));
                else
                  out.append(py::make_tuple(spec.path(), a));
              } else if (f.flag) {
                if (numericValue(spec, mine) != numericValue(spec, theirs))
                  out.append(py::make_tuple(spec.path(), numericValue(spec, mine) != 0.0));
              } else if (valueText(spec, mine) != valueText(spec, theirs)) {
                out.append(py::make_tuple(spec.path(), valueText(spec, mine)));
              }
            }
            return out;
          },
          py::arg("lane"), py::arg("base"),
          "(name, value) of every parameter where the mechanism's config is not the base's.")
      .def_static(
          "inertia_follows_mass",
          [](const PythonConfig& base) { return inertiaFollowsMass(base.tree()); }, py::arg("base"),
          "Whether the base's file leaves the rod's inertia to its m and L.")
      .def_static(
          "takes_directly", [](const std::string& name) { return takenDirectly(specOf(name)); },
          py::arg("name"), "Whether from_numbers takes this parameter.")
      .def(
          "values",
          [](const BatchSimulator& b, const std::string& name,
             const std::optional<std::vector<std::size_t>>& lanes) -> py::object {
            const ParameterSpec& spec = specOf(name);
            std::vector<std::size_t> every;
            if (!lanes)
              for (std::size_t i = 0; i < b.size(); ++i) every.push_back(i);
            const std::vector<std::size_t>& chosen = lanes ? *lanes : every;
            for (std::size_t i : chosen)
              if (i >= b.size())
                throw py::index_error("values: mechanism " + std::to_string(i) + " of " +
                                      std::to_string(b.size()));
            if (spec.field.number || spec.field.whole) {
              Array out(static_cast<py::ssize_t>(chosen.size()));
              for (std::size_t k = 0; k < chosen.size(); ++k)
                out.mutable_data()[k] = numericValue(spec, b.config(chosen[k]));
              return std::move(out);
            }
            py::list out;
            for (std::size_t i : chosen) out.append(valueText(spec, b.config(i)));
            return std::move(out);
          },
          py::arg("name"), py::arg("lanes") = py::none(),
          "Every mechanism's (or those of `lanes`) value of a config name: numbers as an array, "
          "others as text.")
      .def_property_readonly("size", &BatchSimulator::size)
      .def_property_readonly("path", &BatchSimulator::path)
      .def_property_readonly("on_lanes", &BatchSimulator::onLanes)
      .def_property_readonly("sensors", &BatchSimulator::sensorsEnabled)
      .def(
          "step",
          [](BatchSimulator& b, const Array& actions, long steps, const py::object& mask) {
            if (actions.ndim() != 1 || static_cast<std::size_t>(actions.shape(0)) != b.size())
              throw py::value_error("step: actions must hold one value per mechanism (" +
                                    std::to_string(b.size()) + "), got shape " +
                                    shapeText(actions));
            std::vector<bool> active;
            if (!mask.is_none()) active = maskOf(b, mask.cast<Mask>(), "step");
            const std::vector<bool>* only = mask.is_none() ? nullptr : &active;
            Array out({static_cast<py::ssize_t>(b.size()), py::ssize_t{4}});
            double* rows = out.mutable_data();
            runBatchWork("step", static_cast<double>(steps) * static_cast<double>(b.size()),
                         [&](const std::atomic<bool>& stop) {
                           b.step(actions.data(), steps, only, &stop, rows);
                         });
            return out;
          },
          py::arg("actions"), py::arg("steps") = 1, py::arg("mask") = py::none())
      .def(
          "rollout",
          [](BatchSimulator& b, const Array& actions, long steps) {
            const py::ssize_t n = static_cast<py::ssize_t>(b.size());
            if (actions.ndim() != 2 || actions.shape(0) != n)
              throw py::value_error("rollout: actions must have shape (" + std::to_string(n) +
                                    ", T): one value per mechanism and time step, got " +
                                    shapeText(actions));
            const py::ssize_t horizon = actions.shape(1);
            for (py::ssize_t k = 0; k < n * horizon; ++k)
              if (!std::isfinite(actions.data()[k]))
                throw py::value_error("rollout: actions[" + std::to_string(k / horizon) + ", " +
                                      std::to_string(k % horizon) +
                                      "] = " + formatNumber(actions.data()[k]) + " is not finite");
            Array out({n, horizon + 1, py::ssize_t{4}});
            double* o = out.mutable_data();
            std::vector<double> now(4 * static_cast<std::size_t>(n));
            const auto record = [&](py::ssize_t t) {
              b.states(now.data());
              for (py::ssize_t i = 0; i < n; ++i)  // four stores (std::copy_n: a memmove call)
                for (int k = 0; k < 4; ++k) o[(i * (horizon + 1) + t) * 4 + k] = now[4 * i + k];
            };
            record(0);
            runBatchWork(
                "rollout",
                static_cast<double>(horizon) * static_cast<double>(steps) * static_cast<double>(n),
                [&](const std::atomic<bool>& stop) {
                  std::vector<double> column(static_cast<std::size_t>(n));
                  for (py::ssize_t t = 0; t < horizon && !stop; ++t) {
                    for (py::ssize_t i = 0; i < n; ++i) column[i] = actions.data()[i * horizon + t];
                    try {
                      b.step(column.data(), steps, nullptr, &stop);
                    } catch (const std::invalid_argument& e) {
                      throw std::invalid_argument("at time step " + std::to_string(t) + ": " +
                                                  e.what());
                    }
                    if (!stop) record(t + 1);
                  }
                });
            return out;
          },
          py::arg("actions"), py::arg("steps") = 1)
      .def(
          "reset",
          [](BatchSimulator& b, const Mask& mask) {
            b.reset(maskOf(b, mask, "reset"));
            return states(b);
          },
          py::arg("mask"))
      .def(
          "reseed",
          [](BatchSimulator& b, const Mask& mask, const std::vector<std::uint64_t>& seeds) {
            if (seeds.size() != b.size())
              throw py::value_error("reset: seeds must hold one per mechanism (" +
                                    std::to_string(b.size()) + ")");
            b.reseed(maskOf(b, mask, "reset"), seeds);
            return states(b);
          },
          py::arg("mask"), py::arg("seeds"))
      .def(
          "reconfigure",
          [](BatchSimulator& b, const std::vector<std::size_t>& lanes,
             const std::vector<const PythonConfig*>& configs,
             const std::optional<std::vector<std::array<double, 4>>>& starts) {
            std::vector<Config> changed;
            for (const PythonConfig* c : configs) changed.push_back(c->config());
            reconfigureBatch(b, lanes, changed, starts);
            return states(b);
          },
          py::arg("lanes"), py::arg("configs"), py::arg("starts") = py::none(),
          "Mechanisms lanes[k] take configs[k] and start afresh from it (time 0).")
      .def(
          "reconfigure_numbers",
          [](BatchSimulator& b, const std::vector<std::size_t>& lanes,
             const std::vector<std::string>& names, const Array& values,
             bool base_inertia_follows_mass,
             const std::optional<std::vector<std::array<double, 4>>>& starts) {
            const std::vector<const ParameterSpec*> specs = directSpecs(names, "set_params");
            if (values.ndim() != 2 || static_cast<std::size_t>(values.shape(0)) != lanes.size() ||
                static_cast<std::size_t>(values.shape(1)) != names.size())
              throw py::value_error("set_params: values must have shape (" +
                                    std::to_string(lanes.size()) + ", " +
                                    std::to_string(names.size()) + "), got " + shapeText(values));
            // Each mechanism's config now with the numbers written in, by the loader's rules;
            // every row checked before any mechanism changes.
            for (std::size_t lane : lanes)
              if (lane >= b.size())
                throw py::index_error("set_params: mechanism " + std::to_string(lane) + " of " +
                                      std::to_string(b.size()));
            std::vector<Config> changed(lanes.size());
            std::vector<std::string> refused(lanes.size());
            // ~15 us a row, on the batch's threads. Many rows (over ~60 ms) on a thread of its
            // own while this one watches for Ctrl-C: stopped, nothing has changed.
            std::atomic<bool> stop{false};
            const auto build = [&] {
              parallelBlocks(static_cast<long>(lanes.size()), b.threads(), [&](long k0, long k1) {
                for (long k = k0; k < k1 && !stop.load(std::memory_order_relaxed); ++k) {
                  const std::size_t r = static_cast<std::size_t>(k);
                  try {
                    // The rod's inertia follows m and L where the base's file let it and this
                    // mechanism's inertia still does.
                    const Config& now = b.config(lanes[r]);
                    changed[r] =
                        configWithNumbers(now, inertiaFollows(now, base_inertia_follows_mass),
                                          specs, values.data() + r * names.size());
                  } catch (const ConfigError& e) {
                    refused[r] = e.what();
                  }
                }
              });
            };
            if (lanes.size() <= 4096) {
              py::gil_scoped_release release;
              build();
            } else {
              const std::unique_ptr<py::error_already_set> raised =
                  runStoppable(stop, build, std::chrono::milliseconds(20));
              if (raised) throw *raised;
            }
            for (std::size_t k = 0; k < lanes.size(); ++k)  // the first refused row is named
              if (!refused[k].empty())
                raiseConfigError("set_params: mechanism " + std::to_string(lanes[k]) + ": " +
                                 refused[k]);
            reconfigureBatch(b, lanes, changed, starts);
            return states(b);
          },
          py::arg("lanes"), py::arg("names"), py::arg("values"),
          py::arg("base_inertia_follows_mass"), py::arg("starts") = py::none(),
          "Mechanisms lanes[k] with values[k] written into their configs by the loader's rules "
          "(the rod's inertia following m and L where the base's file and the mechanism let it), "
          "started afresh.")
      .def(
          "set_states",
          [](BatchSimulator& b, const Array& x, const Mask& mask) {
            const std::vector<bool> chosen = maskOf(b, mask, "set_states");
            if (x.ndim() != 2 || static_cast<std::size_t>(x.shape(0)) != b.size() ||
                x.shape(1) != 4)
              throw py::value_error("set_states: states must have shape (" +
                                    std::to_string(b.size()) +
                                    ", 4) (q1, q2, u1, u2 of each "
                                    "mechanism), got " +
                                    shapeText(x));
            const auto at = [&x](std::size_t i) {
              const double* v = x.data() + 4 * i;
              return State{v[0], v[1], v[2], v[3]};
            };
            // Every chosen state is checked before any is set: a refusal changes nothing.
            for (std::size_t i = 0; i < b.size(); ++i) {
              if (!chosen[i]) continue;
              const Status status = b.checkState(i, at(i));
              if (!status.ok)
                throw py::value_error("set_states: mechanism " + std::to_string(i) + ": " +
                                      status.error);
            }
            for (std::size_t i = 0; i < b.size(); ++i)
              if (chosen[i]) static_cast<void>(b.setState(i, at(i)));
            return states(b);
          },
          py::arg("states"), py::arg("mask"))
      .def(
          "check_state",
          [](const BatchSimulator& b, std::size_t i, const std::array<double, 4>& x) {
            if (i >= b.size())
              throw py::index_error("check_state: mechanism " + std::to_string(i) + " of " +
                                    std::to_string(b.size()));
            const Status status = b.checkState(i, State{x[0], x[1], x[2], x[3]});
            return status.ok ? std::string() : status.error;
          },
          py::arg("mechanism"), py::arg("state"),
          "'' when set_states would accept state for that mechanism, else why not")
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
