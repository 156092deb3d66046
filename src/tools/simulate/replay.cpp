#include "simulate/replay.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include "kane_sim/InputLog.h"
#include "kane_sim/MechanismState.h"
#include "kane_sim/ros/messages.h"
#include "kane_sim/sim/sim_driver.h"

namespace simulate {
namespace {

// The one topic of type M in the bag; ReplayError when there is none or more than one.
template <typename M>
std::string onlyTopicOf(const rosbag::Bag& bag, const std::string& what) {
  const std::string type = ros::message_traits::datatype<M>();
  std::set<std::string> topics;
  for (const rosbag::ConnectionInfo* c : rosbag::View(bag).getConnections())
    if (c->datatype == type) topics.insert(c->topic);
  if (topics.empty()) throw ReplayError("the bag has no " + type + " topic (" + what + ")");
  if (topics.size() > 1) {
    std::string list;
    for (const std::string& t : topics) list += (list.empty() ? "" : ", ") + t;
    throw ReplayError("the bag has several " + type + " topics (" + list +
                      "): replay one simulation's bag (rosbag filter)");
  }
  return *topics.begin();
}

template <typename M>
std::vector<M> readAll(const rosbag::Bag& bag, const std::string& topic) {
  std::vector<M> out;
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(topic)))
    if (const auto msg = m.instantiate<M>()) out.push_back(*msg);
  return out;
}

}  // namespace

ReplayResult replayBag(const std::string& bag_path, const kane_sim::Config& config) {
  rosbag::Bag bag;
  try {
    bag.open(bag_path, rosbag::bagmode::Read);
  } catch (const std::exception& e) {
    throw ReplayError("cannot read --replay '" + bag_path + "': " + e.what());
  }
  ReplayResult result;
  result.input_topic = onlyTopicOf<kane_sim::InputLog>(
      bag, "record the node's ~input_log, e.g. rosbag record -a, to replay its run");
  result.state_topic = onlyTopicOf<kane_sim::MechanismState>(bag, "the states to compare with");
  std::vector<kane_sim::DriverInput> inputs;
  for (const kane_sim::InputLog& msg : readAll<kane_sim::InputLog>(bag, result.input_topic)) {
    const auto input = kane_sim::driverInput(msg);
    if (!input)
      throw ReplayError("an input on " + result.input_topic + " has kind " +
                        std::to_string(msg.kind) + " or a malformed state");
    inputs.push_back(*input);
  }
  // Received in publish order: stable by tick keeps the order within a tick.
  std::stable_sort(inputs.begin(), inputs.end(),
                   [](const auto& a, const auto& b) { return a.tick < b.tick; });
  std::vector<kane_sim::MechanismState> states =
      readAll<kane_sim::MechanismState>(bag, result.state_topic);
  if (states.empty()) throw ReplayError("no messages on " + result.state_topic);
  std::stable_sort(states.begin(), states.end(),
                   [](const auto& a, const auto& b) { return a.sim_time < b.sim_time; });
  std::set<std::uint64_t> moved_at;  // ticks of resets and set_state
  for (const kane_sim::DriverInput& in : inputs)
    if (in.kind == kane_sim::DriverInput::Kind::kReset ||
        in.kind == kane_sim::DriverInput::Kind::kSetState)
      moved_at.insert(in.tick);

  kane_sim::SimDriver driver(config, {});
  const double rate = config.simulation.physics_rate;
  std::size_t next = 0;
  for (const kane_sim::MechanismState& m : states) {
    result.parameter_changes =
        std::max<std::uint64_t>(result.parameter_changes, m.parameter_changes);
    const double ticks = std::round(m.sim_time * rate);
    if (!(ticks >= 0) || std::abs(ticks - m.sim_time * rate) > 1e-6 * std::max(1.0, ticks))
      throw ReplayError("a state's sim_time " + std::to_string(m.sim_time) +
                        " s is not on the physics grid of " + std::to_string(rate) +
                        " Hz: --config is not the node's");
    const auto target = static_cast<std::uint64_t>(ticks);
    if (target < driver.ticks()) continue;  // the same instant again (paused repeats)
    while (true) {
      // What arrived at this tick is applied before the step from it, as in the node.
      for (; next < inputs.size() && inputs[next].tick <= driver.ticks() && driver.ticks() < target;
           ++next, ++result.inputs)
        driver.apply(inputs[next]);
      if (driver.ticks() >= target) break;
      if (!driver.step())
        throw ReplayError("the replay refused a step at t = " + std::to_string(driver.time()) +
                          " s, where the node went on: --config is not the node's");
    }
    if (moved_at.count(target)) {
      ++result.skipped;
      continue;
    }
    const kane_sim::State& x = driver.simulator().state();
    const double got[] = {m.q[0], m.q[1], m.u[0], m.u[1]};
    const double want[] = {x.q1, x.q2, x.u1, x.u2};
    static const char* names[] = {"q1", "q2", "u1", "u2"};
    for (int i = 0; i < 4; ++i) {
      const double d = std::abs(got[i] - want[i]);
      if (d > result.largest || std::isnan(d)) {
        result.largest = std::isnan(d) ? INFINITY : d;
        result.largest_at = m.sim_time;
        result.largest_of = names[i];
      }
    }
    ++result.compared;
  }
  return result;
}

}  // namespace simulate
