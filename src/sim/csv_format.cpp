#include "kane_sim/sim/csv_format.h"

#include <charconv>
#include <iterator>

namespace kane_sim {

namespace {

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
    // Reaction forces (Kane's method with auxiliary speeds), frame (0) [N].
    {"pin_o_x", [](const Snapshot& s) { return s.constraint_forces.pin_o.x(); }},
    {"pin_o_y", [](const Snapshot& s) { return s.constraint_forces.pin_o.y(); }},
    {"pin_a_x", [](const Snapshot& s) { return s.constraint_forces.pin_a.x(); }},
    {"pin_a_y", [](const Snapshot& s) { return s.constraint_forces.pin_a.y(); }},
    {"pin_b_x", [](const Snapshot& s) { return s.constraint_forces.pin_b.x(); }},
    {"pin_b_y", [](const Snapshot& s) { return s.constraint_forces.pin_b.y(); }},
    {"rail_slider3", [](const Snapshot& s) { return s.constraint_forces.rail_slider3; }},
    {"rail_slider4", [](const Snapshot& s) { return s.constraint_forces.rail_slider4; }},
    {"spring_force", [](const Snapshot& s) { return s.constraint_forces.spring; }},
    // Power flow [W]: each load (their sum is dT/dt), then each body's kinetic energy [J].
    {"power_gravity", [](const Snapshot& s) { return s.load_powers.gravity; }},
    {"power_spring", [](const Snapshot& s) { return s.load_powers.spring; }},
    {"power_crank_damper", [](const Snapshot& s) { return s.load_powers.crank_damper; }},
    {"power_coupler_damper", [](const Snapshot& s) { return s.load_powers.coupler_damper; }},
    {"power_slider3_damper", [](const Snapshot& s) { return s.load_powers.slider3_damper; }},
    {"power_slider4_damper", [](const Snapshot& s) { return s.load_powers.slider4_damper; }},
    {"power_contact", [](const Snapshot& s) { return s.load_powers.contact; }},
    {"kinetic_rod1", [](const Snapshot& s) { return s.body_kinetic_energy[kRod1]; }},
    {"kinetic_rod2", [](const Snapshot& s) { return s.body_kinetic_energy[kRod2]; }},
    {"kinetic_slider3", [](const Snapshot& s) { return s.body_kinetic_energy[kSlider3]; }},
    {"kinetic_slider4", [](const Snapshot& s) { return s.body_kinetic_energy[kSlider4]; }},
    {"impact_energy", [](const Snapshot& s) { return s.impact_energy; }},
};

}  // namespace

const CsvColumn* csvColumnsBegin() { return std::begin(kColumns); }
const CsvColumn* csvColumnsEnd() { return std::end(kColumns); }

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
