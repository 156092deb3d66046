// A recording replayed through the estimator: every reading in order, one row per reading it
// used, and a note for each one it refused or restarted at. The one loop of `observer --bag` and
// Python's Estimator.run, so both give the same rows.
#ifndef KANE_SIM_ESTIMATE_ESTIMATE_RUN_H
#define KANE_SIM_ESTIMATE_ESTIMATE_RUN_H

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "kane_sim/estimate/estimate_table.h"

namespace kane_sim {

// A recording's columns (joint_states' crank_joint and slider4_joint): t the stamps [s]; the
// velocities empty when the recording has none; velocity_rows (when not empty) 1 for the
// readings that carry them (a recording whose messages differ), the others' u1, u2 unused.
struct ReadingColumns {
  std::vector<double> t, q1, q2, effort, u1, u2;
  std::vector<std::uint8_t> velocity_rows;
  bool hasVelocity() const { return !u1.empty(); }  // any reading carries velocities
  bool hasVelocity(std::size_t i) const {
    return !u1.empty() && (velocity_rows.empty() || velocity_rows[i] != 0);
  }
  std::string problem() const;  // "" or what is wrong with the columns' lengths
};

struct EstimateRunSummary {
  std::size_t rows = 0, refused = 0, restarts = 0;
  AlarmReport alarm;               // the last window's verdict
  std::vector<std::string> notes;  // "reading 12 (t = 0.12 s): refused: ..." (the first 20)
  bool interrupted = false;
};

// Runs `columns` through a fresh estimator of `config`; `on_row` gets each row (t from the first
// reading's stamp), `interrupted` (when set) is asked every 4096 readings.
EstimateRunSummary runEstimator(const Config& config, const ReadingColumns& columns,
                                const std::function<void(const EstimateRow&)>& on_row,
                                const std::function<bool()>& interrupted = {});

}  // namespace kane_sim

#endif  // KANE_SIM_ESTIMATE_ESTIMATE_RUN_H
