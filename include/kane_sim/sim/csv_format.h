// The CSV layout of `simulate`: one header, one row per snapshot, full double precision.
#ifndef KANE_SIM_SIM_CSV_FORMAT_H
#define KANE_SIM_SIM_CSV_FORMAT_H

#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "kane_sim/sim/snapshot.h"

namespace kane_sim {

// One output quantity, named once: its CSV column (also Result's and the plots' name), its group
// and key within the group (Python's Result.energies(), .powers(), ...), the /mechanism_state
// field that carries it (plot_bag reads bags through it), and its value. The per-load and
// per-body rows derive from the model's tables (kLoadInfo, the bodies), so a new load adds its
// power column, its Python key and its message field name with no list here to edit.
struct CsvColumn {
  std::string name;
  std::string group;          // "state", "energy", "ledger", "reaction", "power", "kinetic", ...
  std::string key;            // within the group: the load's or body's name, else the column's name
  std::string message_field;  // MechanismState's field, "" when the message has none
  int message_index = -1;     // the element of an array field, -1 for a scalar
  std::function<double(const Snapshot&)> value;
  // The column's name before 2026-11-26 ("" if it kept its name): Python's Result and the CSV
  // readers take it for one release with a DeprecationWarning naming the new one.
  std::string formerly = "";
};
// The columns in order: t,q1,q2,u1,u2,total_energy, then u1dot,u2dot,applied_torque,motor_work,
// kinetic_energy,gravitational_energy,spring_energy,energy_minus_work,F1,F2,spring_elongation,
// power_motor, then the ledger dissipated_energy and energy_balance (E + D - W -
// parameter_energy), commanded_torque, contact_impacts, then the reaction forces pin_o_x ...
// spring_force, the other loads' powers power_gravity ... power_contact (Σ power_* = dT/dt),
// each body's kinetic energy, impact_energy, and the rest of /mechanism_state (F1_star, F2_star,
// parameter_energy, ...). A quantity /mechanism_state carries as a scalar has its field's name.
// The Python module's result arrays use the same table.
const std::vector<CsvColumn>& csvColumns();

// The table as doc/reference/outputs.md shows it (Markdown, one row per column, in order):
// `config_info outputs` prints it; a test keeps the page equal to it.
std::string outputTable();

void writeCsvHeader(std::ostream& out);
void writeCsvRow(std::ostream& out, const Snapshot& snapshot);
// One row of values already taken from snapshots (the browser's rows, in csvColumns' order).
void writeCsvValues(std::ostream& out, const double* values, size_t count);

// One number as the CSVs print it: the shortest text that reads back as exactly this double
// (std::to_chars), so every value round-trips and none carries noise digits.
void writeCsvNumber(std::ostream& out, double value);

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_CSV_FORMAT_H
