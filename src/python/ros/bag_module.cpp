// kane_sim._bag: a bag's JointState topic (and ~input_log) as NumPy columns
// (kane_sim/ros/joint_state_bag.h), for identify. Apart from kane_sim._core, which stays ROS-free:
// this one links rosbag.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <functional>

#include "kane_sim/ros/joint_state_bag.h"

namespace py = pybind11;

namespace {

py::array_t<double> array(std::vector<double>&& values) {
  auto* owned = new std::vector<double>(std::move(values));
  py::capsule free_when_done(owned, [](void* p) { delete static_cast<std::vector<double>*>(p); });
  return py::array_t<double>(static_cast<py::ssize_t>(owned->size()), owned->data(),
                             free_when_done);
}

// `read(interrupted)`'s result: a BagReadError becomes ValueError, and Ctrl-C (Python's signal
// handler, which `interrupted` asks between blocks of messages) its KeyboardInterrupt.
template <typename Read>
auto readTranslated(Read read) {
  std::unique_ptr<py::error_already_set> raised;
  const std::function<bool()> interrupted = [&raised]() {
    if (PyErr_CheckSignals() == 0) return false;
    raised = std::make_unique<py::error_already_set>();
    return true;
  };
  try {
    return read(interrupted);
  } catch (const kane_sim::BagReadError& e) {
    if (raised) throw *raised;
    throw py::value_error(e.what());
  }
}

py::dict readJointStates(const std::string& path, const std::string& topic, const std::string& a,
                         const std::string& b, bool skip_unusable) {
  kane_sim::JointStateColumns c = readTranslated([&](const std::function<bool()>& interrupted) {
    return kane_sim::readJointStates(
        path, topic, a, b, interrupted,
        skip_unusable ? kane_sim::UnusableMessages::kSkip : kane_sim::UnusableMessages::kStop);
  });
  py::dict out;
  out["unstamped"] = c.unstamped;
  out["skipped"] = c.skipped;
  out["skip_notes"] = c.skip_notes;
  out["t"] = array(std::move(c.t));
  out["position_a"] = array(std::move(c.position_a));
  out["position_b"] = array(std::move(c.position_b));
  out["effort_a"] = array(std::move(c.effort_a));
  if (c.has_velocity || (skip_unusable && c.anyVelocity())) {
    if (!c.has_velocity)
      out["velocity_rows"] = py::array_t<std::uint8_t>(
          static_cast<py::ssize_t>(c.velocity_rows.size()), c.velocity_rows.data());
    out["velocity_a"] = array(std::move(c.velocity_a));
    out["velocity_b"] = array(std::move(c.velocity_b));
  }
  return out;
}

template <typename T>
py::array_t<T> array(const std::vector<T>& values) {
  py::array_t<T> out(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

py::dict readInputLog(const std::string& path, const std::string& topic) {
  const kane_sim::InputLogColumns c = readTranslated([&](const std::function<bool()>& interrupted) {
    return kane_sim::readInputLog(path, topic, interrupted);
  });
  py::dict out;
  out["t"] = array(c.t);
  out["seq"] = array(c.seq);
  out["tick"] = array(c.tick);
  out["kind"] = array(c.kind);
  out["value"] = array(c.value);
  return out;
}

std::map<std::string, std::string> topicTypes(const std::string& path) {
  try {
    return kane_sim::bagTopicTypes(path);
  } catch (const kane_sim::BagReadError& e) {
    throw py::value_error(e.what());
  }
}

}  // namespace

PYBIND11_MODULE(_bag, m) {
  m.doc() = "A bag's sensor_msgs/JointState topic as NumPy columns (rosbag's C++ reader)";
  m.def("topic_types", &topicTypes, py::arg("path"),
        "{topic: message type} of the bag at path; ValueError when it is not a readable bag");
  m.def("read_joint_states", &readJointStates, py::arg("path"), py::arg("topic"), py::arg("a"),
        py::arg("b"), py::arg("skip_unusable") = false,
        "t, position_a, position_b, effort_a (and velocity_a, velocity_b when every message has "
        "them) of joints a and b; ValueError naming what a message lacks. skip_unusable: leave "
        "such messages out (counted in skipped, the first named in skip_notes), and give the "
        "velocities when some messages have them, with velocity_rows (1 where they do)");
  m.def("read_input_log", &readInputLog, py::arg("path"), py::arg("topic"),
        "t (header stamps), seq, tick, kind (0 torque, 1 setpoint, 2 reset, 3 set_state) and "
        "value of a kane_sim/InputLog topic, one row per message; ValueError when the topic has "
        "no messages or another type");
}
