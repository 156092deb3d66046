#include "kane_sim/sim/torque_profile.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "kane_sim/config/input_file.h"
#include "kane_sim/format_number.h"
#include "kane_sim/model/math_functions.h"
#include "kane_sim/sim/output_grid.h"
#include "kane_sim/sim/simulator.h"

namespace kane_sim {
namespace {

// What is wrong with playing a table whose header (`where`: "f.csv:1: the header 't,x'") named
// `named` as setpoints (or as torques); "" when nothing is.
std::string headerRefusal(const std::string& where, TorqueProfile::Named named, bool setpoints) {
  if (setpoints && named == TorqueProfile::Named::kTorque)
    return where + " names a torque [N m], not a setpoint [rad] (a setpoint table's header is " +
           "t,setpoint)";
  // And a setpoint's table played as a torque would drive the crank with its radians as
  // newton metres.
  if (!setpoints && named == TorqueProfile::Named::kSetpoint)
    return where + " names a setpoint, not a torque [N m] (a torque table's header is t,torque; " +
           "a setpoint table plays in command.mode position or velocity)";
  return "";
}

// The whole of `text` (surrounding blanks allowed) as a number; strtod, unlike std::stod, also
// takes values below the normal range (1e-320) instead of calling them out of range.
bool readNumber(const std::string& text, double* value) {
  const char* begin = text.c_str();
  char* end = nullptr;
  *value = std::strtod(begin, &end);
  return end != begin && text.find_first_not_of(" \t\r", end - begin) == std::string::npos;
}

double parseNumber(const std::string& text, const std::string& where) {
  double value = 0.0;
  if (!readNumber(text, &value))
    throw std::invalid_argument(where + ": '" + text + "' is not a number");
  if (!std::isfinite(value)) throw std::invalid_argument(where + ": '" + text + "' is not finite");
  return value;
}

// A header is recognised by its content: no field of it reads as a number ("t,torque").
bool isHeader(const std::string& line) {
  std::istringstream fields(line);
  std::string field;
  double value = 0.0;
  while (std::getline(fields, field, ','))
    if (readNumber(field, &value)) return false;
  return true;
}

}  // namespace

TorqueProfile::TorqueProfile(Kind kind, double a, double b, double c)
    : kind_(kind), a_(a), b_(b), c_(c) {}

TorqueProfile TorqueProfile::constant(double torque) {
  return TorqueProfile(Kind::kConstant, torque, 0.0, 0.0);
}

TorqueProfile TorqueProfile::step(double time, double before, double after) {
  return TorqueProfile(Kind::kStep, time, before, after);
}

TorqueProfile TorqueProfile::sine(double amplitude, double frequency, double offset) {
  // Every value the sine can take must be a number: 2 pi f t finite over the longest run, and
  // offset +- amplitude finite (else every row would be a refused command, torque 0).
  if (!std::isfinite(2 * M_PI * frequency * kMaxRunDuration))
    throw std::invalid_argument("sine frequency " + formatNumber(frequency) +
                                " Hz cannot be evaluated (2 pi f t overflows within " +
                                formatNumber(kMaxRunDuration) + " s)");
  if (!std::isfinite(std::abs(offset) + std::abs(amplitude)))
    throw std::invalid_argument("sine amplitude " + formatNumber(amplitude) + " and offset " +
                                formatNumber(offset) + ": offset + amplitude overflows");
  return TorqueProfile(Kind::kSine, amplitude, frequency, offset);
}

TorqueProfile TorqueProfile::table(std::vector<std::pair<double, double>> points) {
  for (size_t i = 0; i < points.size(); ++i) {
    if (!std::isfinite(points[i].first) || !std::isfinite(points[i].second))
      throw std::invalid_argument("torque table entry " + std::to_string(i + 1) + " is not finite");
    if (i > 0 && points[i].first < points[i - 1].first)
      throw std::invalid_argument("torque table entry " + std::to_string(i + 1) +
                                  ": time goes backwards");
  }
  TorqueProfile p(Kind::kTable, 0.0, 0.0, 0.0);
  p.points_ = std::move(points);
  return p;
}

TorqueProfile TorqueProfile::fromCsvFile(const std::string& path, TableValue value) {
  const bool setpoint = value == TableValue::kSetpoint;
  const std::string quantity = setpoint ? "setpoint" : "torque";
  std::ifstream in = openInputFile(path, quantity + " CSV", kMaxTableBytes);
  std::vector<std::pair<double, double>> points;
  std::string line;
  int number = 0;
  bool first_row = true;
  Named header_named = Named::kUnnamed;
  std::string header_where;
  // The columns read: t and the value, the first two unless a header names them (t or time;
  // torque or M_m, or setpoint): a plan of `design plan` (t,q1,q2,u1,u2,M_m,...) plays its M_m.
  size_t time_column = 0, value_column = 1, columns = 2;
  while (std::getline(in, line)) {
    ++number;
    const std::string where = path + ":" + std::to_string(number);
    if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // UTF-8 BOM
    const size_t start = line.find_first_not_of(" \t\r");
    if (start == std::string::npos || line[start] == '#') continue;
    std::vector<std::string> fields;
    std::istringstream split(line);
    for (std::string field; std::getline(split, field, ',');) fields.push_back(field);
    if (first_row && isHeader(line)) {
      first_row = false;
      const auto named = [&](std::initializer_list<const char*> names) {
        for (size_t i = 0; i < fields.size(); ++i) {
          const size_t a = fields[i].find_first_not_of(" \t\r");
          const size_t b = fields[i].find_last_not_of(" \t\r");
          const std::string name = a == std::string::npos ? "" : fields[i].substr(a, b - a + 1);
          for (const char* wanted : names)
            if (name == wanted) return i;
        }
        return std::string::npos;
      };
      const size_t t = named({"t", "time"}), torque = named({"torque", "M_m"});
      const size_t setpoint_column = named({"setpoint"});
      const size_t own = setpoint ? setpoint_column : torque;
      header_named =
          torque != std::string::npos && setpoint_column == std::string::npos   ? Named::kTorque
          : setpoint_column != std::string::npos && torque == std::string::npos ? Named::kSetpoint
                                                                                : Named::kUnnamed;
      header_where = where + ": the header '" + line + "'";
      // A torque's table played as a position setpoint would hold the crank at its newton
      // metres as radians: refused before its rows are read.
      if (setpoint) {
        const std::string refusal = headerRefusal(header_where, header_named, true);
        if (!refusal.empty()) throw std::invalid_argument(refusal);
      }
      if (t != std::string::npos && own != std::string::npos) {
        time_column = t;
        value_column = own;
        columns = fields.size();
      }
      continue;
    }
    first_row = false;
    const size_t end = line.find_last_not_of(" \t\r");
    if (line[end] == ',')
      throw std::invalid_argument(where + ": '" + line +
                                  "' ends with a comma (a value is missing)");
    if (fields.size() < 2 || (columns == 2 && fields.size() != 2) || fields.size() != columns)
      throw std::invalid_argument(
          where + ": expected " +
          (columns == 2 ? "'t," + quantity + "'" : std::to_string(columns) + " columns") +
          ", got '" + line + "'");
    const double t = parseNumber(fields[time_column], where + " (time)");
    const double v = parseNumber(fields[value_column], where + " (" + quantity + ")");
    if (setpoint && std::abs(v) > Simulator::kMaxCrankAngle)
      throw std::invalid_argument(where + " (setpoint): " + fields[value_column] +
                                  " rad is beyond a million turns");
    if (!points.empty() && t < points.back().first)
      throw std::invalid_argument(where + ": time " + fields[time_column] +
                                  " goes backwards (previous " +
                                  std::to_string(points.back().first) + ")");
    points.emplace_back(t, v);
  }
  if (points.empty()) throw std::invalid_argument(quantity + " CSV '" + path + "' has no rows");
  TorqueProfile profile = table(std::move(points));
  profile.named_ = header_named;
  profile.header_ = header_where;
  return profile;
}

void TorqueProfile::checkPlaysAs(bool setpoints) const {
  const std::string refusal = headerRefusal(header_, named_, setpoints);
  if (!refusal.empty()) throw std::invalid_argument(refusal);
}

namespace {

// "a,b[,c]": min_count to max_count finite numbers, each named in the message when it is not.
std::vector<double> parseFlagList(const std::string& flag, const std::string& text,
                                  size_t min_count, size_t max_count) {
  std::vector<double> values;
  std::istringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    try {
      size_t used = 0;
      values.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw std::invalid_argument("--" + flag + ": '" + item + "' is not a number");
    }
    if (!std::isfinite(values.back()))
      throw std::invalid_argument("--" + flag + " must be finite, got " +
                                  formatNumber(values.back()));
  }
  if (!text.empty() && text.back() == ',')
    throw std::invalid_argument("--" + flag + ": '" + text +
                                "' ends with a comma (a value is missing)");
  if (values.size() < min_count || values.size() > max_count)
    throw std::invalid_argument("--" + flag + " takes " + std::to_string(min_count) +
                                (max_count > min_count ? " to " + std::to_string(max_count) : "") +
                                " comma-separated numbers, got '" + text + "'");
  return values;
}

}  // namespace

TorqueProfile TorqueProfile::fromFlag(const std::string& flag, const std::string& text) {
  try {
    if (flag == "torque-step") {
      const auto v = parseFlagList(flag, text, 3, 3);
      return step(v[0], v[1], v[2]);
    }
    if (flag == "torque-sine") {
      const auto v = parseFlagList(flag, text, 2, 3);
      return sine(v[0], v[1], v.size() > 2 ? v[2] : 0.0);
    }
    if (flag == "torque-csv") return fromCsvFile(text);
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    if (what.rfind("--" + flag, 0) == 0) throw;  // already names the flag
    throw std::invalid_argument("--" + flag + ": " + what);
  }
  throw std::invalid_argument("'" + flag + "' is not one of torque-step, torque-sine, torque-csv");
}

TorqueProfile::Parts TorqueProfile::parts() const {
  return Parts{static_cast<int>(kind_), a_, b_, c_, points_, static_cast<int>(named_), header_};
}

TorqueProfile TorqueProfile::fromParts(const Parts& p) {
  switch (p.kind) {
    case 0:
      return constant(p.a);
    case 1:
      return step(p.a, p.b, p.c);
    case 2:
      return sine(p.a, p.b, p.c);
    case 3: {
      if (p.named < 0 || p.named > static_cast<int>(Named::kSetpoint))
        throw std::invalid_argument("torque profile: what its header named (" +
                                    std::to_string(p.named) + ") is not 0, 1 or 2");
      TorqueProfile profile = table(p.points);
      profile.named_ = static_cast<Named>(p.named);
      profile.header_ = p.header;
      return profile;
    }
  }
  throw std::invalid_argument("torque profile kind " + std::to_string(p.kind) +
                              " is not 0 (constant), 1 (step), 2 (sine) or 3 (table)");
}

double TorqueProfile::at(double t) const {
  switch (kind_) {
    case Kind::kConstant:
      return a_;
    case Kind::kStep:
      return t < a_ ? b_ : c_;
    case Kind::kSine:
      // The project's one sin (every build the same bits, the browser's too).
      return c_ + a_ * math::sin(2 * M_PI * b_ * t);
    case Kind::kTable: {
      // The last entry whose time is <= t.
      const auto after = std::upper_bound(points_.begin(), points_.end(), t,
                                          [](double v, const auto& p) { return v < p.first; });
      return after == points_.begin() ? 0.0 : std::prev(after)->second;
    }
  }
  return 0.0;
}

std::string TorqueProfile::describe(const std::string& unit) const {
  std::ostringstream out;
  switch (kind_) {
    case Kind::kConstant:
      out << "constant " << a_ << " " << unit;
      break;
    case Kind::kStep:
      out << "step at " << a_ << " s from " << b_ << " to " << c_ << " " << unit;
      break;
    case Kind::kSine:
      out << c_ << " + " << a_ << " sin(2 pi " << b_ << " Hz t) " << unit;
      break;
    case Kind::kTable:
      out << "table of " << points_.size() << " points";
      break;
  }
  return out.str();
}

}  // namespace kane_sim
