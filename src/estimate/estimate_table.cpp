#include "kane_sim/estimate/estimate_table.h"

#include <set>

#include "kane_sim/sim/csv_format.h"

namespace kane_sim {
namespace {

std::vector<EstimateColumn> makeColumns() {
  using R = const EstimateRow&;
  std::vector<EstimateColumn> c = {
      {"t", "[s] since the first reading's stamp", [](R r) { return r.t; }},
      {"q1", "[rad] estimated crank angle at the reading's stamp",
       [](R r) { return r.estimate.state.q1; }},
      {"q2", "[m] slider 4", [](R r) { return r.estimate.state.q2; }},
      {"u1", "[rad/s]", [](R r) { return r.estimate.state.u1; }},
      {"u2", "[m/s]", [](R r) { return r.estimate.state.u2; }},
      {"sigma_q1", "[rad] standard deviation", [](R r) { return r.estimate.sigma()[0]; }},
      {"sigma_q2", "[m]", [](R r) { return r.estimate.sigma()[1]; }},
      {"sigma_u1", "[rad/s]", [](R r) { return r.estimate.sigma()[2]; }},
      {"sigma_u2", "[m/s]", [](R r) { return r.estimate.sigma()[3]; }},
      {"bias_q1", "[rad] the crank encoder's estimated bias",
       [](R r) { return r.estimate.bias[0]; }},
      {"bias_q2", "[m] slider 4's", [](R r) { return r.estimate.bias[1]; }},
      {"applied_torque", "[N m] M_m held (the reading's effort)",
       [](R r) { return r.estimate.torque; }},
      {"nis", "the reading's normalised innovation squared", [](R r) { return r.nis; }},
      {"nis_dof", "its degrees of freedom (2, or 4 with velocities)",
       [](R r) { return r.nis_dof; }},
      {"alarm", "the last closed window's verdict: 0 OK, 1 WARN, 2 ERROR",
       [](R r) { return static_cast<double>(r.alarm); }},
  };
  // The virtual sensors: simulate's columns of these groups, of the estimated state.
  const std::set<std::string> virtual_groups = {"energy", "reaction", "power", "kinetic"};
  for (const CsvColumn& column : csvColumns()) {
    if (!virtual_groups.count(column.group)) continue;
    const auto value = column.value;
    c.push_back({column.name, "virtual sensor (simulate's column)",
                 [value](R r) { return value(r.snapshot); }});
  }
  return c;
}

}  // namespace

const std::vector<EstimateColumn>& estimateColumns() {
  static const std::vector<EstimateColumn> columns = makeColumns();
  return columns;
}

void writeEstimateCsvHeader(std::ostream& out) {
  const std::vector<EstimateColumn>& columns = estimateColumns();
  for (std::size_t i = 0; i < columns.size(); ++i) out << (i ? "," : "") << columns[i].name;
  out << '\n';
}

void writeEstimateCsvRow(std::ostream& out, const EstimateRow& row) {
  const std::vector<EstimateColumn>& columns = estimateColumns();
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (i) out << ',';
    writeCsvNumber(out, columns[i].value(row));
  }
  out << '\n';
}

VirtualSensors::VirtualSensors(const Config& config) : simulator_(new Simulator(config)) {}
VirtualSensors::~VirtualSensors() = default;

bool VirtualSensors::evaluate(const FilterEstimate& e, Snapshot* snapshot, std::string* why) {
  const Status torque = simulator_->setTorque(e.torque);
  const Status state = torque.ok ? simulator_->setState(e.state) : torque;
  if (!state.ok) {
    *why = state.error;
    return false;
  }
  *snapshot = simulator_->snapshot();
  snapshot->time = e.time;
  if (!snapshot->allFinite()) {
    *why =
        "the virtual sensors of the estimate " + Simulator::stateText(e.state) + " are not finite";
    return false;
  }
  return true;
}

bool estimateRow(const MechanismEstimator& estimator, VirtualSensors* sensors, double first_stamp,
                 EstimateRow* row, std::string* why) {
  EstimateRow next;
  next.estimate = estimator.atStamp();
  next.t = estimator.lastStamp() - first_stamp;
  next.nis = estimator.nis();
  for (bool m : estimator.measured()) next.nis_dof += m ? 1.0 : 0.0;
  next.alarm = estimator.alarm().report().level;
  if (sensors && !sensors->evaluate(next.estimate, &next.snapshot, why)) return false;
  *row = next;
  return true;
}

}  // namespace kane_sim
