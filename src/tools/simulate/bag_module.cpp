// libkane_sim_simulate_bag.so: simulate's bag half (bag_module.h), the only part of simulate
// that links the ROS libraries.
#include "simulate/bag_module.h"

#include <cstdint>
#include <memory>
#include <string>

#include "kane_sim/description/robot_description.h"
#include "kane_sim/ros/bag_writer.h"
#include "kane_sim/ros/messages.h"

namespace simulate {
namespace {

class RosBagOutput : public BagOutput {
 public:
  RosBagOutput(const std::string& path, const kane_sim::Config& config)
      : robot_(kane_sim::describeRobot(config)),
        sensors_enabled_(config.sensors.enabled),
        mode_(config.command.mode),
        bag_(path) {
    bag_.writeStatic(kane_sim::staticTransforms(robot_, kane_sim::simStamp(0)));
  }

  void write(const kane_sim::Snapshot& snapshot) override {
    const ros::Time stamp = kane_sim::simStamp(snapshot.time);
    // real_time_factor 0: offline, not paced against any wall clock.
    bag_.write(kane_sim::buildMessages(snapshot, robot_, 0.0, stamp), stamp, sensors_enabled_);
    if (mode_ != kane_sim::CommandMode::kEffort)  // as the node: servo_state in servo modes
      bag_.writeServoState(kane_sim::servoStateMessage(snapshot, mode_, stamp));
  }

  void writeSensorReading(const kane_sim::SensorReading& reading, double time) override {
    bag_.writeSensorReading(kane_sim::jointStateMessage(reading.joints, kane_sim::simStamp(time)));
  }

  void logInput(const kane_sim::DriverInput& input, double time) override {
    bag_.writeInputLog(kane_sim::inputLogMessage(input, kane_sim::simStamp(time), input_seq_++));
  }

  void close() override { bag_.close(); }

 private:
  kane_sim::RobotDescription robot_;  // the node's tf tree, the same in the bag
  bool sensors_enabled_;
  kane_sim::CommandMode mode_;
  kane_sim::BagWriter bag_;
  std::uint64_t input_seq_ = 0;  // /kane_sim/input_log's number of the next input
};

std::unique_ptr<BagOutput> openBag(const std::string& path, const kane_sim::Config& config) {
  ros::Time::init();  // ros::Time without a master, for the bag writer
  return std::make_unique<RosBagOutput>(path, config);
}

ReplayResult replay(const std::string& bag_path, const kane_sim::Config& config,
                    const std::atomic<bool>* stop) {
  ros::Time::init();
  return replayBag(bag_path, config, stop);
}

}  // namespace
}  // namespace simulate

extern "C" __attribute__((visibility("default"))) const simulate::BagModule*
kane_sim_simulate_bag_module() {
  static const simulate::BagModule module{&simulate::openBag, &simulate::replay};
  return &module;
}
