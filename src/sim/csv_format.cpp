#include "kane_sim/sim/csv_format.h"

#include <charconv>

namespace kane_sim {

namespace {

// The columns, each named once beside the value it holds.
struct CsvColumn {
  const char* name;
  double (*value)(const Snapshot&);
};

const CsvColumn kColumns[] = {
    {"t", [](const Snapshot& s) { return s.time; }},
    {"q1", [](const Snapshot& s) { return s.state.q1; }},
    {"q2", [](const Snapshot& s) { return s.state.q2; }},
    {"u1", [](const Snapshot& s) { return s.state.u1; }},
    {"u2", [](const Snapshot& s) { return s.state.u2; }},
    {"energy", [](const Snapshot& s) { return s.energy.total(); }},
    {"u1dot", [](const Snapshot& s) { return s.u_dot[0]; }},
    {"u2dot", [](const Snapshot& s) { return s.u_dot[1]; }},
    {"torque", [](const Snapshot& s) { return s.torque; }},
    {"motor_work", [](const Snapshot& s) { return s.motor_work; }},
    {"kinetic", [](const Snapshot& s) { return s.energy.kinetic; }},
    {"gravitational", [](const Snapshot& s) { return s.energy.gravitational; }},
    {"spring", [](const Snapshot& s) { return s.energy.spring; }},
    {"energy_minus_work", [](const Snapshot& s) { return s.energy.total() - s.motor_work; }},
    {"F1", [](const Snapshot& s) { return s.active_forces[0]; }},
    {"F2", [](const Snapshot& s) { return s.active_forces[1]; }},
    {"spring_elongation", [](const Snapshot& s) { return s.spring_elongation; }},
    {"motor_power", [](const Snapshot& s) { return s.motor_power; }},
    {"dissipated_energy", [](const Snapshot& s) { return s.dissipated_energy; }},
    {"energy_balance", [](const Snapshot& s) { return s.energyBalance(); }},
    {"commanded_torque", [](const Snapshot& s) { return s.command.commanded; }},
    {"contact_impacts", [](const Snapshot& s) { return static_cast<double>(s.contact_impacts); }},
};

}  // namespace

void writeCsvHeader(std::ostream& out) {
  const char* separator = "";
  for (const CsvColumn& c : kColumns) {
    out << separator << c.name;
    separator = ",";
  }
  out << '\n';
}

void writeCsvRow(std::ostream& out, const Snapshot& s) {
  const char* separator = "";
  for (const CsvColumn& c : kColumns) {
    out << separator;
    writeCsvNumber(out, c.value(s));
    separator = ",";
  }
  out << '\n';
}

void writeCsvNumber(std::ostream& out, double value) {
  char buffer[32];  // the longest shortest form of a double is 24 characters
  const std::to_chars_result r = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.write(buffer, r.ptr - buffer);
}

}  // namespace kane_sim
