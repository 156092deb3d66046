#include "kane_sim/config/load_config.h"

#include "kane_sim/analysis/stability.h"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

namespace kane_sim {
namespace {

// The documented ranges; every check is written so that NaN fails it.
constexpr double kMinPhysicsRate = 1.0;  // [Hz]; a slower "physics step" is not a simulation
constexpr double kMaxPhysicsRate = 1e6;  // [Hz]; beyond this a step is below double's useful dt
// At most this many physics steps per publish: a `step` service call (one publish period) then
// stays well under a second of work.
constexpr double kMaxStepsPerPublish = 1e5;
constexpr double kMinRealTimeFactor = 1e-3;  // besides 0 (free-running)
constexpr double kMaxRealTimeFactor = 1e6;

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

  void collectUnknownKeys() const {
    if (!present_) return;
    for (const auto& entry : node_) {
      const std::string key = entry.first.Scalar();
      if (!used_.count(key)) unknown_keys_->push_back(keyPath(key));
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
  std::vector<std::string>* unknown_keys_;
};

void requirePositive(const std::string& key, double value) {
  if (!(value > 0.0)) throw ConfigError(key, "must be > 0, got " + formatValue(value));
}
void requireNonNegative(const std::string& key, double value) {
  if (!(value >= 0.0)) throw ConfigError(key, "must be >= 0, got " + formatValue(value));
}

// lo <= value <= hi, written so that NaN fails.
void requireRange(const std::string& key, double value, double lo, double hi,
                  const std::string& unit) {
  if (!(value >= lo && value <= hi))
    throw ConfigError(key, "must be in [" + formatValue(lo) + ", " + formatValue(hi) + "] " + unit +
                               ", got " + formatValue(value));
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
  requirePositive(s.keyPath("rod_mass"), p->rod_mass);
  requirePositive(s.keyPath("rod_half_length"), p->rod_half_length);
  requirePositive(s.keyPath("slider3_mass"), p->slider3_mass);
  requirePositive(s.keyPath("slider4_mass"), p->slider4_mass);
  requireNonNegative(s.keyPath("spring_stiffness"), p->spring_stiffness);

  p->rod_inertia = MechanismParameters::kUnset;  // stays NaN without a rod_inertia key
  s.number("rod_inertia", &p->rod_inertia);
  if (std::isnan(p->rod_inertia)) {
    // The default follows from m and L: name them when it cannot be represented.
    p->rod_inertia = MechanismParameters::slenderRodInertia(p->rod_mass, p->rod_half_length);
    if (!(p->rod_inertia > 0.0 && std::isfinite(p->rod_inertia)))
      throw ConfigError(s.keyPath("rod_half_length"),
                        "and mechanism.rod_mass give a rod inertia m (2L)^2/12 of " +
                            formatValue(p->rod_inertia) +
                            " kg m^2, which is not a usable positive "
                            "number (rod_mass " +
                            formatValue(p->rod_mass) + ", rod_half_length " +
                            formatValue(p->rod_half_length) + ")");
  }
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
  std::string equations = equationsName(sim->equations);
  s.text("equations", &equations);
  sim->equations = parseEquationsName(equations, s.keyPath("equations"));
  s.number("absolute_tolerance", &sim->absolute_tolerance);
  s.number("relative_tolerance", &sim->relative_tolerance);
  s.number("publish_rate", &sim->publish_rate);
  s.number("real_time_factor", &sim->real_time_factor);
  s.boolean("publish_clock", &sim->publish_clock);
  s.boolean("start_paused", &sim->start_paused);

  requireRange(s.keyPath("physics_rate"), sim->physics_rate, kMinPhysicsRate, kMaxPhysicsRate,
               "Hz");
  requirePositive(s.keyPath("absolute_tolerance"), sim->absolute_tolerance);
  requirePositive(s.keyPath("relative_tolerance"), sim->relative_tolerance);
  requireRange(s.keyPath("publish_rate"), sim->publish_rate,
               sim->physics_rate / kMaxStepsPerPublish, sim->physics_rate, "Hz");
  const double ticks_per_publish = sim->physics_rate / sim->publish_rate;
  if (std::abs(ticks_per_publish - std::round(ticks_per_publish)) > 1e-9 * ticks_per_publish)
    throw ConfigError(s.keyPath("publish_rate"),
                      "must divide simulation.physics_rate (" + formatValue(sim->physics_rate) +
                          " Hz) into a whole number of physics steps, got " +
                          formatValue(sim->publish_rate));
  if (sim->real_time_factor != 0.0)
    requireRange(s.keyPath("real_time_factor"), sim->real_time_factor, kMinRealTimeFactor,
                 kMaxRealTimeFactor, "(or 0 = as fast as possible)");
}

void readCommand(Section& s, CommandSettings* c, MotorLine* motor) {
  s.number("torque_limit", &c->torque_limit);
  s.number("timeout", &c->timeout);
  s.number("motor_no_load_speed", &motor->no_load_speed);
  requireNonNegative(s.keyPath("torque_limit"), c->torque_limit);
  requireNonNegative(s.keyPath("timeout"), c->timeout);
  requireNonNegative(s.keyPath("motor_no_load_speed"), motor->no_load_speed);
  motor->torque_limit = c->torque_limit;  // the line starts at the stall torque
}

// Keys as joint_states names the joints.
void readDamping(Section& s, JointDamping* d) {
  const std::pair<const char*, double*> keys[] = {{"crank_joint", &d->crank},
                                                  {"coupler_joint", &d->coupler},
                                                  {"slider3_joint", &d->slider3},
                                                  {"slider4_joint", &d->slider4}};
  for (const auto& [key, value] : keys) {
    s.number(key, value);
    requireNonNegative(s.keyPath(key), *value);
  }
}

void readContact(Section& s, SliderContact* c) {
  s.boolean("enabled", &c->enabled);
  s.number("gap", &c->gap);
  s.number("restitution", &c->restitution);
  requireNonNegative(s.keyPath("gap"), c->gap);
  requireRange(s.keyPath("restitution"), c->restitution, 0.0, 1.0, "(0 plastic, 1 elastic)");
}

void readFrames(Section& s, FrameSettings* f) {
  s.text("prefix", &f->prefix);
  s.text("world", &f->world);
  s.number("pivot_height", &f->pivot_height);
  s.boolean("publish_tf", &f->publish_tf);
  requireFrameName(s.keyPath("prefix"), f->prefix, true);
  requireFrameName(s.keyPath("world"), f->world, false);
  // world is the parent of the mechanism's frames: naming it like one of them makes a loop.
  std::string prefix = f->prefix;
  if (!prefix.empty() && prefix.back() != '/') prefix += '/';
  for (const char* own : {"mechanism", "rod1", "rod2", "slider3", "slider4"})
    if (f->world == prefix + own)
      throw ConfigError(s.keyPath("world"), "'" + f->world +
                                                "' is one of the mechanism's own frames (a tf "
                                                "loop); name the fixed world frame, e.g. 'world'");
}

void readDiagnostics(Section& s, DiagnosticsSettings* d) {
  double late_windows = d->late_windows;
  s.number("overrun_fraction", &d->overrun_fraction);
  s.number("late_windows", &late_windows);
  requireRange(s.keyPath("overrun_fraction"), d->overrun_fraction, 0.0, 1.0,
               "(a fraction of the ticks of a 1 s window)");
  requireRange(s.keyPath("late_windows"), late_windows, 1.0, 3600.0, "windows of 1 s");
  if (late_windows != std::floor(late_windows))
    throw ConfigError(s.keyPath("late_windows"),
                      "must be a whole number of windows, got " + formatValue(late_windows));
  d->late_windows = static_cast<int>(late_windows);
}

// The initial state must have a finite geometry and energy (1e308 is a finite number whose
// potential energy is not).
void checkInitialState(const Config& c) {
  const State& x = c.initial_state;
  const EnergyTerms e = mechanismModel(c).energy(x);
  if (!std::isfinite(e.total()))
    throw ConfigError("initial_state", "gives a non-finite energy (q1 " + formatValue(x.q1) +
                                           ", q2 " + formatValue(x.q2) + ", u1 " +
                                           formatValue(x.u1) + ", u2 " + formatValue(x.u2) +
                                           "): use values of the mechanism's size");
  const SliderContact& contact = c.mechanism.contact;
  const double separation =
      mechanismGeometry(c.mechanism.rod_half_length, x.q1, x.q2).sliderSeparation();
  if (contact.enabled && !(separation >= contact.gap))
    throw ConfigError("initial_state",
                      "puts slider 4 " + formatValue(separation) +
                          " m below slider 3 (x_C - x_B), closer than contact.gap " +
                          formatValue(contact.gap) +
                          " m: with contact enabled the sliders must start apart");
}

void checkIntegrable(const Config& c) {
  if (c.simulation.integrator != IntegratorType::kRk4) return;  // dopri5 adapts its step
  const double h = 1.0 / c.simulation.physics_rate;
  const MechanismModel model = mechanismModel(c);
  StiffestConfiguration stiffest = stiffestConfiguration(model, c.initial_state);
  // The initial speeds add their own (centripetal) rates.
  const double initial = fastestRate(model, c.initial_state, 0.0);
  if (!(initial <= stiffest.rate)) stiffest = {initial, c.initial_state.q1, c.initial_state.u1};
  if (!std::isfinite(stiffest.rate))
    throw ConfigError(
        "mechanism",
        "gives equations of motion that are not finite at q1 = " + formatValue(stiffest.q1) +
            " rad: the masses, lengths, stiffness and damping are too far apart "
            "for double precision (rod_mass " +
            formatValue(c.mechanism.rod_mass) + ", slider3_mass " +
            formatValue(c.mechanism.slider3_mass) + ", slider4_mass " +
            formatValue(c.mechanism.slider4_mass) + ", spring_stiffness " +
            formatValue(c.mechanism.spring_stiffness) + ")");
  if (!(stiffest.rate * h <= kRk4StabilityLimit))
    throw ConfigError(
        "simulation.physics_rate",
        "is too low for rk4 on this mechanism: its fastest rate (" + formatValue(stiffest.rate) +
            " 1/s at q1 = " + formatValue(stiffest.q1) + " rad, u1 = " + formatValue(stiffest.u1) +
            " rad/s, from spring_stiffness, the masses, damping and the motor line) needs rate h "
            "<= " +
            formatValue(kRk4StabilityLimit) + ", got " + formatValue(stiffest.rate * h) + " at " +
            formatValue(c.simulation.physics_rate) +
            " Hz; use simulation.integrator dopri5 or a physics_rate of at least " +
            formatValue(std::ceil(stiffest.rate / kRk4StabilityLimit)) + " Hz");
}

}  // namespace

ConfigError::ConfigError(const std::string& key, const std::string& problem)
    : std::runtime_error(key == "file" ? "config file: " + problem
                                       : "config key '" + key + "' " + problem),
      key_(key) {}

IntegratorType parseIntegratorName(const std::string& name, const std::string& key) {
  for (IntegratorType type : {IntegratorType::kRk4, IntegratorType::kDopri5})
    if (name == integratorName(type)) return type;
  throw ConfigError(key, "names an unknown integrator '" + name + "' (valid: rk4, dopri5)");
}

EquationsSource parseEquationsName(const std::string& name, const std::string& key) {
  for (EquationsSource source : {EquationsSource::kGenerated, EquationsSource::kGeneric})
    if (name == equationsName(source)) return source;
  throw ConfigError(key, "names unknown equations '" + name + "' (valid: generated, generic)");
}

LoadedConfig loadConfig(const YAML::Node& root) {
  if (!root || !root.IsMap())
    throw ConfigError("<root>", "must be a map with sections mechanism, initial_state, ...");
  checkKeys(root, "");
  LoadedConfig loaded;
  std::vector<std::string>* unknown = &loaded.unknown_keys;
  Config& config = loaded.config;

  Section mechanism(root, "mechanism", true, unknown);
  readMechanism(mechanism, &config.mechanism);
  Section initial_state(root, "initial_state", true, unknown);
  readInitialState(initial_state, &config.initial_state);
  Section simulation(root, "simulation", false, unknown);
  readSimulation(simulation, &config.simulation);
  Section command(root, "command", false, unknown);
  readCommand(command, &config.command, &config.mechanism.motor);
  Section frames(root, "frames", false, unknown);
  readFrames(frames, &config.frames);
  Section damping(root, "damping", false, unknown);
  readDamping(damping, &config.mechanism.damping);
  Section contact(root, "contact", false, unknown);
  readContact(contact, &config.mechanism.contact);
  Section diagnostics(root, "diagnostics", false, unknown);
  readDiagnostics(diagnostics, &config.diagnostics);

  const std::set<std::string> sections = {"mechanism", "initial_state", "simulation",
                                          "command",   "frames",        "damping",
                                          "contact",   "diagnostics"};
  for (const auto& entry : root) {
    const std::string key = entry.first.Scalar();
    if (!sections.count(key)) unknown->push_back(key);
  }
  for (const Section* s : {&mechanism, &initial_state, &simulation, &command, &frames, &damping,
                           &contact, &diagnostics})
    s->collectUnknownKeys();
  for (const std::string& key : loaded.unknown_keys)
    loaded.warnings.push_back("unknown config key '" + key + "' is ignored");
  checkInitialState(config);
  checkIntegrable(config);
  return loaded;
}

YAML::Node loadYamlFile(const std::string& path) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error))
    throw ConfigError("file", "cannot open '" + path + "' (not a readable file)");
  std::ifstream file(path);
  if (!file) throw ConfigError("file", "cannot open '" + path + "'");
  std::vector<YAML::Node> documents;
  try {
    documents = YAML::LoadAll(file);
  } catch (const YAML::Exception& e) {
    // yaml-cpp says only "bad file" when it stops at its nesting limit.
    if (e.msg == "bad file")
      throw ConfigError("file", "'" + path + "' is nested too deeply at line " +
                                    std::to_string(e.mark.line + 1) + ", column " +
                                    std::to_string(e.mark.column + 1) +
                                    " (a config needs two levels: section, key)");
    throw ConfigError("file", "'" + path + "' is not valid YAML: " + e.what());
  } catch (const std::exception& e) {  // I/O errors and the like
    throw ConfigError("file", "'" + path + "' cannot be read as YAML: " + e.what());
  }
  if (documents.size() > 1)
    throw ConfigError("file", "'" + path + "' holds " + std::to_string(documents.size()) +
                                  " YAML documents; a config is one document (no '---' between "
                                  "sections)");
  return documents.empty() ? YAML::Node() : documents.front();
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
