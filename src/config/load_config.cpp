#include "kane_sim/config/load_config.h"

#include <algorithm>

#include "kane_sim/config/frame_names.h"
#include "kane_sim/config/input_file.h"
#include "kane_sim/config/parameter_schema.h"
#include "kane_sim/format_number.h"
#include "kane_sim/model/mechanism_laws.h"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace kane_sim {
namespace {

// The documented ranges; every check is written so that NaN fails it.
// At most this many physics steps per publish: a `step` service call (one publish period) then
// stays well under a second of work.
constexpr double kMaxStepsPerPublish = 1e5;

// The keys of a map, each a plain name and each once (yaml-cpp would keep one of two
// duplicates silently).
void checkKeys(const YAML::Node& map, const std::string& path) {
  std::set<std::string> seen;
  for (const auto& entry : map) {
    const std::string where = path.empty() ? "<root>" : path;
    if (!entry.first.IsScalar())
      throw ConfigError(where, "has a key that is not a plain name (" +
                                   std::string(entry.first.IsMap() ? "a map" : "a list") + ")");
    const std::string key = entry.first.Scalar();
    if (!seen.insert(key).second)
      throw ConfigError(path.empty() ? key : path + "." + key,
                        "appears twice: keep one (the loader would otherwise ignore one)");
  }
}

std::string describe(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Scalar:
      return "'" + node.Scalar() + "'";
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Map:
      return "a map";
    case YAML::NodeType::Null:
      return "null";
    default:
      return "nothing";
  }
}

// Reads one map section, remembering which keys it consumed so the rest can be reported.
class Section {
 public:
  Section(const YAML::Node& parent, const std::string& name, bool required,
          std::vector<std::string>* unknown_keys)
      : path_(name), unknown_keys_(unknown_keys) {
    // yaml-cpp's lookup of a missing key gives an invalid node that must not be stored.
    const YAML::Node child = parent[name];
    // An optional section whose keys are all commented out is null: an empty map.
    if (!child || (child.IsNull() && !required)) {
      if (required) throw ConfigError(name, "is missing (a map of parameters is required)");
      return;
    }
    if (!child.IsMap()) throw ConfigError(name, "must be a map, got " + describe(child));
    checkKeys(child, name);
    node_.reset(child);
    present_ = true;
  }

  // A required number: present, numeric, finite.
  double number(const std::string& key) {
    const YAML::Node value = fetch(key);
    if (!value) throw ConfigError(keyPath(key), "is missing");
    return toNumber(key, value);
  }
  // Optional: keeps *out when absent; true when present.
  bool number(const std::string& key, double* out) {
    const YAML::Node value = fetch(key);
    if (value) *out = toNumber(key, value);
    return static_cast<bool>(value);
  }
  void boolean(const std::string& key, bool* out) {
    const YAML::Node value = fetch(key);
    if (!value) return;
    bool parsed = false;
    if (!value.IsScalar() || !YAML::convert<bool>::decode(value, parsed))
      throw ConfigError(keyPath(key), "must be true or false, got " + describe(value));
    *out = parsed;
  }
  bool text(const std::string& key, std::string* out) {  // as number()
    const YAML::Node value = fetch(key);
    if (!value) return false;
    if (value.IsNull()) {
      *out = "";
      return true;
    }
    if (!value.IsScalar())
      throw ConfigError(keyPath(key), "must be a string, got " + describe(value));
    *out = value.Scalar();
    return true;
  }

  void collectUnknownKeys() const {
    if (!present_) return;
    for (const auto& entry : node_) {
      const std::string key = entry.first.Scalar();
      if (!used_.count(key)) unknown_keys_->push_back(keyPath(key));
    }
  }

  std::string keyPath(const std::string& key) const { return path_ + "." + key; }
  const std::string& name() const { return path_; }

 private:
  YAML::Node fetch(const std::string& key) {
    used_.insert(key);
    if (!present_) return YAML::Node(YAML::NodeType::Undefined);
    const YAML::Node& section = node_;
    return section[key];
  }

  double toNumber(const std::string& key, const YAML::Node& value) const {
    double parsed = 0.0;
    if (!value.IsScalar() || !YAML::convert<double>::decode(value, parsed))
      throw ConfigError(keyPath(key), "must be a number, got " + describe(value));
    if (!std::isfinite(parsed))
      throw ConfigError(keyPath(key), "must be finite, got " + describe(value));
    return parsed;
  }

  YAML::Node node_;
  bool present_ = false;
  std::string path_;
  std::set<std::string> used_;
  std::vector<std::string>* unknown_keys_;
};

void requirePositive(const std::string& key, double value) {
  if (!(value > 0.0)) throw ConfigError(key, "must be > 0, got " + formatNumber(value));
}
void requireNonNegative(const std::string& key, double value) {
  if (!(value >= 0.0)) throw ConfigError(key, "must be >= 0, got " + formatNumber(value));
}

// lo <= value <= hi, written so that NaN fails.
void requireRange(const std::string& key, double value, double lo, double hi,
                  const std::string& unit) {
  if (!(value >= lo && value <= hi))
    throw ConfigError(key, "must be in [" + formatNumber(lo) + ", " + formatNumber(hi) + "]" +
                               (unit.empty() ? "" : " " + unit) + ", got " + formatNumber(value));
}

void requireFrameName(const std::string& key, const std::string& name, bool allow_empty) {
  if (name.empty() && !allow_empty) throw ConfigError(key, "must not be empty");
  for (char c : name) {
    const bool ok = std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '/';
    if (!ok)
      throw ConfigError(key, "must hold only letters, digits, '_' and '/', got '" + name + "'");
  }
  if (!name.empty() && name.front() == '/')
    throw ConfigError(key,
                      "must not start with '/' (tf2 frame ids are relative), got '" + name + "'");
}

// The index of `name` among a choice's names; ConfigError listing them otherwise.
int choiceIndex(const ParameterSpec& p, const std::string& name, const std::string& key) {
  for (std::size_t i = 0; i < p.choices.size(); ++i)
    if (name == p.choices[i]) return static_cast<int>(i);
  std::string valid;
  for (const std::string& c : p.choices) valid += (valid.empty() ? "" : ", ") + c;
  throw ConfigError(
      key, "names " + std::string(p.choice_noun) + " '" + name + "' (valid: " + valid + ")");
}

// One parameter of the schema: read when present (or required), then its own rule. Defaults are
// the Config's initializers and are not checked here (a test holds them to the rules).
void readParameter(Section& s, const ParameterSpec& p, Config* config) {
  const std::string key = s.keyPath(p.key);
  const ValueRule& rule = p.rule;
  const ConfigField& f = p.field;
  if (f.flag) {
    s.boolean(p.key, &f.flag(*config));
    return;
  }
  if (f.text || f.get_choice) {
    std::string text = f.text ? f.text(*config) : p.choices.at(f.get_choice(*config));
    if (!s.text(p.key, &text)) return;
    if (f.text) {
      requireFrameName(key, text, rule.kind == ValueRule::kAnyName);
      f.text(*config) = text;
      return;
    }
    f.set_choice(*config, choiceIndex(p, text, key));
    return;
  }
  double value = f.whole ? f.whole(*config) : f.number(*config);
  if (p.required)
    value = s.number(p.key);
  else if (!s.number(p.key, &value))
    return;
  storeNumber(key, p, value, config);
}

}  // namespace

void storeNumber(const std::string& key, const ParameterSpec& p, double value, Config* config) {
  const ValueRule& rule = p.rule;
  const ConfigField& f = p.field;
  if (!std::isfinite(value))  // in the file's words, as Section::toNumber says it of YAML
    throw ConfigError(key, std::string("must be finite, got '") +
                               (std::isnan(value) ? ".nan"
                                : value > 0       ? ".inf"
                                                  : "-.inf") +
                               "'");
  switch (rule.kind) {
    case ValueRule::kPositive:
      requirePositive(key, value);
      break;
    case ValueRule::kNonNegative:
      requireNonNegative(key, value);
      break;
    case ValueRule::kRange:
    case ValueRule::kWholeRange:
      requireRange(key, value, rule.lo, rule.hi, rule.range_note);
      break;
    case ValueRule::kZeroOrRange:
      if (value != 0.0) requireRange(key, value, rule.lo, rule.hi, rule.range_note);
      break;
    default:  // kFinite: Section::number checked it
      break;
  }
  if (f.whole) {
    if (value != std::floor(value))
      throw ConfigError(key, "must be a whole number" +
                                 (*p.unit ? " of " + std::string(p.unit) : std::string()) +
                                 ", got " + formatNumber(value));
    f.whole(*config) = static_cast<int>(value);
  } else {
    f.number(*config) = value;
  }
}

namespace {

// The rules that tie parameters of a section together, after its own rules.
void checkMechanism(const Section& s, MechanismParameters* p) {
  if (std::isnan(p->rod_inertia)) {
    // The default follows from m and L: name them when it cannot be represented.
    p->rod_inertia = slenderRodInertia(p->rod_mass, p->rod_half_length);
    if (!(p->rod_inertia > 0.0 && std::isfinite(p->rod_inertia)))
      throw ConfigError(s.keyPath("rod_half_length"),
                        "and mechanism.rod_mass give a rod inertia m (2L)^2/12 of " +
                            formatNumber(p->rod_inertia) +
                            " kg m^2, which is not a usable positive "
                            "number (rod_mass " +
                            formatNumber(p->rod_mass) + ", rod_half_length " +
                            formatNumber(p->rod_half_length) + ")");
  }
}

void checkSimulation(const Section& s, const SimulationSettings& sim) {
  requireRange(s.keyPath("publish_rate"), sim.publish_rate, sim.physics_rate / kMaxStepsPerPublish,
               sim.physics_rate, "Hz");
  if (wholeStepsPerPeriod(sim.physics_rate, sim.publish_rate) == 0.0)
    throw ConfigError(s.keyPath("publish_rate"),
                      "must divide simulation.physics_rate (" + formatNumber(sim.physics_rate) +
                          " Hz) into a whole number of physics steps, got " +
                          formatNumber(sim.publish_rate));
}

void checkSensors(const Section& s, const Config& config, std::vector<std::string>* warnings) {
  const SensorSettings& sensors = config.sensors;
  const SimulationSettings& sim = config.simulation;
  if (sensors.rate != 0.0) {  // 0: publish_rate's, checked above
    requireRange(s.keyPath("rate"), sensors.rate, sim.physics_rate / kMaxStepsPerPublish,
                 sim.physics_rate, "Hz (0 = simulation.publish_rate)");
    if (wholeStepsPerPeriod(sim.physics_rate, sensors.rate) == 0.0)
      throw ConfigError(s.keyPath("rate"), "must divide simulation.physics_rate (" +
                                               formatNumber(sim.physics_rate) +
                                               " Hz) into a whole number of physics steps, got " +
                                               formatNumber(sensors.rate));
  }
  const double rate = sensors.rate > 0 ? sensors.rate : sim.publish_rate;
  const double in_flight = (sensors.latency + sensors.latency_jitter) * rate;
  if (in_flight > kMaxReadingsInFlight)
    throw ConfigError(s.keyPath("latency"),
                      formatNumber(sensors.latency) + " s (+ latency_jitter " +
                          formatNumber(sensors.latency_jitter) + " s) at " + formatNumber(rate) +
                          " readings per second keeps " +
                          std::to_string(std::llround(std::min(in_flight, 1e18))) +
                          " readings in flight, more than " +
                          std::to_string(std::llround(kMaxReadingsInFlight)) +
                          ": lower sensors.latency, latency_jitter or rate");
  // Readings never overtake one another: a jitter longer than the reading period makes many
  // arrive at the same tick, under one stamp with different values.
  if (sensors.enabled && sensors.latency_jitter * rate > 1.0)
    warnings->push_back(s.keyPath("latency_jitter") + " " + formatNumber(sensors.latency_jitter) +
                        " s is longer than the reading " + "period " + formatNumber(1.0 / rate) +
                        " s: readings bunch up and several arrive under one stamp; keep the "
                        "jitter below the period");
}

// The estimator's restart gap against the readings it will see (the sensors' rate).
void checkEstimator(const Config& config, std::vector<std::string>* warnings) {
  const double rate = sensorReadingRate(config);
  if (rate > 0.0 && config.estimator.restart_gap * rate < 2.0)
    warnings->push_back("estimator.restart_gap " + formatNumber(config.estimator.restart_gap) +
                        " s is shorter than two sensor readings (" + formatNumber(2.0 / rate) +
                        " s): the estimator would restart at almost every reading");
}

void checkFrames(const Section& s, const FrameSettings& f) {
  // world is the parent of the mechanism's frames: naming it like one of them makes a loop.
  const FrameNames names(f);
  std::vector<std::string> own(names.bodies.begin(), names.bodies.end());
  own.push_back(names.mechanism);
  if (std::find(own.begin(), own.end(), f.world) != own.end())
    throw ConfigError(s.keyPath("world"), "'" + f.world +
                                              "' is one of the mechanism's own frames (a tf "
                                              "loop); name the fixed world frame, e.g. 'world'");
}

}  // namespace

ConfigError::ConfigError(const std::string& key, const std::string& problem)
    : std::runtime_error(key == "file" ? "config file: " + problem
                                       : "config key '" + key + "' " + problem),
      key_(key) {}

void setConfigValue(YAML::Node& root, const std::string& section, const std::string& key,
                    const YAML::Node& value) {
  if (!root.IsMap()) throw ConfigError("<root>", "must be a map with sections mechanism, ...");
  YAML::Node node = root[section];
  if (!node || node.IsNull()) root[section] = YAML::Node(YAML::NodeType::Map);
  if (!root[section].IsMap())
    throw ConfigError(section + "." + key, "cannot be set: '" + section + "' is not a section");
  root[section][key] = value;
}

IntegratorType parseIntegratorName(const std::string& name, const std::string& key) {
  return static_cast<IntegratorType>(
      choiceIndex(*findParameter("simulation", "integrator"), name, key));
}

EquationsSource parseEquationsName(const std::string& name, const std::string& key) {
  return static_cast<EquationsSource>(
      choiceIndex(*findParameter("simulation", "equations"), name, key));
}

LoadedConfig loadConfig(const YAML::Node& root) {
  if (!root || !root.IsMap())
    throw ConfigError("<root>", "must be a map with sections mechanism, initial_state, ...");
  checkKeys(root, "");
  LoadedConfig loaded;
  std::vector<std::string>* unknown = &loaded.unknown_keys;
  Config& config = loaded.config;

  // Section by section in the file's order: each parameter with its own rule, then the rules
  // that tie a section's parameters together.
  std::vector<Section> sections;
  for (const SectionSpec& spec : configSections()) {
    sections.emplace_back(root, spec.name, spec.required, unknown);
    Section& s = sections.back();
    for (const ParameterSpec& p : parameterSchema())
      if (s.name() == p.section) readParameter(s, p, &config);
    if (s.name() == "mechanism") checkMechanism(s, &config.mechanism);
    if (s.name() == "simulation") checkSimulation(s, config.simulation);
    if (s.name() == "frames") checkFrames(s, config.frames);
    if (s.name() == "sensors") checkSensors(s, config, &loaded.warnings);
    if (s.name() == "estimator") checkEstimator(config, &loaded.warnings);
  }
  config.mechanism.motor.torque_limit = config.command.torque_limit;  // the line's stall torque

  for (const auto& entry : root) {
    const std::string key = entry.first.Scalar();
    const auto known = [&key](const SectionSpec& spec) { return key == spec.name; };
    if (std::none_of(configSections().begin(), configSections().end(), known))
      unknown->push_back(key);
  }
  for (const Section& s : sections) s.collectUnknownKeys();
  for (const std::string& key : loaded.unknown_keys) {
    std::string warning = "unknown config key '" + key + "' is ignored";
    // A misspelt uncertainty leaves its parameter taken as exact: say which keys there are.
    if (key.rfind("uncertainty.", 0) == 0) {
      warning += ": the uncertainty: section has a row for each parameter identify fits (";
      const char* separator = "";
      for (const ParameterSpec& p : parameterSchema())
        if (std::string(p.section) == "uncertainty") {
          warning += separator + std::string(p.key);
          separator = ", ";
        }
      warning += ")";
    }
    loaded.warnings.push_back(warning);
  }
  return loaded;
}

namespace {

// YAML's merge key, as PyYAML (and so rosparam) reads it: `<<: *anchor` (or a list of them) puts
// the anchored map's entries into this map where it has no entry of its own. yaml-cpp keeps "<<"
// as a plain key, which would make the node and the offline tools read one file as two configs.
bool isMergeKey(const YAML::Node& key) {
  return key.IsScalar() && key.Scalar() == "<<" && key.Tag() != "!";  // not the quoted "<<"
}

// A config has ~100 nodes; aliases of aliases can make a few lines stand for billions (each
// alias is walked again), so the walk gives up past this many.
constexpr long kMaxYamlNodes = 100000;

// A config is two levels deep (section, key); an alias that contains itself is infinitely deep.
constexpr int kMaxYamlDepth = 64;

// Whether `node` holds a merge key anywhere; counts the nodes walked in `walked` and throws
// ConfigError past kMaxYamlNodes or kMaxYamlDepth.
bool hasMergeKey(const YAML::Node& node, long* walked, int depth = 0) {
  if (++*walked > kMaxYamlNodes)
    throw ConfigError("file", "holds more than " + std::to_string(kMaxYamlNodes) +
                                  " YAML nodes once its aliases are expanded (a config has about "
                                  "a hundred): aliases of aliases?");
  if (depth > kMaxYamlDepth)
    throw ConfigError(
        "file", "nests deeper than " + std::to_string(kMaxYamlDepth) +
                    " levels once its aliases are expanded (a config has two): an alias inside "
                    "its own anchor, or anchors nested in anchors?");
  if (node.IsSequence()) {
    bool found = false;
    for (const YAML::Node& item : node) found = hasMergeKey(item, walked, depth + 1) || found;
    return found;
  }
  if (!node.IsMap()) return false;
  bool found = false;
  for (const auto& entry : node)  // the whole tree: its size is what is bounded
    found = hasMergeKey(entry.second, walked, depth + 1) || isMergeKey(entry.first) || found;
  return found;
}
// Duplicate keys are kept (force_insert) for the loader to name.
YAML::Node expandMergeKeys(const YAML::Node& node) {
  if (node.IsSequence()) {
    YAML::Node out(YAML::NodeType::Sequence);
    for (const YAML::Node& item : node) out.push_back(expandMergeKeys(item));
    return out;
  }
  if (!node.IsMap()) return YAML::Clone(node);
  YAML::Node out(YAML::NodeType::Map);
  YAML::Node merged;
  bool has_merge = false;
  for (const auto& entry : node) {
    if (isMergeKey(entry.first)) {
      merged.reset(entry.second);
      has_merge = true;
    } else {
      out.force_insert(YAML::Clone(entry.first), expandMergeKeys(entry.second));
    }
  }
  if (!has_merge) return out;
  std::vector<YAML::Node> sources;
  if (merged.IsSequence())
    for (const YAML::Node& item : merged) sources.push_back(item);
  else
    sources.push_back(merged);
  for (const YAML::Node& source : sources) {
    if (!source.IsMap())
      throw ConfigError(
          "file", "a merge key '<<' must name a map (or a list of maps), got " + describe(source));
    const YAML::Node& own = out;                       // const: looking a key up adds nothing
    for (const auto& entry : expandMergeKeys(source))  // earlier sources win, as in PyYAML
      if (!own[entry.first.Scalar()]) out.force_insert(entry.first, entry.second);
  }
  return out;
}

}  // namespace

namespace {

// One config document from a stream; `name` says where it came from in every message (a file's
// path, or what the browser's page calls its text).
YAML::Node parseYamlDocument(std::istream& in, const std::string& name) {
  std::vector<YAML::Node> documents;
  try {
    documents = YAML::LoadAll(in);
  } catch (const YAML::Exception& e) {
    // yaml-cpp says only "bad file" when it stops at its nesting limit.
    if (e.msg == "bad file")
      throw ConfigError("file", "'" + name + "' is nested too deeply at line " +
                                    std::to_string(e.mark.line + 1) + ", column " +
                                    std::to_string(e.mark.column + 1) +
                                    " (a config needs two levels: section, key)");
    throw ConfigError("file", "'" + name + "' is not valid YAML: " + e.what());
  } catch (const std::exception& e) {  // I/O errors and the like
    throw ConfigError("file", "'" + name + "' cannot be read as YAML: " + e.what());
  }
  if (documents.size() > 1)
    throw ConfigError("file", "'" + name + "' holds " + std::to_string(documents.size()) +
                                  " YAML documents; a config is one document (no '---' between "
                                  "sections)");
  if (documents.empty()) return YAML::Node();
  long walked = 0;  // expandMergeKeys walks no more nodes than this check did
  return hasMergeKey(documents.front(), &walked) ? expandMergeKeys(documents.front())
                                                 : documents.front();
}

}  // namespace

YAML::Node loadYamlFile(const std::string& path) {
  std::ifstream file;
  try {
    file = openInputFile(path, "config", kMaxConfigBytes);
  } catch (const std::invalid_argument& e) {
    throw ConfigError("file", e.what());
  }
  return parseYamlDocument(file, path);
}

YAML::Node loadYamlText(const std::string& text, const std::string& name) {
  if (text.size() > kMaxConfigBytes)
    throw ConfigError("file", "'" + name + "' is " + std::to_string(text.size()) +
                                  " bytes; a config is at most " + std::to_string(kMaxConfigBytes) +
                                  " bytes");
  std::istringstream in(text);
  return parseYamlDocument(in, name);
}

LoadedConfig loadConfigFile(const std::string& path) { return loadConfig(loadYamlFile(path)); }

std::string defaultConfigFile() {
  std::error_code error;
  for (const char* path : {KANE_SIM_INSTALLED_CONFIG, KANE_SIM_SOURCE_CONFIG})
    if (std::filesystem::is_regular_file(path, error)) return path;
  throw ConfigError("file", std::string("the default config is in neither ") +
                                KANE_SIM_INSTALLED_CONFIG + " nor " + KANE_SIM_SOURCE_CONFIG +
                                "; name one with --config");
}

}  // namespace kane_sim
