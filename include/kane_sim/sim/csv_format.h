// The CSV layout of `simulate`: one header, one row per snapshot, full double precision.
#ifndef KANE_SIM_SIM_CSV_FORMAT_H
#define KANE_SIM_SIM_CSV_FORMAT_H

#include <ostream>

#include "kane_sim/sim/snapshot.h"

namespace kane_sim {

// One column: its name in the header and the value it holds.
struct CsvColumn {
  const char* name;
  double (*value)(const Snapshot&);
};
// The columns in order: t,q1,q2,u1,u2,energy, then u1dot,u2dot,torque,motor_work,kinetic,
// gravitational,spring,energy_minus_work,F1,F2,spring_elongation,motor_power, then the ledger
// dissipated_energy and energy_balance (E + D - W - parameter_energy), commanded_torque (torque
// is the applied one), contact_impacts, then the reaction forces pin_o_x ... spring_force, the
// loads' powers power_gravity ... power_contact (with motor_power: Σ = dT/dt), each body's
// kinetic energy and impact_energy. The Python module's result arrays use the same table.
const CsvColumn* csvColumnsBegin();
const CsvColumn* csvColumnsEnd();

void writeCsvHeader(std::ostream& out);
void writeCsvRow(std::ostream& out, const Snapshot& snapshot);

// One number as the CSVs print it: the shortest text that reads back as exactly this double
// (std::to_chars), so every value round-trips and none carries noise digits.
void writeCsvNumber(std::ostream& out, double value);

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_CSV_FORMAT_H
