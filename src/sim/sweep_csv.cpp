// A sweep's CSV: the case's keys and values, its status, then the result columns.
#include <iterator>

#include "kane_sim/sim/csv_format.h"
#include "kane_sim/sim/sweep.h"

namespace kane_sim {

namespace {

const SweepColumn kSweepColumns[] = {
    {"t", [](const SweepResult& r) { return r.time; }, false},
    {"q1", [](const SweepResult& r) { return r.final_state.q1; }, false},
    {"q2", [](const SweepResult& r) { return r.final_state.q2; }, false},
    {"u1", [](const SweepResult& r) { return r.final_state.u1; }, false},
    {"u2", [](const SweepResult& r) { return r.final_state.u2; }, false},
    {"max_abs_q1", [](const SweepResult& r) { return r.max_abs_q1; }, false},
    {"max_abs_q2", [](const SweepResult& r) { return r.max_abs_q2; }, false},
    {"ledger_error", [](const SweepResult& r) { return r.ledger_error; }, false},
    {"motor_work", [](const SweepResult& r) { return r.motor_work; }, false},
    {"dissipated_energy", [](const SweepResult& r) { return r.dissipated_energy; }, false},
    {"contact_impacts", [](const SweepResult& r) { return double(r.contact_impacts); }, true},
    {"slider_crossings", [](const SweepResult& r) { return double(r.slider_crossings); }, true},
    {"steps", [](const SweepResult& r) { return double(r.steps); }, true},
    {"wall_time", [](const SweepResult& r) { return r.wall_time; }, false},
};

}  // namespace

const SweepColumn* sweepColumnsBegin() { return std::begin(kSweepColumns); }
const SweepColumn* sweepColumnsEnd() { return std::end(kSweepColumns); }

void writeSweepCsvHeader(std::ostream& out, const SweepPlan& plan) {
  out << "case";
  for (const std::string& key : plan.keys) out << ',' << key;
  out << ",status";
  for (const SweepColumn& c : kSweepColumns) out << ',' << c.name;
  out << '\n';
}

void writeSweepCsvRow(std::ostream& out, const SweepPlan& plan, size_t index, const SweepResult& r,
                      size_t first_case) {
  out << first_case + index;
  for (double v : plan.cases[index]) {
    out << ',';
    writeCsvNumber(out, v);
  }
  out << ',' << r.status;
  // config_refused: nothing ran, so empty fields, not zeros that read as data.
  const bool ran = r.status != "config_refused";
  for (const SweepColumn& c : kSweepColumns) {
    out << ',';
    if (!ran) continue;
    if (c.count)
      out << static_cast<long long>(c.value(r));
    else
      writeCsvNumber(out, c.value(r));
  }
  out << '\n';
}

}  // namespace kane_sim
