#include "kane_sim/config/load_config.h"

#include <cctype>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace kane_sim {
namespace {

constexpr double kMaxPhysicsRate = 1e6;  // [Hz]; beyond this a step is below double's useful dt

std::string formatValue(double value) {
  std::ostringstream out;
  out.precision(17);
  out << value;
  return out.str();
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
          std::vector<std::string>* warnings)
      : path_(name), warnings_(warnings) {
    // yaml-cpp's lookup of a missing key gives an invalid node that must not be stored.
    const YAML::Node child = parent[name];
    if (!child) {
      if (required) throw ConfigError(name, "is missing (a map of parameters is required)");
      return;
    }
    if (!child.IsMap()) throw ConfigError(name, "must be a map, got " + describe(child));
    node_.reset(child);
    present_ = true;
  }

  // A required number: present, numeric, finite.
  double number(const std::string& key) {
    const YAML::Node value = fetch(key);
    if (!value) throw ConfigError(keyPath(key), "is missing");
    return toNumber(key, value);
  }
  void number(const std::string& key, double* out) {  // optional: keeps *out when absent
    const YAML::Node value = fetch(key);
    if (value) *out = toNumber(key, value);
  }
  void boolean(const std::string& key, bool* out) {
    const YAML::Node value = fetch(key);
    if (!value) return;
    bool parsed = false;
    if (!value.IsScalar() || !YAML::convert<bool>::decode(value, parsed))
      throw ConfigError(keyPath(key), "must be true or false, got " + describe(value));
    *out = parsed;
  }
  void text(const std::string& key, std::string* out) {
    const YAML::Node value = fetch(key);
    if (!value) return;
    if (value.IsNull()) {
      *out = "";
      return;
    }
    if (!value.IsScalar())
      throw ConfigError(keyPath(key), "must be a string, got " + describe(value));
    *out = value.Scalar();
  }

  void warnAboutUnknownKeys() const {
    if (!present_) return;
    for (const auto& entry : node_) {
      const std::string key = entry.first.as<std::string>();
      if (!used_.count(key))
        warnings_->push_back("unknown config key '" + keyPath(key) + "' is ignored");
    }
  }

  std::string keyPath(const std::string& key) const { return path_ + "." + key; }

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
  std::vector<std::string>* warnings_;
};

void requirePositive(const std::string& key, double value) {
  if (!(value > 0.0)) throw ConfigError(key, "must be > 0, got " + formatValue(value));
}
void requireNonNegative(const std::string& key, double value) {
  if (!(value >= 0.0)) throw ConfigError(key, "must be >= 0, got " + formatValue(value));
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

void readMechanism(Section& s, MechanismParameters* p) {
  p->rod_mass = s.number("rod_mass");
  p->rod_half_length = s.number("rod_half_length");
  p->slider3_mass = s.number("slider3_mass");
  p->slider4_mass = s.number("slider4_mass");
  p->spring_stiffness = s.number("spring_stiffness");
  p->gravity = s.number("gravity");
  p->rod_inertia = MechanismParameters::slenderRodInertia(p->rod_mass, p->rod_half_length);
  s.number("rod_inertia", &p->rod_inertia);

  requirePositive(s.keyPath("rod_mass"), p->rod_mass);
  requirePositive(s.keyPath("rod_half_length"), p->rod_half_length);
  requirePositive(s.keyPath("slider3_mass"), p->slider3_mass);
  requirePositive(s.keyPath("slider4_mass"), p->slider4_mass);
  requireNonNegative(s.keyPath("spring_stiffness"), p->spring_stiffness);
  requirePositive(s.keyPath("rod_inertia"), p->rod_inertia);
}

void readInitialState(Section& s, State* x) {
  x->q1 = s.number("q1");
  x->q2 = s.number("q2");
  x->u1 = s.number("u1");
  x->u2 = s.number("u2");
}

void readSimulation(Section& s, SimulationSettings* sim) {
  s.number("physics_rate", &sim->physics_rate);
  std::string integrator = integratorName(sim->integrator);
  s.text("integrator", &integrator);
  sim->integrator = parseIntegratorName(integrator, s.keyPath("integrator"));
  s.number("absolute_tolerance", &sim->absolute_tolerance);
  s.number("relative_tolerance", &sim->relative_tolerance);
  s.number("publish_rate", &sim->publish_rate);
  s.number("real_time_factor", &sim->real_time_factor);
  s.boolean("publish_clock", &sim->publish_clock);
  s.boolean("start_paused", &sim->start_paused);

  requirePositive(s.keyPath("physics_rate"), sim->physics_rate);
  if (sim->physics_rate > kMaxPhysicsRate)
    throw ConfigError(s.keyPath("physics_rate"), "must be <= " + formatValue(kMaxPhysicsRate) +
                                                     " Hz, got " + formatValue(sim->physics_rate));
  requirePositive(s.keyPath("absolute_tolerance"), sim->absolute_tolerance);
  requirePositive(s.keyPath("relative_tolerance"), sim->relative_tolerance);
  requirePositive(s.keyPath("publish_rate"), sim->publish_rate);
  if (sim->publish_rate > sim->physics_rate)
    throw ConfigError(s.keyPath("publish_rate"), "must be <= simulation.physics_rate (" +
                                                     formatValue(sim->physics_rate) + " Hz), got " +
                                                     formatValue(sim->publish_rate));
  const double ticks_per_publish = sim->physics_rate / sim->publish_rate;
  if (std::abs(ticks_per_publish - std::round(ticks_per_publish)) > 1e-9 * ticks_per_publish)
    throw ConfigError(s.keyPath("publish_rate"),
                      "must divide simulation.physics_rate (" + formatValue(sim->physics_rate) +
                          " Hz) into a whole number of physics steps, got " +
                          formatValue(sim->publish_rate));
  requireNonNegative(s.keyPath("real_time_factor"), sim->real_time_factor);
}

void readCommand(Section& s, CommandSettings* c) {
  s.number("torque_limit", &c->torque_limit);
  s.number("timeout", &c->timeout);
  requireNonNegative(s.keyPath("torque_limit"), c->torque_limit);
  requireNonNegative(s.keyPath("timeout"), c->timeout);
}

void readFrames(Section& s, FrameSettings* f) {
  s.text("prefix", &f->prefix);
  s.text("world", &f->world);
  s.number("pivot_height", &f->pivot_height);
  requireFrameName(s.keyPath("prefix"), f->prefix, true);
  requireFrameName(s.keyPath("world"), f->world, false);
}

}  // namespace

ConfigError::ConfigError(const std::string& key, const std::string& problem)
    : std::runtime_error("config key '" + key + "' " + problem), key_(key) {}

IntegratorType parseIntegratorName(const std::string& name, const std::string& key) {
  for (IntegratorType type : {IntegratorType::kRk4, IntegratorType::kDopri5})
    if (name == integratorName(type)) return type;
  throw ConfigError(key, "names an unknown integrator '" + name + "' (valid: rk4, dopri5)");
}

LoadedConfig loadConfig(const YAML::Node& root) {
  if (!root || !root.IsMap())
    throw ConfigError("<root>", "must be a map with sections mechanism, initial_state, ...");
  LoadedConfig loaded;
  std::vector<std::string>* warnings = &loaded.warnings;
  Config& config = loaded.config;

  Section mechanism(root, "mechanism", true, warnings);
  readMechanism(mechanism, &config.mechanism);
  Section initial_state(root, "initial_state", true, warnings);
  readInitialState(initial_state, &config.initial_state);
  Section simulation(root, "simulation", false, warnings);
  readSimulation(simulation, &config.simulation);
  Section command(root, "command", false, warnings);
  readCommand(command, &config.command);
  Section frames(root, "frames", false, warnings);
  readFrames(frames, &config.frames);

  const std::set<std::string> sections = {"mechanism", "initial_state", "simulation", "command",
                                          "frames"};
  for (const auto& entry : root) {
    const std::string key = entry.first.as<std::string>();
    if (!sections.count(key)) warnings->push_back("unknown config key '" + key + "' is ignored");
  }
  for (const Section* s : {&mechanism, &initial_state, &simulation, &command, &frames})
    s->warnAboutUnknownKeys();
  return loaded;
}

LoadedConfig loadConfigFile(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw ConfigError("file", "cannot open '" + path + "'");
  YAML::Node root;
  try {
    root = YAML::Load(file);
  } catch (const YAML::Exception& e) {
    throw ConfigError("file", "'" + path + "' is not valid YAML: " + e.what());
  }
  return loadConfig(root);
}

}  // namespace kane_sim
