// kane_sim._core.Simulator: the one driver (SimDriver) and the one offline loop (runProfile) that
// `simulate` runs, with results as NumPy arrays named like simulate's CSV columns.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "kane_sim/format_number.h"
#include "kane_sim/model/generated_mechanism.h"
#include "kane_sim/sim/csv_format.h"
#include "kane_sim/sim/output_grid.h"
#include "kane_sim/sim/profile_commands.h"
#include "kane_sim/sim/sim_driver.h"
#include "kane_sim/sim/state_rates.h"
#include "python_layer.h"

namespace kane_sim {
namespace python {
namespace {

using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

// Python's signals are looked at (with the GIL) this often in a run without the GIL.
constexpr long kSignalCheckSteps = 20000;
// A result larger than this many values is refused before anything runs (16 GiB of doubles).
constexpr double kMaxResultValues = 2.0 * 1024 * 1024 * 1024;
// Events kept for Simulator.events() between two calls.
constexpr size_t kMaxEvents = 1000;

// A refused step, with the driver's message (a RuntimeError in Python).
struct StepRefused : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::string num(double v) { return formatNumber(v); }

// A Python callable f(t, state) -> torque, called before every step with the GIL held.
class CallableCommands {
 public:
  explicit CallableCommands(py::function f) : f_(std::move(f)) {}
  void update(SimDriver& driver) {
    const State& x = driver.simulator().state();
    Array state(4);
    double* s = state.mutable_data();
    s[0] = x.q1, s[1] = x.q2, s[2] = x.u1, s[3] = x.u2;
    const py::object out = f_(driver.time(), state);
    double value;
    try {
      // A float, or anything with __float__ (ints, NumPy scalars), but no complex: its real
      // part would be a silent guess.
      if (PyComplex_Check(out.ptr()) || !PyNumber_Check(out.ptr())) throw py::cast_error();
      value = PyFloat_AsDouble(out.ptr());
      if (value == -1.0 && PyErr_Occurred()) {
        if (!PyErr_ExceptionMatches(PyExc_OverflowError)) throw py::error_already_set();
        PyErr_Clear();
        throw py::value_error(
            "torque callable returned a number beyond the range of a float "
            "at t = " +
            num(driver.time()) + " s");
      }
    } catch (const py::cast_error&) {
      throw py::type_error("torque callable returned " +
                           std::string(py::str(py::type::of(out).attr("__name__"))) +
                           " at t = " + num(driver.time()) + " s, expected a float");
    }
    if (!std::isfinite(value))
      throw py::value_error("torque callable returned " + num(value) +
                            " at t = " + num(driver.time()) + " s: values must be finite");
    last_ = value;
    sendCommand(driver, value);
  }
  double last() const { return last_; }

 private:
  py::function f_;
  double last_ = 0.0;
};

// Sensor readings (sensors.enabled) as they reach joint_states: taken off the driver after every
// step, so that none piles up in a long run, and handed to Python as arrays.
class Readings {
 public:
  static constexpr long kValuesPerReading = 2 + 2 * kNumJoints;
  void takeFrom(SimDriver& driver) {
    SensorReading r;
    while (driver.takeSensorReading(&r)) {
      arrival_.push_back(driver.time());
      sample_.push_back(r.sample_time);
      position_.insert(position_.end(), r.joints.position.begin(), r.joints.position.end());
      velocity_.insert(velocity_.end(), r.joints.velocity.begin(), r.joints.velocity.end());
    }
  }
  // {"t": arrival [s], "sample_t" [s], "position": (N, 4), "velocity": (N, 4)}; joints in
  // joint_states' order: crank, coupler, slider 3, slider 4.
  py::dict toDict() const {
    const py::ssize_t n = static_cast<py::ssize_t>(arrival_.size());
    py::dict out;
    out["t"] = Array(n, arrival_.data());
    out["sample_t"] = Array(n, sample_.data());
    out["position"] = Array({n, py::ssize_t{kNumJoints}}, position_.data());
    out["velocity"] = Array({n, py::ssize_t{kNumJoints}}, velocity_.data());
    return out;
  }
  void clear() { *this = Readings(); }

 private:
  std::vector<double> arrival_, sample_, position_, velocity_;
};

// One call at a time into a simulator: a run releases the GIL (another Python thread may call
// in meanwhile) and a torque callable runs inside one (it may call back); either would change the
// driver in the middle of a step. The second call is refused (RuntimeError), nothing changes.
class Exclusive {
 public:
  Exclusive(std::atomic<bool>& busy, const char* call) : busy_(busy) {
    if (busy_.exchange(true))
      throw std::runtime_error(std::string(call) +
                               ": the Simulator is in a run or step (from another thread, or its "
                               "torque callable calls it); one call at a time");
  }
  ~Exclusive() { busy_ = false; }
  Exclusive(const Exclusive&) = delete;
  Exclusive& operator=(const Exclusive&) = delete;

 private:
  std::atomic<bool>& busy_;
};

class PythonSimulator {
 public:
  explicit PythonSimulator(const PythonConfig& config)
      : config_(config),
        driver_(config.config(), [this](const SimEvent& e) { onEvent(e); }),
        held_(driver_.servoMode() ? driver_.snapshot().servo.setpoint : 0.0) {}

  const PythonConfig& config() const { return config_; }
  double time() const { return driver_.time(); }
  std::uint64_t ticks() const { return driver_.ticks(); }
  double stepSize() const { return driver_.simulator().stepSize(); }
  bool servoMode() const { return driver_.servoMode(); }

  Array state() const {
    const Exclusive exclusive(busy_, "state");
    return stateArray();
  }

  void setState(const Array& x) {
    const Exclusive exclusive(busy_, "set_state");
    if (x.ndim() != 1 || x.shape(0) != 4)
      throw py::value_error("set_state: state must be 4 numbers (q1, q2, u1, u2), got shape " +
                            shapeText(x));
    const double* v = x.data();
    const Status status = driver_.setState(State{v[0], v[1], v[2], v[3]});
    if (!status.ok) throw py::value_error("set_state: " + status.error);
  }

  void reset() {
    const Exclusive exclusive(busy_, "reset");
    driver_.reset();
    held_ = driver_.servoMode() ? driver_.snapshot().servo.setpoint : 0.0;
  }

  // The torque [N m] (servo modes: the setpoint) held from now on.
  void setTorque(double value) {
    const Exclusive exclusive(busy_, "set_torque");
    if (!std::isfinite(value))
      throw py::value_error(std::string(servoMode() ? "setpoint" : "torque") +
                            " must be finite, got " + num(value));
    if (sendCommand(driver_, value) == TorqueCommand::Verdict::kRejected)
      throw py::value_error(lastEventOr("the command " + num(value) + " was refused"));
    held_ = value;
  }
  double heldTorque() const { return held_; }

  // n steps with the held torque (re-sent, so command.timeout never lapses); Ctrl-C stops them.
  Array step(long n) {
    const Exclusive exclusive(busy_, "step");
    if (n < 0) throw py::value_error("step: n must be >= 0, got " + std::to_string(n));
    const TorqueProfile profile = TorqueProfile::constant(held_);
    ProfileCommands commands(profile, config_.config().command.timeout);
    commands.update(driver_);
    const RunEnd end = runWithoutGil(
        commands, n, std::max(n, 1L), [](const SimDriver&) {}, &pending_readings_);
    if (end == RunEnd::kStepRefused) throw StepRefused(lastEventOr("a step was refused"));
    return stateArray();
  }

  // The run: rows every 1/output_rate s (default: every physics step) from now to now +
  // duration; every column of simulate's CSV, as arrays (states_only: t, q1, q2, u1, u2 alone,
  // without a snapshot per row: what a fit's thousands of replays need).
  py::dict run(double duration, const py::object& torque, const py::object& output_rate_arg,
               bool states_only) {
    const Exclusive exclusive(busy_, "run");
    const double physics_rate = config_.config().simulation.physics_rate;
    double output_rate = physics_rate;
    if (!output_rate_arg.is_none()) {
      try {
        output_rate = output_rate_arg.cast<double>();
      } catch (const py::cast_error&) {
        throw py::type_error("run: output_rate must be a number [Hz] or None, got " +
                             typeName(output_rate_arg));
      }
    }
    OutputGrid grid;
    try {
      grid = outputGrid(physics_rate, duration, output_rate, "duration", "output_rate");
    } catch (const std::invalid_argument& e) {
      throw py::value_error(std::string("run: ") + e.what());
    }
    const long columns = states_only ? StateRows::kColumns : static_cast<long>(csvColumns().size());
    const long rows = grid.rows + 1;
    // The sensor readings come back too: arrival and sample time, 4 positions, 4 speeds each.
    const double readings_count = duration * sensorReadingRate(config_.config());
    if (static_cast<double>(rows) * columns + readings_count * Readings::kValuesPerReading >
        kMaxResultValues)
      throw py::value_error("run: " + num(static_cast<double>(rows)) + " rows of " +
                            std::to_string(columns) + " columns and " + num(readings_count) +
                            " sensor readings are more than 16 GiB: use a lower output_rate, "
                            "sensors.rate or a shorter duration");
    Rows out(states_only ? 0 : columns, states_only ? 0 : rows);
    StateRows states(states_only ? rows : 0);
    Readings readings;
    const auto sample = [&](const SimDriver& d) {
      if (states_only)
        states.add(d);
      else
        out.add(d.snapshot());
    };
    const auto finish = [&]() {
      last_result_ = states_only ? states.toDict() : out.toDict();
      last_readings_ = readings.toDict();
    };
    RunEnd end = RunEnd::kFinished;
    try {
      if (py::isinstance<py::function>(torque)) {
        CallableCommands commands(torque.cast<py::function>());
        commands.update(driver_);
        readings.takeFrom(driver_);
        sample(driver_);
        end = runProfile(
            driver_, commands, grid.steps(), grid.steps_per_row, nullptr,
            [this, &readings](const SimDriver&) { readings.takeFrom(driver_); }, sample);
        held_ = commands.last();
      } else if (py::isinstance<py::array>(torque) || py::isinstance<py::list>(torque)) {
        const Array values = Array::ensure(torque);
        if (!values)  // not convertible to numbers (NumPy's error is cleared by ensure)
          throw py::type_error("run: a torque array must hold numbers, got " + typeName(torque));
        checkTorqueArray(values, grid.steps());
        SampledCommands commands(values.data(), grid.steps(), driver_.ticks());
        commands.update(driver_);
        readings.takeFrom(driver_);
        sample(driver_);
        end = runWithoutGil(commands, grid.steps(), grid.steps_per_row, sample, &readings);
        held_ = commands.last();
      } else {
        const TorqueProfile profile = profileOf(torque);
        ProfileCommands commands(profile, config_.config().command.timeout);
        commands.update(driver_);
        readings.takeFrom(driver_);
        sample(driver_);
        end = runWithoutGil(commands, grid.steps(), grid.steps_per_row, sample, &readings);
        held_ = profile.at(driver_.time());
      }
    } catch (...) {
      finish();  // what was computed until the exception
      throw;
    }
    finish();
    py::dict result = last_result_;
    if (end == RunEnd::kStepRefused) throw StepRefused(lastEventOr("a step was refused"));
    return result;
  }

  // The result of the last run, also when it ended with an exception (Ctrl-C, a refused step,
  // the torque callable's error): the rows computed until then.
  py::object lastResult() const { return last_result_; }
  // The sensor readings of the last run (empty arrays with the sensors off).
  py::object lastReadings() const { return last_readings_; }
  // Those that step() collected since the last call.
  py::dict takeReadings() {
    const Exclusive exclusive(busy_, "take_readings");
    py::dict out = pending_readings_.toDict();
    pending_readings_.clear();
    return out;
  }

  py::dict snapshot() const {
    const Exclusive exclusive(busy_, "snapshot");
    const Snapshot s = driver_.snapshot();
    py::dict out;
    for (const CsvColumn& c : csvColumns()) out[c.name.c_str()] = c.value(s);
    out["resting_contact"] = s.resting_contact;
    out["reactions_determinate"] = s.constraint_forces.determinate;
    return out;
  }

  // x' = (q1', q2', u1', u2') for each row of `states` (N x 4, or one state of 4) at the torque
  // (a number, or one per state): the equations the simulator steps, without the GIL, on every
  // core for large N.
  Array rates(const Array& states, const Array& torque) const {
    const Exclusive exclusive(busy_, "rates");
    const bool single = states.ndim() == 1;
    if (!(single ? states.shape(0) == 4 : states.ndim() == 2 && states.shape(1) == 4))
      throw py::value_error("rates: states must have shape (N, 4) or (4,), got " +
                            shapeText(states));
    const long n = single ? 1 : states.shape(0);
    if (!(torque.ndim() == 0 || (torque.ndim() == 1 && torque.shape(0) == n)))
      throw py::value_error("rates: torque must be a number or have shape (" + std::to_string(n) +
                            ",), got " + shapeText(torque));
    const double* x = states.data();
    const double* m = torque.data();
    const bool per_state = torque.ndim() == 1;
    for (long i = 0; i < n * 4; ++i)
      if (!std::isfinite(x[i]))
        throw py::value_error("rates: states[" + std::to_string(i / 4) + ", " +
                              std::to_string(i % 4) + "] is " + num(x[i]) +
                              ": states must be finite");
    // The drive never delivers more than command.torque_limit (commands are clamped to it).
    const double limit = config_.config().command.torque_limit;
    for (long i = 0; i < (per_state ? n : 1); ++i)
      if (!std::isfinite(m[i]) || std::abs(m[i]) > limit)
        throw py::value_error("rates: torque" + (per_state ? "[" + std::to_string(i) + "]" : "") +
                              " is " + num(m[i]) + ": torques must be finite and within " +
                              "command.torque_limit " + num(limit) + " N m");
    Array out = single ? Array(4) : Array({n, 4L});
    double* y = out.mutable_data();
    long bad;
    {
      py::gil_scoped_release release;
      bad = stateRates(driver_.simulator(), x, n, m, per_state, y);
    }
    // A state whose rates are not finite is refused by row, in set_state's words (beyond the
    // mechanism's scale, a non-finite energy or u').
    if (bad >= 0) {
      const State s{x[4 * bad], x[4 * bad + 1], x[4 * bad + 2], x[4 * bad + 3]};
      const Status usable = driver_.simulator().checkUsable(s);
      throw py::value_error(
          "rates: states[" + std::to_string(bad) +
          "]: " + (usable.ok ? Simulator::stateText(s) + " gives non-finite rates" : usable.error));
    }
    return out;
  }

  py::object get(const std::string& name) const { return config_.get(name); }

  // A parameter changed at run time, as dynamic_reconfigure does in the node (at the current
  // state; the energy jump booked as parameter_energy). Others are fixed once built.
  void set(const std::string& name, const std::string& value_yaml) {
    const Exclusive exclusive(busy_, "set");
    PythonConfig next = config_.with(name, value_yaml);  // ConfigError: nothing changes
    if (!PythonConfig::reconfigurable(name))
      throw py::value_error(name +
                            " is fixed once a Simulator is built (the node does not reconfigure "
                            "it either): set it on the Config and build a new Simulator");
    driver_.reconfigure(next.config());
    config_ = std::move(next);
  }

  std::vector<std::pair<double, std::string>> takeEvents() {
    const Exclusive exclusive(busy_, "events");
    std::vector<std::pair<double, std::string>> out(events_.begin(), events_.end());
    events_.clear();
    return out;
  }

 private:
  Array stateArray() const {
    const State& x = driver_.simulator().state();
    Array out(4);
    double* o = out.mutable_data();
    o[0] = x.q1, o[1] = x.q2, o[2] = x.u1, o[3] = x.u2;
    return out;
  }

  // runProfile without the GIL (other Python threads run meanwhile), looking at Python's signals
  // every kSignalCheckSteps steps. A handler that raised (Ctrl-C's KeyboardInterrupt) stops the
  // run and is thrown here, with the GIL back -- also when it came on the run's last step, which
  // ends the run as finished: the exception is fetched when it is raised, never left pending
  // (a result returned with an exception set is Python's SystemError).
  // The sensor readings due after each step go to `readings`.
  template <typename Commands, typename OnSample>
  RunEnd runWithoutGil(Commands& commands, long steps, long steps_per_sample, OnSample on_sample,
                       Readings* readings) {
    std::atomic<bool> stop{false};
    std::unique_ptr<py::error_already_set> raised;
    const bool sensors = driver_.sensorsEnabled();
    const auto check_signals = [this, &stop, &raised, sensors, readings](const SimDriver& d) {
      if (sensors) readings->takeFrom(driver_);
      if (d.ticks() % kSignalCheckSteps != 0 || raised) return;
      py::gil_scoped_acquire acquire;
      if (PyErr_CheckSignals() != 0) {
        raised = std::make_unique<py::error_already_set>();  // fetches and clears it
        stop = true;
      }
    };
    RunEnd end;
    {
      py::gil_scoped_release release;
      end = runProfile(driver_, commands, steps, steps_per_sample, &stop, check_signals, on_sample);
    }
    if (raised) throw *raised;
    return end;
  }

  // Snapshot columns, column-major so that every column is one contiguous array.
  class Rows {
   public:
    Rows(long columns, long capacity) : columns_(columns), capacity_(capacity) {
      data_.resize(static_cast<size_t>(columns * capacity));
    }
    void add(const Snapshot& s) {
      if (filled_ == capacity_) return;
      long c = 0;
      for (const CsvColumn& col : csvColumns())
        data_[static_cast<size_t>(c++ * capacity_ + filled_)] = col.value(s);
      ++filled_;
    }
    py::dict toDict() const {
      py::dict out;
      long c = 0;
      for (const CsvColumn& col : csvColumns())
        out[col.name.c_str()] = Array(filled_, data_.data() + c++ * capacity_);
      return out;
    }

   private:
    long columns_, capacity_, filled_ = 0;
    std::vector<double> data_;
  };

  // t, q1, q2, u1, u2 of each row, straight from the driver (no snapshot).
  class StateRows {
   public:
    static constexpr long kColumns = 5;
    explicit StateRows(long capacity) : capacity_(capacity) {
      data_.resize(static_cast<size_t>(kColumns * capacity));
    }
    void add(const SimDriver& d) {
      if (filled_ == capacity_) return;
      const State& x = d.simulator().state();
      const double values[kColumns] = {d.time(), x.q1, x.q2, x.u1, x.u2};
      for (long c = 0; c < kColumns; ++c)
        data_[static_cast<size_t>(c * capacity_ + filled_)] = values[c];
      ++filled_;
    }
    py::dict toDict() const {
      static const char* const names[kColumns] = {"t", "q1", "q2", "u1", "u2"};
      py::dict out;
      for (long c = 0; c < kColumns; ++c)
        out[names[c]] = Array(filled_, data_.data() + c * capacity_);
      return out;
    }

   private:
    long capacity_, filled_ = 0;
    std::vector<double> data_;
  };

  static std::string typeName(const py::handle& h) {
    return std::string(py::str(py::type::of(h).attr("__name__")));
  }

  static void checkTorqueArray(const Array& values, long steps) {
    if (values.ndim() != 1 || values.shape(0) != steps)
      throw py::value_error("run: a torque array holds one value per physics step: shape (" +
                            std::to_string(steps) + ",) for this duration, got " +
                            shapeText(values));
    for (long i = 0; i < steps; ++i)
      if (!std::isfinite(values.data()[i]))
        throw py::value_error("run: torque[" + std::to_string(i) + "] is " + num(values.data()[i]) +
                              ": values must be finite");
  }

  TorqueProfile profileOf(const py::object& torque) const {
    if (torque.is_none()) return TorqueProfile::constant(held_);
    if (py::isinstance<TorqueProfile>(torque)) {
      TorqueProfile profile = torque.cast<TorqueProfile>();
      try {  // a table's header against the config's mode
        profile.checkPlaysAs(servoMode());
      } catch (const std::invalid_argument& e) {
        throw py::value_error(std::string("run: torque: ") + e.what());
      }
      return profile;
    }
    double value;
    try {
      value = torque.cast<double>();
    } catch (const py::cast_error&) {
      throw py::type_error(
          "run: torque must be a number, a TorqueProfile, an array of one value per step or a "
          "callable f(t, state), got " +
          std::string(py::str(py::type::of(torque).attr("__name__"))));
    }
    if (!std::isfinite(value))
      throw py::value_error("run: torque must be finite, got " + num(value));
    return TorqueProfile::constant(value);
  }

  void onEvent(const SimEvent& e) {
    // The same report again (a held torque beyond the limit is clamped at every re-send): said
    // once until the events are taken, as simulate says it once.
    for (const auto& seen : events_)
      if (seen.second == e.message) return;
    events_.emplace_back(e.time, e.message);
    if (events_.size() > kMaxEvents) events_.pop_front();
  }
  std::string lastEventOr(const std::string& fallback) const {
    return events_.empty() ? fallback : events_.back().second;
  }

  PythonConfig config_;
  std::deque<std::pair<double, std::string>> events_;
  SimDriver driver_;
  double held_;                            // the torque (or setpoint) in force, re-sent by step()
  mutable std::atomic<bool> busy_{false};  // a call is in progress (Exclusive)
  py::object last_result_ = py::none();
  py::object last_readings_ = py::none();
  Readings pending_readings_;
};

}  // namespace

void bindSimulator(py::module_& m) {
  static py::exception<StepRefused> step_refused(m, "StepRefused", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const StepRefused& e) {
      PyErr_SetString(step_refused.ptr(), e.what());
    }
  });
  m.def(
      "output_columns",
      [] {
        py::list out;
        for (const CsvColumn& c : csvColumns())
          out.append(
              py::make_tuple(c.name, c.group, c.key, c.message_field, c.message_index, c.formerly));
        return out;
      },
      "The output quantities in CSV order: (column, group, key, message field, index or -1, "
      "the column's former name or '').");
  py::class_<PythonSimulator>(m, "Simulator")
      .def(py::init<const PythonConfig&>(), py::arg("config"))
      .def_property_readonly("config", &PythonSimulator::config)
      .def_property_readonly("time", &PythonSimulator::time)
      .def_property_readonly("ticks", &PythonSimulator::ticks)
      .def_property_readonly("step_size", &PythonSimulator::stepSize)
      .def_property_readonly("servo_mode", &PythonSimulator::servoMode)
      .def_property_readonly("state", &PythonSimulator::state)
      .def("set_state", &PythonSimulator::setState, py::arg("state"))
      .def("reset", &PythonSimulator::reset)
      .def("set_torque", &PythonSimulator::setTorque, py::arg("torque"))
      .def_property_readonly("commanded_torque", &PythonSimulator::heldTorque)
      .def("step", &PythonSimulator::step, py::arg("n") = 1)
      .def("run", &PythonSimulator::run, py::arg("duration"), py::arg("torque") = py::none(),
           py::arg("output_rate") = py::none(), py::arg("states_only") = false)
      .def_property_readonly("last_result", &PythonSimulator::lastResult)
      .def_property_readonly("last_readings", &PythonSimulator::lastReadings)
      .def("take_readings", &PythonSimulator::takeReadings)
      .def("snapshot", &PythonSimulator::snapshot)
      .def("rates", &PythonSimulator::rates, py::arg("states"), py::arg("torque") = 0.0)
      .def("get", &PythonSimulator::get, py::arg("name"))
      .def("set", &PythonSimulator::set, py::arg("name"), py::arg("value_yaml"))
      .def("take_events", &PythonSimulator::takeEvents);
}

}  // namespace python
}  // namespace kane_sim
