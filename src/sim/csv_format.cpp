#include "kane_sim/sim/csv_format.h"

#include <charconv>

namespace kane_sim {

void writeCsvHeader(std::ostream& out) {
  out << "t,q1,q2,u1,u2,energy,u1dot,u2dot,torque,motor_work,kinetic,gravitational,spring,"
         "energy_minus_work,F1,F2,spring_elongation,motor_power,dissipated_energy,energy_balance,"
         "commanded_torque,contact_impacts\n";
}

void writeCsvRow(std::ostream& out, const Snapshot& s) {
  const double values[] = {s.time,
                           s.state.q1,
                           s.state.q2,
                           s.state.u1,
                           s.state.u2,
                           s.energy.total(),
                           s.u_dot[0],
                           s.u_dot[1],
                           s.torque,
                           s.motor_work,
                           s.energy.kinetic,
                           s.energy.gravitational,
                           s.energy.spring,
                           s.energy.total() - s.motor_work,
                           s.active_forces[0],
                           s.active_forces[1],
                           s.spring_elongation,
                           s.motor_power,
                           s.dissipated_energy,
                           s.energyBalance(),
                           s.command.commanded,
                           static_cast<double>(s.contact_impacts)};
  bool first = true;
  for (double v : values) {
    if (!first) out << ',';
    writeCsvNumber(out, v);
    first = false;
  }
  out << '\n';
}

void writeCsvNumber(std::ostream& out, double value) {
  char buffer[32];  // the longest shortest form of a double is 24 characters
  const std::to_chars_result r = std::to_chars(buffer, buffer + sizeof(buffer), value);
  out.write(buffer, r.ptr - buffer);
}

}  // namespace kane_sim
