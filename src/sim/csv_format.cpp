#include "kane_sim/sim/csv_format.h"

#include <charconv>
#include <map>
#include <sstream>

#include "kane_sim/format_number.h"

namespace kane_sim {

namespace {

using Value = std::function<double(const Snapshot&)>;

// A column of its own group, keyed by its name.
CsvColumn column(const char* name, const char* group, const char* message_field, int index,
                 Value value, const char* formerly = "") {
  return {name, group, name, message_field, index, std::move(value), formerly};
}

std::vector<CsvColumn> makeColumns() {
  std::vector<CsvColumn> c = {
      column("t", "time", "sim_time", -1, [](const Snapshot& s) { return s.time; }),
      column("q1", "state", "q", 0, [](const Snapshot& s) { return s.state.q1; }),
      column("q2", "state", "q", 1, [](const Snapshot& s) { return s.state.q2; }),
      column("u1", "state", "u", 0, [](const Snapshot& s) { return s.state.u1; }),
      column("u2", "state", "u", 1, [](const Snapshot& s) { return s.state.u2; }),
      column(
          "total_energy", "energy", "total_energy", -1,
          [](const Snapshot& s) { return s.energy.total(); }, "energy"),
      column("u1dot", "equations", "u_dot", 0, [](const Snapshot& s) { return s.u_dot[0]; }),
      column("u2dot", "equations", "u_dot", 1, [](const Snapshot& s) { return s.u_dot[1]; }),
      column(
          "applied_torque", "command", "applied_torque", -1,
          [](const Snapshot& s) { return s.torque; }, "torque"),
      column("motor_work", "ledger", "motor_work", -1,
             [](const Snapshot& s) { return s.motor_work; }),
      column(
          "kinetic_energy", "energy", "kinetic_energy", -1,
          [](const Snapshot& s) { return s.energy.kinetic; }, "kinetic"),
  };
  // Each conservative load's potential energy [J] (Σ + T = total_energy), under its LoadInfo's
  // energy column: the message's fields of those names for the textbook's gravity and spring,
  // its load_energies array (keyed by load_names) for any other.
  for (int n = 0; n < kNumLoadNames; ++n) {
    const LoadInfo& load = kLoadInfo[n];
    if (!load.energy_column) continue;
    const LoadName name = static_cast<LoadName>(n);
    const bool own_field = name == LoadName::kGravity || name == LoadName::kSpring;
    const char* formerly = name == LoadName::kGravity  ? "gravitational"
                           : name == LoadName::kSpring ? "spring"
                                                       : "";
    c.push_back({load.energy_column, "energy", load.energy_column,
                 own_field ? load.energy_column : "load_energies", own_field ? -1 : n,
                 [n](const Snapshot& s) { return s.energy.potential[n]; }, formerly});
  }
  c.insert(c.end(), {
                        column("energy_minus_work", "derived", "", -1,
                               [](const Snapshot& s) { return s.energy.total() - s.motor_work; }),
                        column("F1", "equations", "active_forces", 0,
                               [](const Snapshot& s) { return s.active_forces[0]; }),
                        column("F2", "equations", "active_forces", 1,
                               [](const Snapshot& s) { return s.active_forces[1]; }),
                        column("spring_elongation", "geometry", "spring_elongation", -1,
                               [](const Snapshot& s) { return s.spring_elongation; }),
                    });
  // The loads' powers [W], power_<load> for each name of the model's load list (Σ = dT/dt). The
  // motor's comes here, where its older name motor_power stood; the others follow.
  auto loadPower = [](int n) {
    return [n](const Snapshot& s) { return s.load_powers.by_name[n]; };
  };
  const auto loadPowerColumn = [&](int n, std::string formerly) {
    const std::string load = kLoadInfo[n].name;
    return CsvColumn{"power_" + load,    "power", load, "load_powers", n, loadPower(n),
                     std::move(formerly)};
  };
  const int motor = static_cast<int>(LoadName::kMotor);
  c.push_back(loadPowerColumn(motor, "motor_power"));
  c.insert(
      c.end(),
      {
          column("dissipated_energy", "ledger", "dissipated_energy", -1,
                 [](const Snapshot& s) { return s.dissipated_energy; }),
          column("energy_balance", "ledger", "energy_balance", -1,
                 [](const Snapshot& s) { return s.energyBalance(); }),
          column("commanded_torque", "command", "commanded_torque", -1,
                 [](const Snapshot& s) { return s.command.commanded; }),
          column("contact_impacts", "contact", "contact_impacts", -1,
                 [](const Snapshot& s) { return static_cast<double>(s.contact_impacts); }),
          // Reaction forces (Kane's method with auxiliary speeds), frame (0) [N].
          column("pin_o_x", "reaction", "pin_o_force", 0,
                 [](const Snapshot& s) { return s.constraint_forces.pin_o.x(); }),
          column("pin_o_y", "reaction", "pin_o_force", 1,
                 [](const Snapshot& s) { return s.constraint_forces.pin_o.y(); }),
          column("pin_a_x", "reaction", "pin_a_force", 0,
                 [](const Snapshot& s) { return s.constraint_forces.pin_a.x(); }),
          column("pin_a_y", "reaction", "pin_a_force", 1,
                 [](const Snapshot& s) { return s.constraint_forces.pin_a.y(); }),
          column("pin_b_x", "reaction", "pin_b_force", 0,
                 [](const Snapshot& s) { return s.constraint_forces.pin_b.x(); }),
          column("pin_b_y", "reaction", "pin_b_force", 1,
                 [](const Snapshot& s) { return s.constraint_forces.pin_b.y(); }),
          column(
              "rail_force_slider3", "reaction", "rail_force_slider3", -1,
              [](const Snapshot& s) { return s.constraint_forces.rail_slider3; }, "rail_slider3"),
          column(
              "rail_force_slider4", "reaction", "rail_force_slider4", -1,
              [](const Snapshot& s) { return s.constraint_forces.rail_slider4; }, "rail_slider4"),
          column("spring_force", "reaction", "spring_force", -1,
                 [](const Snapshot& s) { return s.constraint_forces.spring; }),
      });
  for (int n = 0; n < kNumLoadNames; ++n)
    if (n != motor) c.push_back(loadPowerColumn(n, ""));
  // Each body's kinetic energy [J] (Σ = T): the message's body_kinetic_energy array.
  const char* bodies[kNumBodies] = {"rod1", "rod2", "slider3", "slider4"};
  for (int b = 0; b < kNumBodies; ++b)
    c.push_back({std::string("kinetic_") + bodies[b], "kinetic", bodies[b], "body_kinetic_energy",
                 b, [b](const Snapshot& s) { return s.body_kinetic_energy[b]; }});
  c.push_back(column("impact_energy", "ledger", "impact_energy", -1,
                     [](const Snapshot& s) { return s.impact_energy; }));
  // The rest of /mechanism_state, so that the message has no field outside this table but
  // real_time_factor (the node's pacing, not the mechanism's) and load_names (the powers' keys).
  // Counts and flags as numbers (a bool as 0 or 1).
  const auto count = [](std::uint64_t n) { return static_cast<double>(n); };
  c.insert(
      c.end(),
      {
          column("F1_star", "equations", "inertia_forces", 0,
                 [](const Snapshot& s) { return s.inertia_forces[0]; }),
          column("F2_star", "equations", "inertia_forces", 1,
                 [](const Snapshot& s) { return s.inertia_forces[1]; }),
          column("parameter_energy", "ledger", "parameter_energy", -1,
                 [](const Snapshot& s) { return s.parameter_energy; }),
          column("parameter_changes", "events", "parameter_changes", -1,
                 [count](const Snapshot& s) { return count(s.parameter_changes); }),
          column("slider_separation", "geometry", "slider_separation", -1,
                 [](const Snapshot& s) { return s.slider_separation; }),
          column("slider_crossings", "contact", "slider_crossings", -1,
                 [count](const Snapshot& s) { return count(s.slider_crossings); }),
          column("resting_contact", "flags", "resting_contact", -1,
                 [](const Snapshot& s) { return s.resting_contact ? 1.0 : 0.0; }),
          column("contact_force", "contact", "contact_force", -1,
                 [](const Snapshot& s) { return s.contact_force; }),
          column("reactions_determinate", "flags", "reactions_determinate", -1,
                 [](const Snapshot& s) { return s.constraint_forces.determinate ? 1.0 : 0.0; }),
      });
  return c;
}

}  // namespace

const std::vector<CsvColumn>& csvColumns() {
  static const std::vector<CsvColumn> columns = makeColumns();
  return columns;
}

std::string outputTable() {
  // Python's Result reaches each group through one property.
  const std::map<std::string, std::string> result_property = {{"energy", "energies"},
                                                              {"ledger", "ledger"},
                                                              {"reaction", "reactions"},
                                                              {"power", "powers"},
                                                              {"kinetic", "kinetic_per_body"}};
  std::ostringstream out;
  out << "| CSV column / Result column | group | Python group access | mechanism_state field | "
         "formerly |\n"
      << "|---|---|---|---|---|\n";
  for (const CsvColumn& c : csvColumns()) {
    const auto property = result_property.find(c.group);
    std::string python;
    if (property != result_property.end())
      python = "`Result." + property->second + "[\"" + c.key + "\"]`";
    std::string field = c.message_field.empty() ? "" : "`" + c.message_field;
    if (!field.empty())
      field += (c.message_index >= 0 ? "[" + std::to_string(c.message_index) + "]`" : "`");
    const std::string formerly = c.formerly.empty() ? "" : "`" + c.formerly + "`";
    out << "| `" << c.name << "` | " << c.group << " | " << python << " | " << field << " | "
        << formerly << " |\n";
  }
  return out.str();
}

void writeCsvHeader(std::ostream& out) {
  const char* separator = "";
  for (const CsvColumn& c : csvColumns()) {
    out << separator << c.name;
    separator = ",";
  }
  out << '\n';
}

void writeCsvRow(std::ostream& out, const Snapshot& s) {
  thread_local std::vector<double> row;  // one row's values, reused: no allocation per row
  row.clear();
  for (const CsvColumn& c : csvColumns()) row.push_back(c.value(s));
  writeCsvValues(out, row.data(), row.size());
}

void writeCsvValues(std::ostream& out, const double* values, size_t count) {
  for (size_t i = 0; i < count; ++i) {
    if (i) out << ',';
    writeCsvNumber(out, values[i]);
  }
  out << '\n';
}

void writeCsvNumber(std::ostream& out, double value) {
  char buffer[32];  // the longest shortest form of a double is 24 characters
  out.write(buffer, shortestChars(buffer, value) - buffer);
}

}  // namespace kane_sim
