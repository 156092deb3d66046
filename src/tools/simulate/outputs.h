// Where simulate's rows go: a CSV (kane_sim/cli/staged_output.h) and/or a bag (the bag module,
// bag_module.h), both fed from the same snapshots. A write that fails is an OutputError.
#ifndef KANE_SIM_TOOLS_SIMULATE_OUTPUTS_H
#define KANE_SIM_TOOLS_SIMULATE_OUTPUTS_H

#include <cstdint>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>

#include "kane_sim/cli/simulate_options.h"
#include "kane_sim/cli/staged_output.h"
#include "kane_sim/config/config.h"
#include "kane_sim/sim/sim_driver.h"
#include "kane_sim/sim/snapshot.h"
#include "simulate/bag_module.h"

namespace simulate {

using kane_sim::cli::CsvOutput;
using kane_sim::cli::Options;
using kane_sim::cli::OutputError;
using kane_sim::cli::StagedPath;

// Where the rows go: a CSV stream and/or a bag, both fed from the same snapshots.
class Outputs {
 public:
  Outputs(const Options& options, const kane_sim::Config& config) {
    // With a bag and no --csv, no CSV.
    if (!options.csv_path.empty() || options.bag_path.empty())
      csv_ = std::make_unique<CsvOutput>(options.csv_path);
    if (!options.bag_path.empty()) {
      bag_path_ = options.bag_path;
      bag_file_ = std::make_unique<StagedPath>(options.bag_path);
      try {
        bag_ = bagModule().open(bag_file_->staging(), config);
      } catch (const std::exception& e) {
        throw OutputError("cannot write --bag '" + options.bag_path + "': " + e.what());
      }
    }
    if (csv_) kane_sim::writeCsvHeader(csv_->stream());
  }

  void write(const kane_sim::Snapshot& snapshot) {
    if (csv_) {
      kane_sim::writeCsvRow(csv_->stream(), snapshot);
      if (!csv_->stream()) throw OutputError("writing the CSV failed (disk full?)");
    }
    if (bag_) {
      try {
        bag_->write(snapshot);
      } catch (const std::exception& e) {
        throw OutputError("writing --bag '" + bag_path_ + "' failed (disk full?): " + e.what());
      }
    }
  }

  // Sensor readings due by now (sensors on) -> /joint_states in the bag, stamped now, as the
  // node publishes them. The CSV holds the truth only.
  void writeDueSensorReadings(kane_sim::SimDriver& driver) {
    kane_sim::SensorReading reading;
    while (driver.takeSensorReading(&reading)) {
      if (!bag_) continue;
      try {
        bag_->writeSensorReading(reading, driver.time());
      } catch (const std::exception& e) {
        throw OutputError("writing --bag '" + bag_path_ + "' failed (disk full?): " + e.what());
      }
    }
  }

  // A driver input (a profile's command, a servo's setpoint) on the bag's /kane_sim/input_log,
  // numbered and stamped at `time` [s] as the node logs it on ~input_log.
  void logInput(const kane_sim::DriverInput& input, double time) {
    if (!bag_) return;
    try {
      bag_->logInput(input, time);
    } catch (const std::exception& e) {
      throw OutputError("writing --bag '" + bag_path_ + "' failed (disk full?): " + e.what());
    }
  }

  // Completes the outputs (the bag's index, the CSV's last bytes) and puts them in place.
  void finish() {
    if (bag_) {
      try {
        bag_->close();
      } catch (const std::exception& e) {
        throw OutputError("closing --bag '" + bag_path_ + "' failed (disk full?): " + e.what());
      }
      bag_file_->publish();
    }
    if (csv_) csv_->finish();
  }

 private:
  std::unique_ptr<StagedPath> bag_file_;
  std::string bag_path_;
  std::unique_ptr<CsvOutput> csv_;
  std::unique_ptr<BagOutput> bag_;
};

}  // namespace simulate

#endif  // KANE_SIM_TOOLS_SIMULATE_OUTPUTS_H
