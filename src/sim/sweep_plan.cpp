// Sweep plans: a grid of axes or a CSV of parameter sets, and each case's config.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "kane_sim/config/load_config.h"
#include "kane_sim/config/parameter_schema.h"
#include "kane_sim/format_number.h"
#include "kane_sim/sim/config_check.h"
#include "kane_sim/sim/numbers_into_configs.h"
#include "kane_sim/sim/sweep.h"

namespace kane_sim {
namespace {

double parseNumber(const std::string& text, const std::string& what) {
  try {
    size_t used = 0;
    const double value = std::stod(text, &used);
    if (used == text.size() && std::isfinite(value)) return value;
  } catch (const std::exception&) {
  }
  throw std::invalid_argument(what + ": '" + text + "' is not a finite number");
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::istringstream in(text);
  std::string part;
  while (std::getline(in, part, separator)) parts.push_back(part);
  if (!text.empty() && text.back() == separator) parts.emplace_back();
  return parts;
}

std::string trim(const std::string& s) {
  const size_t begin = s.find_first_not_of(" \t\r");
  const size_t end = s.find_last_not_of(" \t\r");
  return begin == std::string::npos ? "" : s.substr(begin, end - begin + 1);
}

bool isName(const std::string& part) {
  return !part.empty() && std::all_of(part.begin(), part.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
  });
}

void requireKey(const std::string& key) {
  const std::vector<std::string> parts = split(key, '.');
  if (parts.size() != 2 || !isName(parts[0]) || !isName(parts[1]))
    throw std::invalid_argument(
        "sweep key '" + key +
        "' must be section.key as in the config file, of letters, digits and '_' (e.g. "
        "mechanism.spring_stiffness; a cell starting with =, +, - or @ would be a spreadsheet "
        "formula)");
}

// At most this many cases: a grid typo (count 1e9) should be an error, not an out-of-memory.
constexpr double kMaxCases = 1e7;

}  // namespace

SweepAxis parseSweepAxis(const std::string& spec) {
  const size_t equals = spec.find('=');
  if (equals == std::string::npos)
    throw std::invalid_argument("--sweep '" + spec + "' must be KEY=START:STOP:COUNT");
  SweepAxis axis;
  axis.key = trim(spec.substr(0, equals));
  requireKey(axis.key);
  const std::vector<std::string> range = split(spec.substr(equals + 1), ':');
  if (range.size() != 3)
    throw std::invalid_argument("--sweep '" + spec + "': the range must be START:STOP:COUNT");
  const double start = parseNumber(range[0], "--sweep " + axis.key + " START");
  const double stop = parseNumber(range[1], "--sweep " + axis.key + " STOP");
  const double count = parseNumber(range[2], "--sweep " + axis.key + " COUNT");
  if (!(count >= 1 && count <= kMaxCases && count == std::floor(count)))
    throw std::invalid_argument("--sweep " + axis.key + " COUNT must be a whole number in [1, " +
                                std::to_string(static_cast<long>(kMaxCases)) + "], got '" +
                                range[2] + "'");
  const long n = static_cast<long>(count);
  // start (1 - t) + stop t: no stop - start, which overflows for -1e308:1e308; t = 1 gives stop.
  for (long i = 0; i < n; ++i) {
    const double t = n == 1 ? 0.0 : static_cast<double>(i) / static_cast<double>(n - 1);
    axis.values.push_back(start * (1.0 - t) + stop * t);
  }
  return axis;
}

SweepPlan sweepGrid(const std::vector<SweepAxis>& axes) {
  SweepPlan plan;
  double total = 1;
  for (const SweepAxis& axis : axes) {
    if (std::find(plan.keys.begin(), plan.keys.end(), axis.key) != plan.keys.end())
      throw std::invalid_argument("--sweep names " + axis.key + " twice");
    plan.keys.push_back(axis.key);
    total *= static_cast<double>(axis.values.size());
  }
  if (axes.empty())
    throw std::invalid_argument("a sweep needs at least one key to vary, the grid has none");
  if (total > kMaxCases)
    throw std::invalid_argument("a sweep needs 1 to " +
                                std::to_string(static_cast<long>(kMaxCases)) +
                                " cases, the grid has " + formatNumber(total));
  std::vector<size_t> at(axes.size(), 0);
  for (long c = 0; c < static_cast<long>(total); ++c) {
    std::vector<double> values;
    for (size_t a = 0; a < axes.size(); ++a) values.push_back(axes[a].values[at[a]]);
    plan.cases.push_back(std::move(values));
    for (size_t a = axes.size(); a-- > 0;) {  // the last axis varies fastest
      if (++at[a] < axes[a].values.size()) break;
      at[a] = 0;
    }
  }
  return plan;
}

SweepPlan sweepFromCsv(std::istream& in) {
  SweepPlan plan;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    // A UTF-8 byte-order mark (spreadsheets write one) is not part of the first key.
    if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line = line.substr(3);
    line = trim(line);
    if (line.empty() || line[0] == '#') continue;
    const std::vector<std::string> fields = split(line, ',');
    if (plan.keys.empty()) {
      for (const std::string& field : fields) {
        plan.keys.push_back(trim(field));
        requireKey(plan.keys.back());
        if (std::count(plan.keys.begin(), plan.keys.end(), plan.keys.back()) > 1)
          throw std::invalid_argument("line 1: " + plan.keys.back() + " appears twice");
      }
      continue;
    }
    if (fields.size() != plan.keys.size())
      throw std::invalid_argument("line " + std::to_string(number) + " has " +
                                  std::to_string(fields.size()) + " values for " +
                                  std::to_string(plan.keys.size()) + " keys");
    std::vector<double> values;
    for (size_t i = 0; i < fields.size(); ++i)
      values.push_back(
          parseNumber(trim(fields[i]), "line " + std::to_string(number) + ", " + plan.keys[i]));
    plan.cases.push_back(std::move(values));
    if (plan.cases.size() > kMaxCases) throw std::invalid_argument("more cases than a sweep takes");
  }
  if (plan.keys.empty() || plan.cases.empty())
    throw std::invalid_argument("needs a header of keys and at least one row of values");
  return plan;
}

namespace {

// `base` with the case's values set; ConfigError when a key's section is not a map.
YAML::Node caseTree(const YAML::Node& base, const SweepPlan& plan, size_t index) {
  YAML::Node root = YAML::Clone(base);
  for (size_t k = 0; k < plan.keys.size(); ++k) {
    const std::vector<std::string> parts = split(plan.keys[k], '.');
    setConfigValue(root, parts[0], parts[1], YAML::Node(plan.cases[index][k]));
  }
  return root;
}

}  // namespace

namespace {
constexpr const char* kNotAKey = "is not a config key the simulation reads (a typo?)";
bool isParameter(const std::string& key) {
  const std::vector<std::string> parts = split(key, '.');
  // "section.key" exactly ('' or 'nosuch' once read past the end of `parts`).
  return parts.size() == 2 && findParameter(parts[0], parts[1]) != nullptr;
}
}  // namespace

Config sweepCaseConfig(const YAML::Node& base, const SweepPlan& plan, size_t index) {
  for (const std::string& key : plan.keys)
    if (!isParameter(key)) throw ConfigError(key, kNotAKey);
  return loadSimulationConfig(caseTree(base, plan, index)).config;
}

SweepCaseConfigs::SweepCaseConfigs(const YAML::Node& base, const SweepPlan& plan) : plan_(plan) {
  for (const std::string& key : plan.keys) {
    const std::vector<std::string> parts = split(key, '.');
    const ParameterSpec* spec = parts.size() == 2 ? findParameter(parts[0], parts[1]) : nullptr;
    if (!spec || !takenDirectly(*spec)) return;  // the loader's path, case by case
    specs_.push_back(spec);
  }
  try {
    base_ = loadSimulationConfig(YAML::Clone(base)).config;
  } catch (const std::exception&) {
    return;  // a base the loader refuses: each case says so, as before
  }
  inertia_from_mass_ = inertiaFollowsMass(base);
  direct_ = !specs_.empty();
}

Config SweepCaseConfigs::at(const YAML::Node& own_base, size_t index) const {
  if (!direct_) return sweepCaseConfig(own_base, plan_, index);
  return configWithNumbers(base_, inertia_from_mass_, specs_, plan_.cases[index].data());
}

void checkSweepKeys(const SweepPlan& plan) {
  for (const std::string& key : plan.keys)
    if (!isParameter(key)) throw std::invalid_argument("sweep key '" + key + "' " + kNotAKey);
}

}  // namespace kane_sim
