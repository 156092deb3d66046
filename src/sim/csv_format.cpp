#include "kane_sim/sim/csv_format.h"

#include <charconv>
#include <map>
#include <sstream>

namespace kane_sim {

namespace {

using Value = std::function<double(const Snapshot&)>;

// A column of its own group, keyed by its name.
CsvColumn column(const char* name, const char* group, const char* message_field, int index,
                 Value value) {
  return {name, group, name, message_field, index, std::move(value)};
}

std::vector<CsvColumn> makeColumns() {
  std::vector<CsvColumn> c = {
      column("t", "time", "sim_time", -1, [](const Snapshot& s) { return s.time; }),
      column("q1", "state", "q", 0, [](const Snapshot& s) { return s.state.q1; }),
      column("q2", "state", "q", 1, [](const Snapshot& s) { return s.state.q2; }),
      column("u1", "state", "u", 0, [](const Snapshot& s) { return s.state.u1; }),
      column("u2", "state", "u", 1, [](const Snapshot& s) { return s.state.u2; }),
      column("energy", "energy", "total_energy", -1,
             [](const Snapshot& s) { return s.energy.total(); }),
      column("u1dot", "equations", "u_dot", 0, [](const Snapshot& s) { return s.u_dot[0]; }),
      column("u2dot", "equations", "u_dot", 1, [](const Snapshot& s) { return s.u_dot[1]; }),
      column("torque", "command", "applied_torque", -1, [](const Snapshot& s) { return s.torque; }),
      column("motor_work", "ledger", "motor_work", -1,
             [](const Snapshot& s) { return s.motor_work; }),
      column("kinetic", "energy", "kinetic_energy", -1,
             [](const Snapshot& s) { return s.energy.kinetic; }),
      column("gravitational", "energy", "gravitational_energy", -1,
             [](const Snapshot& s) { return s.energy.gravitational; }),
      column("spring", "energy", "spring_energy", -1,
             [](const Snapshot& s) { return s.energy.spring; }),
      column("energy_minus_work", "derived", "", -1,
             [](const Snapshot& s) { return s.energy.total() - s.motor_work; }),
      column("F1", "equations", "active_forces", 0,
             [](const Snapshot& s) { return s.active_forces[0]; }),
      column("F2", "equations", "active_forces", 1,
             [](const Snapshot& s) { return s.active_forces[1]; }),
      column("spring_elongation", "geometry", "spring_elongation", -1,
             [](const Snapshot& s) { return s.spring_elongation; }),
  };
  // The loads' powers [W], one per name of the model's load list (Σ = dT/dt). The motor's
  // column kept its older name, motor_power, here among the ledger's; the others follow.
  auto loadPower = [](int n) {
    return [n](const Snapshot& s) { return s.load_powers.by_name[n]; };
  };
  const auto loadPowerColumn = [&](int n, std::string name) {
    const std::string load = kLoadInfo[n].name;
    return CsvColumn{std::move(name), "power", load, "load_powers", n, loadPower(n)};
  };
  const int motor = static_cast<int>(LoadName::kMotor);
  c.push_back(loadPowerColumn(motor, "motor_power"));
  c.insert(c.end(),
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
               column("rail_slider3", "reaction", "rail_force_slider3", -1,
                      [](const Snapshot& s) { return s.constraint_forces.rail_slider3; }),
               column("rail_slider4", "reaction", "rail_force_slider4", -1,
                      [](const Snapshot& s) { return s.constraint_forces.rail_slider4; }),
               column("spring_force", "reaction", "spring_force", -1,
                      [](const Snapshot& s) { return s.constraint_forces.spring; }),
           });
  for (int n = 0; n < kNumLoadNames; ++n)
    if (n != motor) c.push_back(loadPowerColumn(n, std::string("power_") + kLoadInfo[n].name));
  // Each body's kinetic energy [J] (Σ = T): the message's body_kinetic_energy array.
  const char* bodies[kNumBodies] = {"rod1", "rod2", "slider3", "slider4"};
  for (int b = 0; b < kNumBodies; ++b)
    c.push_back({std::string("kinetic_") + bodies[b], "kinetic", bodies[b], "body_kinetic_energy",
                 b, [b](const Snapshot& s) { return s.body_kinetic_energy[b]; }});
  c.push_back(column("impact_energy", "ledger", "impact_energy", -1,
                     [](const Snapshot& s) { return s.impact_energy; }));
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
  out << "| CSV column / Result column | group | Python group access | mechanism_state field |\n"
      << "|---|---|---|---|\n";
  for (const CsvColumn& c : csvColumns()) {
    const auto property = result_property.find(c.group);
    std::string python;
    if (property != result_property.end())
      python = "`Result." + property->second + "[\"" + c.key + "\"]`";
    std::string field = c.message_field.empty() ? "" : "`" + c.message_field;
    if (!field.empty())
      field += (c.message_index >= 0 ? "[" + std::to_string(c.message_index) + "]`" : "`");
    out << "| `" << c.name << "` | " << c.group << " | " << python << " | " << field << " |\n";
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
  const char* separator = "";
  for (const CsvColumn& c : csvColumns()) {
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
