// Helpers for the node tests (rostest): record a topic, wait for conditions on wall time.
#ifndef KANE_SIM_TEST_NODE_TEST_UTILS_H
#define KANE_SIM_TEST_NODE_TEST_UTILS_H

#include <chrono>
#include <cmath>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <dynamic_reconfigure/Reconfigure.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_msgs/Float64.h>

#include "kane_sim/MechanismState.h"

namespace kane_sim {
namespace test {

// Waits (wall time) until `done` holds; false on timeout.
inline bool waitFor(const std::function<bool()>& done, double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (std::chrono::steady_clock::now() < deadline) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return done();
}

inline void sleepWall(double seconds) {
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
}

// Keeps every message of a topic (callbacks run on the test's AsyncSpinner). The messages live
// in storage the callback shares: a callback still running on a spinner thread when the
// Recorder goes out of scope (unsubscribing does not wait for it) writes into live memory.
template <class M>
class Recorder {
 public:
  Recorder(ros::NodeHandle& nh, const std::string& topic, uint32_t queue = 10000)
      : store_(std::make_shared<Store>()) {
    std::shared_ptr<Store> store = store_;
    sub_ = nh.subscribe<M>(topic, queue, [store](const typename M::ConstPtr& msg) {
      std::lock_guard<std::mutex> lock(store->mutex);
      store->messages.push_back(*msg);
    });
  }
  std::vector<M> messages() const {
    std::lock_guard<std::mutex> lock(store_->mutex);
    return store_->messages;
  }
  size_t count() const {
    std::lock_guard<std::mutex> lock(store_->mutex);
    return store_->messages.size();
  }
  M last() const {
    std::lock_guard<std::mutex> lock(store_->mutex);
    return store_->messages.back();
  }
  void clear() {
    std::lock_guard<std::mutex> lock(store_->mutex);
    store_->messages.clear();
  }
  bool waitForCount(size_t n, double timeout_s) const {
    return waitFor([&] { return count() >= n; }, timeout_s);
  }
  bool connected() const { return sub_.getNumPublishers() > 0; }

 private:
  struct Store {
    std::mutex mutex;
    std::vector<M> messages;
  };
  std::shared_ptr<Store> store_;
  ros::Subscriber sub_;
};

// Publishes and waits until the sim is listening, so the first message is not lost.
template <class M>
ros::Publisher connectedPublisher(ros::NodeHandle& nh, const std::string& topic) {
  ros::Publisher pub = nh.advertise<M>(topic, 10);
  waitFor([&] { return pub.getNumSubscribers() > 0; }, 10.0);
  return pub;
}

// One torque_command (or setpoint) value.
inline void send(ros::Publisher& pub, double value) {
  std_msgs::Float64 msg;
  msg.data = value;
  pub.publish(msg);
}

// Sets one double parameter of the node under test through dynamic_reconfigure; returns the
// value the server answers with (the one in force: a refused value comes back reverted).
inline double reconfigure(const std::string& name, double value,
                          const std::string& server = "kane_sim") {
  dynamic_reconfigure::Reconfigure srv;
  dynamic_reconfigure::DoubleParameter p;
  p.name = name;
  p.value = value;
  srv.request.config.doubles.push_back(p);
  EXPECT_TRUE(ros::service::waitForService(server + "/set_parameters", ros::Duration(10)));
  // roscpp now and then loses a service call on a loaded machine (ros/ros_comm#1976: the node
  // logged "Exception thrown while while deserializing service call: Buffer Overrun" and applied
  // nothing, once in a full suite under ctest -j2). Setting the same values again is the same
  // request.
  bool answered = false;
  for (int attempt = 0; attempt < 3 && !answered; ++attempt)
    answered = ros::service::call(server + "/set_parameters", srv);
  EXPECT_TRUE(answered) << "set_parameters of " << server << " was not answered in 3 calls";
  for (const auto& d : srv.response.config.doubles)
    if (d.name == name) return d.value;
  ADD_FAILURE() << name << " missing from the answer of " << server;
  return std::nan("");
}

// Every number of a mechanism_state is finite (what the node promises on every topic).
inline bool allFinite(const MechanismState& m) {
  const double scalars[] = {m.sim_time,          m.commanded_torque,     m.applied_torque,
                            m.kinetic_energy,    m.gravitational_energy, m.spring_energy,
                            m.total_energy,      m.motor_work,           m.dissipated_energy,
                            m.parameter_energy,  m.energy_balance,       m.spring_elongation,
                            m.slider_separation, m.contact_force,        m.real_time_factor};
  for (double v : scalars)
    if (!std::isfinite(v)) return false;
  for (const auto* a : {&m.q, &m.u, &m.u_dot, &m.active_forces, &m.inertia_forces})
    for (double v : *a)
      if (!std::isfinite(v)) return false;
  for (double v : m.load_powers)
    if (!std::isfinite(v)) return false;
  return true;
}

// The power of the load `name` (load_names), NaN when the message has no such load.
inline double loadPower(const MechanismState& m, const std::string& name) {
  for (std::size_t i = 0; i < m.load_names.size() && i < m.load_powers.size(); ++i)
    if (m.load_names[i] == name) return m.load_powers[i];
  return std::nan("");
}

// The fixture most node tests share: the node under test (started by test/node/sim_node.launch)
// is publishing mechanism_state, and a torque_command publisher is connected to it.
class SimNodeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    torque_ = connectedPublisher<std_msgs::Float64>(nh_, "torque_command");
    ASSERT_TRUE(state_.waitForCount(1, 15.0)) << "no mechanism_state from the node under test";
  }

  // Waits until the latest mechanism_state satisfies `done`.
  bool waitForState(const std::function<bool(const MechanismState&)>& done, double timeout) {
    return waitFor([&] { return state_.count() > 0 && done(state_.last()); }, timeout);
  }

  ros::NodeHandle nh_;
  Recorder<MechanismState> state_{nh_, "mechanism_state"};
  ros::Publisher torque_;
};

}  // namespace test
}  // namespace kane_sim

#endif  // KANE_SIM_TEST_NODE_TEST_UTILS_H
