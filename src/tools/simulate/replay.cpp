#include "simulate/replay.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <iterator>
#include <memory>
#include <set>
#include <vector>

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include "kane_sim/Checkpoint.h"
#include "kane_sim/InputLog.h"
#include "kane_sim/MechanismState.h"
#include "kane_sim/format_number.h"
#include "kane_sim/ros/messages.h"
#include "kane_sim/sim/checkpoint.h"
#include "kane_sim/sim/config_check.h"
#include "kane_sim/sim/output_grid.h"
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

// Every message on `topic`; ReplayError when one is of another version of M (recorded by an
// older kane_sim: it would otherwise be skipped without a word).
template <typename M>
bool hasTopicOf(const rosbag::Bag& bag) {
  const std::string type = ros::message_traits::datatype<M>();
  for (const rosbag::ConnectionInfo* c : rosbag::View(bag).getConnections())
    if (c->datatype == type) return true;
  return false;
}

template <typename M>
std::vector<M> readAll(const rosbag::Bag& bag, const std::string& topic) {
  std::vector<M> out;
  for (const rosbag::MessageInstance& m : rosbag::View(bag, rosbag::TopicQuery(topic))) {
    const auto msg = m.instantiate<M>();
    if (!msg)
      throw ReplayError(topic + " holds " + m.getDataType() + " of another version (md5 " +
                        m.getMD5Sum() + ", this simulate reads " +
                        ros::message_traits::md5sum<M>() +
                        "): the bag was recorded by another kane_sim version; record it again");
    out.push_back(*msg);
  }
  return out;
}

std::string seqRange(std::uint64_t first, std::uint64_t last) {
  return first == last ? "input " + std::to_string(first)
                       : "inputs " + std::to_string(first) + "-" + std::to_string(last);
}

// A run of inputs the bag lacks: seqs first .. last.
struct InputGap {
  std::uint64_t first, last;
};

// The inputs in the order the node received them, from `first` on (those before are inside the
// starting checkpoint). The first one missing is refused with its number (nothing can be
// replayed without it); later gaps are returned, to be compared up to and named: a gap would
// otherwise show up as a difference far from its cause.
std::vector<InputGap> checkSequence(std::vector<kane_sim::InputLog>* logs, const std::string& topic,
                                    std::uint64_t first, bool from_checkpoint) {
  std::stable_sort(logs->begin(), logs->end(),
                   [](const auto& a, const auto& b) { return a.seq < b.seq; });
  logs->erase(std::remove_if(logs->begin(), logs->end(),
                             [first](const auto& log) { return log.seq < first; }),
              logs->end());
  std::uint64_t expected = first;
  std::vector<InputGap> gaps;
  for (const kane_sim::InputLog& log : *logs) {
    if (log.seq < expected) continue;  // recorded twice (two recorders merged): the same input
    if (log.seq > expected && expected == first)
      throw ReplayError(seqRange(expected, log.seq - 1) + " of " + topic +
                        (from_checkpoint
                             ? " were not recorded after the bag's first ~checkpoint"
                             : " were not recorded: the recording began after the node had "
                               "received them and the bag has no ~checkpoint to start from "
                               "(record the node's ~checkpoint too, e.g. rosbag record -a)") +
                        "; replaying without them would differ from the node");
    if (log.seq > expected) gaps.push_back({expected, log.seq - 1});
    expected = log.seq + 1;
  }
  logs->erase(std::unique(logs->begin(), logs->end(),
                          [](const auto& a, const auto& b) { return a.seq == b.seq; }),
              logs->end());
  return gaps;
}

// The config a checkpoint carries, through the one loader (a damaged one is named).
kane_sim::Config checkpointConfig(const kane_sim::Checkpoint& c, const std::string& topic) {
  try {
    return kane_sim::loadSimulationConfig(YAML::Load(c.config)).config;
  } catch (const std::exception& e) {
    throw ReplayError("the " + c.cause + " checkpoint on " + topic + " at tick " +
                      std::to_string(c.tick) + " holds a config the loader refuses: " + e.what());
  }
}

// A driver at checkpoint `c`: built from its config, restored from its state.
std::unique_ptr<kane_sim::SimDriver> driverAt(const kane_sim::Checkpoint& c,
                                              const std::string& topic) {
  auto driver = std::make_unique<kane_sim::SimDriver>(checkpointConfig(c, topic),
                                                      kane_sim::SimDriver::EventHandler{});
  try {
    driver->restore(kane_sim::parseCheckpoint(c.state));
  } catch (const kane_sim::CheckpointError& e) {
    throw ReplayError("the " + c.cause + " checkpoint on " + topic + " at tick " +
                      std::to_string(c.tick) + " cannot be restored: " + e.what());
  }
  if (driver->ticks() != c.tick)
    throw ReplayError("the " + c.cause + " checkpoint on " + topic + " says tick " +
                      std::to_string(c.tick) + " but holds tick " +
                      std::to_string(driver->ticks()) + ": the bag is damaged");
  return driver;
}

}  // namespace

namespace {

ReplayResult replayOpenBag(const rosbag::Bag& bag, const kane_sim::Config& config,
                           const std::atomic<bool>* stop) {
  ReplayResult result;
  result.input_topic = onlyTopicOf<kane_sim::InputLog>(
      bag, "record the node's ~input_log, e.g. rosbag record -a, to replay its run");
  result.state_topic = onlyTopicOf<kane_sim::MechanismState>(bag, "the states to compare with");
  // Checkpoints, when recorded: the run starts at the first (the driver, its config and the
  // inputs it already holds) and re-synchronises at each later one.
  std::vector<kane_sim::Checkpoint> checkpoints;
  if (hasTopicOf<kane_sim::Checkpoint>(bag)) {
    result.checkpoint_topic = onlyTopicOf<kane_sim::Checkpoint>(bag, "checkpoints");
    checkpoints = readAll<kane_sim::Checkpoint>(bag, result.checkpoint_topic);
    std::stable_sort(checkpoints.begin(), checkpoints.end(), [](const auto& a, const auto& b) {
      return a.tick != b.tick ? a.tick < b.tick : a.next_input < b.next_input;
    });
  }
  std::vector<kane_sim::InputLog> logs = readAll<kane_sim::InputLog>(bag, result.input_topic);
  // The run starts at the first checkpoint whose next input was recorded: a recorder started
  // mid-run gets the latched checkpoint from before it began, and the inputs between that one
  // and the recording's start are missing; the next checkpoint (<= 10 s on) has its next input.
  // Inputs missing later (a gap) are compared up to and named, and the run re-synchronises at
  // the first checkpoint after them.
  std::set<std::uint64_t> recorded;
  for (const kane_sim::InputLog& log : logs) recorded.insert(log.seq);
  const auto startsRecorded = [&recorded](std::uint64_t first) {
    return recorded.empty() || first > *recorded.rbegin() || recorded.count(first) > 0;
  };
  // A checkpoint's next_input says which inputs it already holds: an input that arrived after it
  // (a later tick) with a smaller seq, or one before it with a larger, means a damaged one.
  // (Inputs in seq order have non-decreasing ticks: the neighbours of next_input tell.)
  std::stable_sort(logs.begin(), logs.end(),
                   [](const auto& a, const auto& b) { return a.seq < b.seq; });
  for (const kane_sim::Checkpoint& c : checkpoints) {
    const auto after = std::lower_bound(
        logs.begin(), logs.end(), c.next_input,
        [](const kane_sim::InputLog& log, std::uint64_t seq) { return log.seq < seq; });
    const kane_sim::InputLog* wrong = nullptr;
    if (after != logs.begin() && std::prev(after)->tick > c.tick) wrong = &*std::prev(after);
    if (after != logs.end() && after->tick < c.tick) wrong = &*after;
    if (wrong)
      throw ReplayError("the " + c.cause + " checkpoint on " + result.checkpoint_topic +
                        " at tick " + std::to_string(c.tick) + " says the next input is " +
                        std::to_string(c.next_input) + ", but input " + std::to_string(wrong->seq) +
                        " arrived at tick " + std::to_string(wrong->tick) +
                        ": the checkpoint is damaged");
  }
  std::size_t start = 0;
  while (start < checkpoints.size() && !startsRecorded(checkpoints[start].next_input)) ++start;
  if (start == checkpoints.size() && !checkpoints.empty()) start = 0;  // checkSequence names it
  checkpoints.erase(checkpoints.begin(), checkpoints.begin() + static_cast<long>(start));
  result.checkpoints_passed_over = start;
  std::unique_ptr<kane_sim::SimDriver> driver =
      checkpoints.empty()
          ? std::make_unique<kane_sim::SimDriver>(config, kane_sim::SimDriver::EventHandler{})
          : driverAt(checkpoints.front(), result.checkpoint_topic);
  const std::uint64_t start_tick = driver->ticks();
  result.start_tick = start_tick;
  const std::vector<InputGap> gaps =
      checkSequence(&logs, result.input_topic,
                    checkpoints.empty() ? 0 : checkpoints.front().next_input, !checkpoints.empty());
  std::vector<kane_sim::DriverInput> inputs;
  for (const kane_sim::InputLog& msg : logs) {
    const auto input = kane_sim::driverInput(msg);
    if (!input)
      throw ReplayError("an input on " + result.input_topic + " has kind " +
                        std::to_string(msg.kind) + " or a malformed state");
    inputs.push_back(*input);
  }
  // In the order received (seq); ticks never go back along it.
  for (std::size_t i = 1; i < inputs.size(); ++i)
    if (inputs[i].tick < inputs[i - 1].tick)
      throw ReplayError("input " + std::to_string(logs[i].seq) + " of " + result.input_topic +
                        " arrived at tick " + std::to_string(inputs[i].tick) +
                        ", before the one received ahead of it (tick " +
                        std::to_string(inputs[i - 1].tick) + "): not one node's run");
  std::vector<kane_sim::MechanismState> states =
      readAll<kane_sim::MechanismState>(bag, result.state_topic);
  if (states.empty()) throw ReplayError("no messages on " + result.state_topic);
  // Every state's sim time must be a time this run could have: finite, >= 0, within the longest
  // run, on the physics grid (a state at t = inf was once "compared" with tick 0 and passed).
  const double rate = 1.0 / driver->simulator().stepSize();
  for (const kane_sim::MechanismState& m : states) {
    if (!(m.sim_time >= 0 && m.sim_time <= kane_sim::kMaxRunDuration))
      throw ReplayError("a state on " + result.state_topic + " has sim_time " +
                        kane_sim::formatNumber(m.sim_time) + " s, not in [0, " +
                        kane_sim::formatNumber(kane_sim::kMaxRunDuration) +
                        "] s: the bag is damaged or not kane_sim's");
    const double ticks = std::round(m.sim_time * rate);
    if (std::abs(ticks - m.sim_time * rate) > 1e-6 * std::max(1.0, ticks))
      throw ReplayError("a state's sim_time " + kane_sim::formatNumber(m.sim_time) +
                        " s is not on the physics grid of " + kane_sim::formatNumber(rate) +
                        " Hz: --config is not the node's");
    for (const double v : {m.q[0], m.q[1], m.u[0], m.u[1]})
      if (!std::isfinite(v))
        throw ReplayError("the state at t = " + kane_sim::formatTime(m.sim_time) + " s on " +
                          result.state_topic + " holds " + kane_sim::formatNumber(v) +
                          ": the node never publishes one; the bag is damaged");
  }
  std::stable_sort(states.begin(), states.end(),
                   [](const auto& a, const auto& b) { return a.sim_time < b.sim_time; });
  std::set<std::uint64_t> moved_at;  // ticks of resets and set_state
  for (const kane_sim::DriverInput& in : inputs)
    if (in.kind == kane_sim::DriverInput::Kind::kReset ||
        in.kind == kane_sim::DriverInput::Kind::kSetState)
      moved_at.insert(in.tick);
  // A move's checkpoint marks its tick too: a bag that starts there lacks the move's input, and
  // holds the state before the move at that tick as well as the one after.
  for (const kane_sim::Checkpoint& c : checkpoints)
    if (c.cause == "reset" || c.cause == "set_state") moved_at.insert(c.tick);

  // The starting checkpoint holds a state the bag recorded at its tick (at a move, the bag
  // holds the states before and after it there): else the checkpoint is damaged.
  if (!checkpoints.empty()) {
    const kane_sim::State& x = driver->simulator().state();
    bool any = false, matched = false;
    const kane_sim::MechanismState* first = nullptr;
    for (const kane_sim::MechanismState& m : states) {
      if (std::llround(m.sim_time * rate) != static_cast<long long>(start_tick)) continue;
      any = true;
      first = first ? first : &m;
      matched |= m.q[0] == x.q1 && m.q[1] == x.q2 && m.u[0] == x.u1 && m.u[1] == x.u2;
    }
    if (any && !matched)
      throw ReplayError("the checkpoint at tick " + std::to_string(start_tick) + " on " +
                        result.checkpoint_topic + " holds q1 = " + kane_sim::formatNumber(x.q1) +
                        " where the bag's state there has " + kane_sim::formatNumber(first->q[0]) +
                        ": the checkpoint is damaged");
  }
  // Each gap blinds the replay from the last input before it (its tick: what the node did after
  // that depended on inputs the bag lacks) to the first checkpoint after it that holds them all
  // (its next input beyond the gap), or to the end when there is none.
  struct Blind {
    std::uint64_t after_tick;  // states beyond this tick are not compared ...
    std::size_t resync;        // ... until checkpoints[resync] (npos: none)
    InputGap gap;
    std::uint64_t states = 0;
    double from = 0.0, to = 0.0;  // [s] sim times of the first and last state not compared
  };
  constexpr std::size_t kNone = static_cast<std::size_t>(-1);
  std::vector<Blind> blinds;
  for (const InputGap& gap : gaps) {
    const auto before = std::lower_bound(
        logs.begin(), logs.end(), gap.first,
        [](const kane_sim::InputLog& log, std::uint64_t seq) { return log.seq < seq; });
    const std::uint64_t after_tick = std::prev(before)->tick;  // gap.first > the first recorded
    if (!blinds.empty() && (blinds.back().resync == kNone ||
                            checkpoints[blinds.back().resync].next_input <= gap.last)) {
      // Within the previous stretch: it lasts until a checkpoint beyond this gap too.
      Blind& b = blinds.back();
      b.gap.last = gap.last;
      while (b.resync != kNone && checkpoints[b.resync].next_input <= gap.last)
        b.resync = b.resync + 1 < checkpoints.size() ? b.resync + 1 : kNone;
      continue;
    }
    std::size_t resync = kNone;
    for (std::size_t k = 1; k < checkpoints.size() && resync == kNone; ++k)
      if (checkpoints[k].next_input > gap.last && checkpoints[k].tick > after_tick) resync = k;
    blinds.push_back({after_tick, resync, gap});
  }
  std::size_t blind = 0;       // the next (or current) stretch without inputs
  std::size_t next = 0;        // the next input to apply
  std::size_t checkpoint = 1;  // the next checkpoint to re-synchronise at
  // A checkpoint is due once the driver is at its tick with every input before it applied.
  const auto checkpointDue = [&] {
    return checkpoint < checkpoints.size() && checkpoints[checkpoint].tick <= driver->ticks() &&
           (next == inputs.size() || logs[next].seq >= checkpoints[checkpoint].next_input);
  };
  // What arrived by the driver's tick, applied in the order the node met it: a checkpoint taken
  // between two of those inputs is met between them.
  const auto applyArrivedInputs = [&] {
    while (true) {
      if (checkpointDue()) {
        driver = driverAt(checkpoints[checkpoint++], result.checkpoint_topic);
        ++result.resynchronised;
      } else if (next < inputs.size() && inputs[next].tick <= driver->ticks()) {
        driver->apply(inputs[next++]);
        ++result.inputs;
      } else {
        break;
      }
    }
  };
  const std::uint64_t last_state_tick =
      states.empty() ? 0 : static_cast<std::uint64_t>(std::llround(states.back().sim_time * rate));
  for (const kane_sim::MechanismState& m : states) {
    result.parameter_changes =
        std::max<std::uint64_t>(result.parameter_changes, m.parameter_changes);
    const auto target = static_cast<std::uint64_t>(std::llround(m.sim_time * rate));
    // Past a gap: not compared until its re-synchronising checkpoint, then from there.
    bool blinded = false;
    while (blind < blinds.size() && target > blinds[blind].after_tick) {
      Blind& b = blinds[blind];
      if (b.resync == kNone || target < checkpoints[b.resync].tick) {
        if (b.states++ == 0) b.from = m.sim_time;
        b.to = m.sim_time;
        ++result.uncompared;
        blinded = true;
        break;
      }
      driver = driverAt(checkpoints[b.resync], result.checkpoint_topic);
      ++result.resynchronised;
      checkpoint = b.resync + 1;
      next = static_cast<std::size_t>(
          std::lower_bound(
              logs.begin(), logs.end(), checkpoints[b.resync].next_input,
              [](const kane_sim::InputLog& log, std::uint64_t seq) { return log.seq < seq; }) -
          logs.begin());
      ++blind;
    }
    if (blinded) continue;
    if (target < driver->ticks()) continue;  // before the first checkpoint, or a repeat
    while (true) {
      // What arrived at this tick is applied before the step from it, as in the node (not at
      // the target's own tick: a reset or set_state there would move the state compared).
      if (driver->ticks() >= target) break;
      applyArrivedInputs();
      if (stop && stop->load(std::memory_order_relaxed)) {
        result.interrupted = true;
        result.interrupted_at = driver->time();
        return result;
      }
      if (!driver->step())
        throw ReplayError("the replay refused a step at t = " +
                          kane_sim::formatTime(driver->time()) + " s, where the node went on: " +
                          (checkpoints.empty()
                               ? std::string("--config is not the node's")
                               : "the checkpoint it started from (tick " +
                                     std::to_string(start_tick) + ") is not the node's: damaged?"));
      kane_sim::SensorReading reading;  // the node takes them as they come: so does the replay
      while (driver->takeSensorReading(&reading)) {
      }
    }
    if (moved_at.count(target)) {
      ++result.skipped;  // the bag holds both sides of a move at one instant
      continue;
    }
    const kane_sim::State& x = driver->simulator().state();
    const double got[] = {m.q[0], m.q[1], m.u[0], m.u[1]};
    const double want[] = {x.q1, x.q2, x.u1, x.u2};
    static const char* names[] = {"q1", "q2", "u1", "u2"};
    for (int i = 0; i < 4; ++i) {
      const double d = std::abs(got[i] - want[i]);
      if (d > result.largest) {
        result.largest = d;
        result.largest_at = m.sim_time;
        result.largest_of = names[i];
      }
    }
    ++result.compared;
    // What arrived at this very tick acts from the next step on: applied now, after the state
    // is compared, so that a gap that follows finds every input before it replayed and counted.
    applyArrivedInputs();
  }
  // Inputs after the bag's last state (nothing to compare them with): those past its tick, not
  // those a gap left unreplayed (the gaps' messages name them).
  result.inputs_after_last_state = static_cast<std::size_t>(
      std::count_if(inputs.begin() + static_cast<std::ptrdiff_t>(next), inputs.end(),
                    [&](const auto& input) { return input.tick > last_state_tick; }));
  for (const Blind& b : blinds) {
    std::string text = seqRange(b.gap.first, b.gap.last) + " of " + result.input_topic +
                       " were not recorded (a gap in the bag): compared up to t = " +
                       kane_sim::formatTime(static_cast<double>(b.after_tick) / rate) +
                       " s, the last input before them";
    if (b.states > 0)
      text += "; " + std::to_string(b.states) + " states from t = " + kane_sim::formatTime(b.from) +
              " to " + kane_sim::formatTime(b.to) + " s not compared";
    text += b.resync == kNone ? " (no later ~checkpoint holds the missing inputs)"
                              : "; re-synchronised at the checkpoint of tick " +
                                    std::to_string(checkpoints[b.resync].tick);
    result.gaps.push_back(text);
  }
  return result;
}

}  // namespace

ReplayResult replayBag(const std::string& bag_path, const kane_sim::Config& config,
                       const std::atomic<bool>* stop) {
  rosbag::Bag bag;
  try {
    bag.open(bag_path, rosbag::bagmode::Read);
  } catch (const std::exception& e) {
    throw ReplayError("cannot read --replay '" + bag_path + "': " + e.what());
  }
  try {
    return replayOpenBag(bag, config, stop);
  } catch (const rosbag::BagException& e) {  // a damaged chunk or record, met while reading
    throw ReplayError("'" + bag_path + "' is damaged: " + e.what());
  }
}

}  // namespace simulate
