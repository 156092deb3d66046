// simulate's bag half: writing a run into a bag (--bag) and replaying one (--replay) need the ROS
// libraries (rosbag, roslib, the messages), whose loading alone took 18 of a CSV run's 29 ms of
// start-up on a 2-core VM. They live in a module, libkane_sim_simulate_bag.so, loaded when a run
// asks for a bag; a CSV run loads none of them.
#ifndef KANE_SIM_TOOLS_SIMULATE_BAG_MODULE_H
#define KANE_SIM_TOOLS_SIMULATE_BAG_MODULE_H

#include <atomic>
#include <memory>
#include <string>

#include "kane_sim/config/config.h"
#include "kane_sim/sensors/joint_sensors.h"
#include "kane_sim/sim/sim_driver.h"
#include "kane_sim/sim/snapshot.h"
#include "simulate/replay.h"

namespace simulate {

// A bag being written: what the node would publish, built from the run's snapshots. A write that
// fails throws (std::exception).
class BagOutput {
 public:
  virtual ~BagOutput() = default;
  // /clock, /joint_states, /tf, /mechanism_state, the markers (and /servo_state in servo modes).
  virtual void write(const kane_sim::Snapshot& snapshot) = 0;
  // A sensor reading on /joint_states, stamped `time` [s] when it is delivered.
  virtual void writeSensorReading(const kane_sim::SensorReading& reading, double time) = 0;
  // A driver input on /kane_sim/input_log, numbered and stamped `time` [s] as the node logs it.
  virtual void logInput(const kane_sim::DriverInput& input, double time) = 0;
  // The bag's index; nothing is written after it.
  virtual void close() = 0;
};

// The module's entry points.
struct BagModule {
  // A bag at `path` for a run of `config`, its /tf_static written; throws when it cannot open.
  std::unique_ptr<BagOutput> (*open)(const std::string& path, const kane_sim::Config& config);
  // simulate --replay (replay.h).
  ReplayResult (*replay)(const std::string& bag_path, const kane_sim::Config& config,
                         const std::atomic<bool>* stop);
};

// The module's name, and the symbol it exports its entry points under.
constexpr const char* kBagModuleLibrary = "libkane_sim_simulate_bag.so";
constexpr const char* kBagModuleSymbol = "kane_sim_simulate_bag_module";

// Loads the module on first use (beside simulate's own directory's parent, as devel/lib and an
// install's lib hold it, else on the library path); throws std::runtime_error naming it and
// why it could not be loaded.
const BagModule& bagModule();

}  // namespace simulate

#endif  // KANE_SIM_TOOLS_SIMULATE_BAG_MODULE_H
