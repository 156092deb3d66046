#include "kane_sim/design/plan_file.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "kane_sim/config/input_file.h"
#include "kane_sim/config/parameter_schema.h"
#include "kane_sim/format_number.h"

namespace kane_sim {

const char* const kPlanColumns = "t,q1,q2,u1,u2,M_m,K_q1,K_q2,K_u1,K_u2";

namespace {

constexpr int kColumnCount = 10;

// 17 significant digits: a number read back is the number written.
std::string exact(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value + 0.0);
  return text;
}

// Text from a file, fit for a message: bytes outside printable ASCII as \xNN, at most 80.
std::string printable(const std::string& text) {
  std::string out;
  for (unsigned char c : text.substr(0, 80)) {
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02X", c);
      out += escaped;
    }
  }
  return text.size() > 80 ? out + "..." : out;
}

std::string trimmed(const std::string& text) {
  const size_t begin = text.find_first_not_of(" \t\r");
  if (begin == std::string::npos) return "";
  return text.substr(begin, text.find_last_not_of(" \t\r") - begin + 1);
}

double parseValue(const std::string& text, const std::string& where) {
  const std::string value = trimmed(text);
  char* end = nullptr;
  const double number = std::strtod(value.c_str(), &end);
  if (value.empty() || *end != '\0')
    throw PlanError(where + ": '" + printable(value) + "' is not a number");
  if (!std::isfinite(number)) throw PlanError(where + ": '" + printable(value) + "' is not finite");
  return number;
}

}  // namespace

std::map<std::string, double> planMechanism(const Config& config) {
  std::map<std::string, double> values;
  Config copy = config;
  for (const ParameterSpec& spec : parameterSchema())
    if (inEquations(spec.role) && spec.field.number) values[spec.path()] = spec.field.number(copy);
  values["spring_rest_length"] = mechanismModel(config).springRestLength();
  return values;
}

void writePlanCsv(std::ostream& out, const Plan& plan, const Config& config,
                  const std::vector<std::string>& notes) {
  for (const std::string& note : notes) out << "# " << note << "\n";
  for (const auto& [name, value] : planMechanism(config))
    out << "# " << name << " = " << exact(value) << "\n";
  out << "# periodic = " << (plan.periodic ? 1 : 0) << "\n";
  out << kPlanColumns << "\n";
  for (const PlanPoint& p : plan.points) {
    out << exact(p.t);
    for (int i = 0; i < 4; ++i) out << "," << exact(p.x[i]);
    out << "," << exact(p.torque);
    for (int i = 0; i < 4; ++i) out << "," << exact(p.K[i]);
    out << "\n";
  }
  out << "# end of plan: " << plan.points.size() << " rows\n";
}

bool isPlanCsv(const std::string& path) {
  try {
    std::ifstream in = openInputFile(path, "plan CSV", kMaxTableBytes);
    for (std::string line; std::getline(in, line);) {
      const std::string text = trimmed(line);
      if (text.empty() || text[0] == '#') continue;
      return text == kPlanColumns;
    }
  } catch (const std::invalid_argument&) {
  }
  return false;
}

PlanFile readPlanCsv(const std::string& path) {
  std::ifstream in;
  try {
    in = openInputFile(path, "plan CSV", kMaxTableBytes);
  } catch (const std::invalid_argument& e) {
    throw PlanError(e.what());
  }
  PlanFile file;
  bool header_seen = false;
  long end_rows = -1;  // the end line's count
  int number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    const std::string where = path + ":" + std::to_string(number);
    const std::string text = trimmed(line);
    if (text.empty()) continue;
    if (text[0] == '#') {
      const std::string end_mark = "# end of plan: ";
      if (header_seen && text.rfind(end_mark, 0) == 0) {
        end_rows = static_cast<long>(parseValue(
            text.substr(end_mark.size(), text.find(' ', end_mark.size()) - end_mark.size()),
            where + " (the end line's rows)"));
        continue;
      }
      const size_t equals = text.find('=');
      if (header_seen || equals == std::string::npos) continue;
      const std::string name = trimmed(text.substr(1, equals - 1));
      if (name == "periodic") {
        file.plan.periodic = parseValue(text.substr(equals + 1), where + " (periodic)") != 0.0;
      } else if (name.find(' ') == std::string::npos) {
        file.mechanism[name] = parseValue(text.substr(equals + 1), where + " (" + name + ")");
      }
      continue;
    }
    if (!header_seen) {
      if (text != kPlanColumns)
        throw PlanError(where + ": expected the plan's header '" + kPlanColumns + "', got '" +
                        printable(text) + "'");
      header_seen = true;
      continue;
    }
    if (end_rows >= 0) throw PlanError(where + ": a row after the plan's end line");
    if (static_cast<long>(file.plan.points.size()) >= kMaxPlanRows)
      throw PlanError(where + ": more than " + std::to_string(kMaxPlanRows) + " rows");
    std::vector<double> values;
    std::stringstream fields(text);
    static const char* const names[] = {"t",   "q1",   "q2",   "u1",   "u2",
                                        "M_m", "K_q1", "K_q2", "K_u1", "K_u2"};
    for (std::string field; std::getline(fields, field, ',');) {
      if (values.size() == kColumnCount)
        throw PlanError(where + ": more than " + std::to_string(kColumnCount) + " columns");
      values.push_back(parseValue(field, where + " (" + names[values.size()] + ")"));
    }
    if (values.size() != kColumnCount)
      throw PlanError(where + ": " + std::to_string(values.size()) + " columns, the plan has " +
                      std::to_string(kColumnCount) + " (" + kPlanColumns + ")");
    PlanPoint p;
    p.t = values[0];
    p.x << values[1], values[2], values[3], values[4];
    p.torque = values[5];
    p.K << values[6], values[7], values[8], values[9];
    std::vector<PlanPoint>& points = file.plan.points;
    if (points.empty() && p.t != 0.0)
      throw PlanError(where + ": the first row's t is " + formatNumber(p.t) +
                      ", a plan starts at 0");
    if (points.size() == 1) {
      file.plan.step = p.t - points[0].t;
      if (!(file.plan.step >= 1e-6))
        throw PlanError(where + ": rows " + formatNumber(file.plan.step) +
                        " s apart: a plan's rows are at least 1e-06 s apart");
    }
    if (points.size() >= 1) {
      const double step = file.plan.step;
      const double expected = static_cast<double>(points.size()) * step;
      if (!(step > 0.0) || std::abs(p.t - expected) > 1e-6 * step)
        throw PlanError(
            where + ": t = " + formatNumber(p.t) + " after " + formatNumber(points.back().t) +
            ": the rows must be evenly spaced " +
            (step > 0.0 ? formatNumber(step) + " s apart (a gap or a repeat)" : "and increasing"));
    }
    points.push_back(p);
  }
  if (!header_seen) throw PlanError("plan CSV '" + path + "' has no header line " + kPlanColumns);
  if (file.plan.points.size() < 2)
    throw PlanError("plan CSV '" + path + "' has " + std::to_string(file.plan.points.size()) +
                    " rows: a plan has at least 2");
  if (end_rows != static_cast<long>(file.plan.points.size()))
    throw PlanError("plan CSV '" + path + "' " +
                    (end_rows < 0 ? std::string("has no end line '# end of plan: N rows'")
                                  : "says it has " + std::to_string(end_rows) + " rows") +
                    " after its " + std::to_string(file.plan.points.size()) +
                    " rows: cut off or edited? (design plan writes it whole)");
  return file;
}

std::string planMismatch(const PlanFile& file, const Config& config) {
  const State& start = config.initial_state;
  const double config_start[] = {start.q1, start.q2, start.u1, start.u2};
  const char* names[] = {"q1", "q2", "u1", "u2"};
  for (int i = 0; i < 4; ++i)
    if (!file.plan.points.empty() &&
        std::abs(file.plan.points.front().x[i] - config_start[i]) > 1e-9)
      return std::string("initial_state.") + names[i] + ": the plan starts at " +
             formatNumber(file.plan.points.front().x[i]) + ", the config at " +
             formatNumber(config_start[i]);
  for (const auto& [name, value] : planMechanism(config)) {
    const auto it = file.mechanism.find(name);
    if (it == file.mechanism.end())
      return name +
             ": the plan does not say what it was designed for (a plan of another "
             "version or edited)";
    if (std::abs(it->second - value) > 1e-9 * std::max(std::abs(value), 1e-12))
      return name + ": the plan was designed for " + formatNumber(it->second) +
             ", the config has " + formatNumber(value);
  }
  return "";
}

}  // namespace kane_sim
