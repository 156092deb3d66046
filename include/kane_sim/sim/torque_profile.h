// Torque as a function of sim time for the offline tool: constant, step, sine, or a table of
// (t, torque) pairs held from each time on (zero-order hold, like a stream of commands).
#ifndef KANE_SIM_SIM_TORQUE_PROFILE_H
#define KANE_SIM_SIM_TORQUE_PROFILE_H

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace kane_sim {

class TorqueProfile {
 public:
  static TorqueProfile constant(double torque);
  static TorqueProfile step(double time, double before, double after);
  static TorqueProfile sine(double amplitude, double frequency, double offset);
  // Times must be finite and non-decreasing, torques finite; before the first time: 0.
  static TorqueProfile table(std::vector<std::pair<double, double>> points);
  // What a table's values are to its reader: a torque [N m] or a servo's setpoint, whichever the
  // mode it is played in makes them (simulate's --torque-csv, sweeps, the page: the header is
  // remembered and checkPlaysAs refuses the other), or a setpoint [rad] (pd_controller's
  // ~setpoint_table, a servo mode), which a header naming a torque (torque, M_m) is not, and
  // whose values are within a million turns (Simulator::kMaxCrankAngle, as the servo's
  // setpoints).
  enum class TableValue { kTorque, kSetpoint };
  // What a table's CSV header named its values: a torque (torque or M_m) and no setpoint, a
  // setpoint and no torque, or neither (no header, both, or not read from a file).
  enum class Named { kUnnamed, kTorque, kSetpoint };
  // A CSV of `t,torque` (`t,setpoint`) lines (an optional header line, # comments); throws
  // std::invalid_argument naming the file, the line and the bad value.
  static TorqueProfile fromCsvFile(const std::string& path, TableValue value = TableValue::kTorque);
  // simulate's flags, for every tool that takes them: flag "torque-step" (text "T,BEFORE,AFTER"),
  // "torque-sine" ("A,F[,OFFSET]") or "torque-csv" (a file). Throws std::invalid_argument naming
  // the flag and the value ("--torque-sine: 'x' is not a number").
  static TorqueProfile fromFlag(const std::string& flag, const std::string& text);

  // What it is made of, enough to make it again (on another machine: a cluster's worker).
  struct Parts {
    int kind = 0;  // 0 constant, 1 step, 2 sine, 3 table
    double a = 0.0, b = 0.0, c = 0.0;
    std::vector<std::pair<double, double>> points;
    int named = 0;  // Named
    // Where the header is and what it says: "sp.csv:1: the header 't,setpoint'".
    std::string header;
  };
  Parts parts() const;
  // Through the factories above: what they refuse is refused (std::invalid_argument).
  static TorqueProfile fromParts(const Parts& parts);

  // Throws std::invalid_argument, naming the file, the line and the header, when the header named
  // the other quantity than what it is played as: a setpoint table played as torques would drive
  // the crank with its radians as newton metres, and the reverse.
  void checkPlaysAs(bool setpoints) const;

  double at(double t) const;  // [N m]
  bool isConstant() const { return kind_ == Kind::kConstant; }
  // "constant 0.5 N m", "step at 1 s from 0 to 2 N m", ...; unit: of the values ("rad" when
  // the profile is a position servo's setpoint).
  std::string describe(const std::string& unit = "N m") const;

 private:
  enum class Kind { kConstant, kStep, kSine, kTable };
  TorqueProfile(Kind kind, double a, double b, double c);

  Kind kind_;
  // constant: a; step: a = time, b = before, c = after; sine: a = amplitude, b = f, c = offset
  double a_, b_, c_;
  std::vector<std::pair<double, double>> points_;
  Named named_ = Named::kUnnamed;
  std::string header_;  // Parts::header
};

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_TORQUE_PROFILE_H
