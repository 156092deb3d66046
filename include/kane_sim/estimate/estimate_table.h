// The estimator's output, one row per reading: the estimate at the reading's stamp (latency
// compensated), its standard deviations, the biases, the innovations' test, and the virtual
// sensors - what the simulator's snapshot of the estimated state shows (reactions, spring force,
// energies, each load's power). One column list for `observer --csv`, Python's Estimator.run
// and the guide's table; the virtual sensors' columns are simulate's own (sim/csv_format.h).
#ifndef KANE_SIM_ESTIMATE_ESTIMATE_TABLE_H
#define KANE_SIM_ESTIMATE_ESTIMATE_TABLE_H

#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "kane_sim/estimate/mechanism_estimator.h"
#include "kane_sim/sim/simulator.h"
#include "kane_sim/sim/snapshot.h"

namespace kane_sim {

// One row's sources.
struct EstimateRow {
  double t = 0.0;  // [s] since the run's first reading's stamp
  FilterEstimate estimate;
  double nis = 0.0;
  double nis_dof = 0.0;
  AlarmLevel alarm = AlarmLevel::kOk;
  Snapshot snapshot;  // of the estimated state under the held torque
};

struct EstimateColumn {
  std::string name;
  std::string doc;
  std::function<double(const EstimateRow&)> value;
};
const std::vector<EstimateColumn>& estimateColumns();
void writeEstimateCsvHeader(std::ostream& out);
void writeEstimateCsvRow(std::ostream& out, const EstimateRow& row);

// The virtual sensors: a Simulator of the config put into each estimated state, never stepped.
class VirtualSensors {
 public:
  explicit VirtualSensors(const Config& config);
  ~VirtualSensors();
  // The snapshot of `e` (time = e.time); false, with `why`, when the simulator refuses the state
  // (beyond its checks): the caller keeps its last row.
  bool evaluate(const FilterEstimate& e, Snapshot* snapshot, std::string* why);

 private:
  std::unique_ptr<Simulator> simulator_;
};

// Fills `row` from the estimator's last update (`first_stamp`: the run's first reading's); the
// snapshot (virtual sensors) only with `sensors` (null: left as it was, for a caller that
// publishes none of them).
bool estimateRow(const MechanismEstimator& estimator, VirtualSensors* sensors, double first_stamp,
                 EstimateRow* row, std::string* why);

}  // namespace kane_sim

#endif  // KANE_SIM_ESTIMATE_ESTIMATE_TABLE_H
