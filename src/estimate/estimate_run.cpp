#include "kane_sim/estimate/estimate_run.h"

#include "kane_sim/format_number.h"

namespace kane_sim {
namespace {

constexpr std::size_t kMaxNotes = 20;

}  // namespace

std::string ReadingColumns::problem() const {
  const std::size_t n = t.size();
  if (n == 0) return "no readings";
  if (q1.size() != n || q2.size() != n || effort.size() != n)
    return "t, q1, q2 and effort must have one value per reading (" + std::to_string(n) + ")";
  if (u1.size() != u2.size() || (!u1.empty() && u1.size() != n))
    return "u1 and u2 must both be given, one value per reading, or neither";
  if (!velocity_rows.empty() && (velocity_rows.size() != n || u1.empty()))
    return "velocity_rows must have one value per reading, and u1 and u2 be given";
  return "";
}

EstimateRunSummary runEstimator(const Config& config, const ReadingColumns& columns,
                                const std::function<void(const EstimateRow&)>& on_row,
                                const std::function<bool()>& interrupted) {
  MechanismEstimator estimator(config);
  VirtualSensors sensors(config);
  EstimateRunSummary summary;
  const auto note = [&](std::size_t i, const std::string& what) {
    if (summary.notes.size() < kMaxNotes)
      summary.notes.push_back("reading " + std::to_string(i) + " (t = " +
                              formatNumber(columns.t[i] - columns.t[0]) + " s): " + what);
  };
  EstimateRow row;
  for (std::size_t i = 0; i < columns.t.size(); ++i) {
    if (interrupted && i % 4096 == 0 && interrupted()) {
      summary.interrupted = true;
      break;
    }
    RigReading r;
    r.stamp = columns.t[i];
    r.q1 = columns.q1[i];
    r.q2 = columns.q2[i];
    r.torque = columns.effort[i];
    r.has_velocity = columns.hasVelocity(i);
    if (r.has_velocity) {
      r.u1 = columns.u1[i];
      r.u2 = columns.u2[i];
    }
    const EstimatorStep step = estimator.update(r);
    if (step.event == EstimatorEvent::kRefused) {
      ++summary.refused;
      note(i, "refused: " + step.reason);
      continue;
    }
    if (step.event == EstimatorEvent::kRestarted) {
      ++summary.restarts;
      note(i, "restarted: " + step.reason);
    }
    std::string why;
    if (!estimateRow(estimator, &sensors, columns.t[0], &row, &why)) {
      ++summary.refused;
      note(i, "no row: " + why);
      continue;
    }
    on_row(row);
    ++summary.rows;
  }
  summary.alarm = estimator.alarm().report();
  return summary;
}

}  // namespace kane_sim
