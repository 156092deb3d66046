#include "kane_sim/config/parameter_schema.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "kane_sim/format_number.h"
#include "kane_sim/model/generated_equations.h"
#include "kane_sim/model/joint_names.h"
#include "schema_rows.h"

namespace kane_sim {
namespace {

using namespace schema_rows;  // NOLINT: the rows' vocabulary

struct JointSensorKeys {
  const char* position_noise;
  const char* velocity_noise;
  const char* bias_walk;
  const char* encoder_counts;
  bool revolute;
};
constexpr JointSensorKeys kJointSensorKeys[kNumJoints] = {
    {"crank_position_noise", "crank_velocity_noise", "crank_bias_walk", "crank_encoder_counts",
     true},
    {"coupler_position_noise", "coupler_velocity_noise", "coupler_bias_walk",
     "coupler_encoder_counts", true},
    {"slider3_position_noise", "slider3_velocity_noise", "slider3_bias_walk",
     "slider3_encoder_counts", false},
    {"slider4_position_noise", "slider4_velocity_noise", "slider4_bias_walk",
     "slider4_encoder_counts", false}};

// σ up to 1e6 (of rad or m) keeps every reading finite over the longest stampable run.
constexpr ValueRule kNoiseRule{ValueRule::kRange, 0.0, 1e6, ""};
constexpr ValueRule kCountsRule{ValueRule::kZeroOrRange, 1.0, 1e12, "(0 = not quantised)"};

// sensors.<joint>_*: four parameters per joint, each reaching its joint's settings.
template <int J>
void appendJointSensor(std::vector<ParameterSpec>* out) {
  const JointSensorKeys& k = kJointSensorKeys[J];
  const std::string joint = kJointNames[J];
  static const std::string docs[4] = {
      joint + ": σ of the white noise on position", joint + ": σ of the white noise on velocity",
      joint + ": position bias random walk (its σ grows as this × √t)",
      joint + ": encoder resolution; position rounded to whole counts"};
  // clang-format off
  out->insert(out->end(), {
      row("sensors", k.position_noise, KANE_SIM_FIELD(sensors.joints[J].position_noise),
          k.revolute ? "rad" : "m", kNoiseRule).doc(docs[0].c_str()),
      row("sensors", k.velocity_noise, KANE_SIM_FIELD(sensors.joints[J].velocity_noise),
          k.revolute ? "rad/s" : "m/s", kNoiseRule).doc(docs[1].c_str()),
      row("sensors", k.bias_walk, KANE_SIM_FIELD(sensors.joints[J].bias_walk),
          k.revolute ? "rad/√s" : "m/√s", kNoiseRule).doc(docs[2].c_str()),
      row("sensors", k.encoder_counts, KANE_SIM_FIELD(sensors.joints[J].encoder_counts),
          k.revolute ? "counts/turn" : "counts/m", kCountsRule).doc(docs[3].c_str()),
  });
  // clang-format on
}

// uncertainty.<section.key>: a standard error for each parameter a recorded motion can tell, in
// the identifiable rows' order (Config::uncertainty), its unit theirs.
template <std::size_t I>
double& uncertaintyField(Config& c) {
  return c.uncertainty[I];
}
template <std::size_t... I>
constexpr std::array<double& (*)(Config&), sizeof...(I)> uncertaintyFields(
    std::index_sequence<I...>) {
  return {{&uncertaintyField<I>...}};
}

void appendUncertainties(const std::vector<ParameterSpec>& rows, std::vector<ParameterSpec>* out) {
  static const auto fields = uncertaintyFields(std::make_index_sequence<kMaxIdentifiable>());
  static std::deque<std::string> keys, docs;  // the rows' text, kept for the program's life
  std::size_t i = 0;
  for (const ParameterSpec& spec : rows) {
    if (!identifiable(spec)) continue;
    if (i == fields.size())
      throw std::logic_error("parameter schema: more identifiable rows than kMaxIdentifiable");
    keys.push_back(spec.path());
    docs.push_back("the standard error of " + spec.path() +
                   " (identify writes it): the estimator takes the model as uncertain by this "
                   "much; 0 = known exactly");
    out->push_back(row("uncertainty", keys.back().c_str(), fields[i++], spec.unit, kNoiseRule)
                       .role(ParameterRole::kOperational)
                       .doc(docs.back().c_str()));
  }
}

std::vector<ParameterSpec> declareParameters() {
  // Gains up to 1e6: every servo term stays finite for any finite error the physics allows.
  constexpr ValueRule kGainRule{ValueRule::kRange, 0.0, 1e6, ""};
  constexpr ValueRule kLatencyRule{ValueRule::kRange, 0.0, 10.0, "s"};
  // clang-format off
  std::vector<ParameterSpec> parameters = {
      // ---- initial_state: where the motion starts; the spring is unstretched there ---------
      row("initial_state", "q1", KANE_SIM_FIELD(initial_state.q1), "rad", kAny)
          .symbol("q10").role(ParameterRole::kInitialState).required()
          .doc("crank angle"),
      row("initial_state", "q2", KANE_SIM_FIELD(initial_state.q2), "m", kAny)
          .symbol("q20").role(ParameterRole::kInitialState).required()
          .doc("x of slider 4 (C); the spring is unstretched at (q10, q20)"),
      row("initial_state", "u1", KANE_SIM_FIELD(initial_state.u1), "rad/s", kAny)
          .symbol("u10").role(ParameterRole::kInitialState).required()
          .doc("crank speed"),
      row("initial_state", "u2", KANE_SIM_FIELD(initial_state.u2), "m/s", kAny)
          .symbol("u20").role(ParameterRole::kInitialState).required()
          .doc("speed of slider 4"),
      // ---- simulation ------------------------------------------------------------------------
      // Below 1 Hz a "physics step" is not a simulation; above 1 MHz a step nears double's
      // useful resolution of time.
      row("simulation", "physics_rate", KANE_SIM_FIELD(simulation.physics_rate), "Hz",
              {ValueRule::kRange, 1.0, 1e6, "Hz"})
          .doc("physics steps per second of sim time (one step is 1/physics_rate)")
          .crossRule("with rk4, fast enough for the motion's fastest rate: \\|λ\\| h ≤ 2.5 over a "
              "sampled turn of the crank, at rest and as fast as the initial energy lets "
              "it swing, with the dampers and the motor line (as a crank damper of "
              "torque_limit/ω0) counted; checked at start-up and at every reconfiguration"),
      choice("simulation", "integrator", KANE_SIM_FIELD(simulation.integrator))
          .doc("rk4: one fixed step; dopri5: error-controlled Dormand–Prince inside each step"),
      choice("simulation", "equations", KANE_SIM_FIELD(simulation.equations))
          .doc("generated (from SymPy, the fast path) or generic (the Kane assembly term by "
              "term); same physics to rounding"),
      row("simulation", "absolute_tolerance", KANE_SIM_FIELD(simulation.absolute_tolerance), "",
              kPositive)
          .doc("dopri5's absolute error tolerance"),
      row("simulation", "relative_tolerance", KANE_SIM_FIELD(simulation.relative_tolerance), "",
              kPositive)
          .doc("dopri5's relative error tolerance"),
      row("simulation", "publish_rate", KANE_SIM_FIELD(simulation.publish_rate), "Hz", kAny)
          .doc("joint_states, tf and mechanism_state per second")
          .crossRule("in [physics_rate / 10⁵, physics_rate] and divides physics_rate"),
      row("simulation", "real_time_factor", KANE_SIM_FIELD(simulation.real_time_factor), "",
              {ValueRule::kZeroOrRange, 1e-3, 1e6, "(or 0 = as fast as possible)"})
          .reconfigure(operational("real_time_factor", 0.0, 1e6))
          .doc("sim time per wall time; 0 = as fast as possible"),
      row("simulation", "publish_clock", KANE_SIM_FIELD(simulation.publish_clock), "", kFlag)
          .doc("the node owns /clock (sim.launch's `publish_clock` arg sets it)"),
      row("simulation", "start_paused", KANE_SIM_FIELD(simulation.start_paused), "", kFlag)
          .doc("wait for `unpause` or `step`"),
      row("simulation", "lockstep", KANE_SIM_FIELD(simulation.lockstep), "", kFlag)
          .doc("step past a published state only when a torque_command_stamped answers its "
              "stamp (sim.launch's `lockstep` arg)"),
      row("simulation", "lockstep_timeout", KANE_SIM_FIELD(simulation.lockstep_timeout), "s",
              {ValueRule::kRange, 1e-3, 3600.0, "s (wall)"})
          .doc("wall time lockstep waits for an answer before its fallback (counted in "
              "/diagnostics)"),
      row("simulation", "realtime_priority", KANE_SIM_FIELD(simulation.realtime_priority), "",
              {ValueRule::kWholeRange, 0.0, 99.0, "(0 = off, else a SCHED_FIFO priority)"})
          .doc("the node's physics loop at this SCHED_FIFO priority with its memory locked "
              "(needs privileges; refused with a warning otherwise; ignored with "
              "real_time_factor 0)"),
      choice("simulation", "lockstep_fallback", KANE_SIM_FIELD(simulation.lockstep_fallback))
          .doc("without an answer in time: hold the last command, or zero (0 N m)"),
      // ---- command: the driver moment M_m ----------------------------------------------------
      row("command", "torque_limit", KANE_SIM_FIELD(command.torque_limit), "N m", kNonNegative)
          .reconfigure(operational("torque_limit", 0.0, 1e4))
          .doc("\\|M_m\\| is clamped to this; the motor line's stall torque"),
      row("command", "timeout", KANE_SIM_FIELD(command.timeout), "s", kNonNegative)
          .reconfigure(operational("command_timeout", 0.0, 3600.0))
          .doc("no command for this long (sim time) → torque 0; 0 disables"),
      choice("command", "mode", KANE_SIM_FIELD(command.mode))
          .doc("effort: torque_command is M_m; velocity / position: servo_setpoint [rad/s | "
              "rad] is held by the drive's servo (gains below), whose torque goes through "
              "torque_limit and the motor line"),
      choice("command", "feedforward", KANE_SIM_FIELD(command.feedforward))
          .doc("servo modes: none, or holding: add the moment that balances gravity and the "
              "spring at the present configuration (-F_1 at u = 0, from the model's "
              "equations)"),
      row("command", "position_kp", KANE_SIM_FIELD(command.position_kp), "N m/rad", kGainRule)
          .reconfigure(operational("position_kp", 0.0, 1e4))
          .doc("position servo: proportional gain"),
      row("command", "position_ki", KANE_SIM_FIELD(command.position_ki), "N m/(rad s)", kGainRule)
          .reconfigure(operational("position_ki", 0.0, 1e4))
          .doc("position servo: integral gain (the integral stops while the output "
              "saturates, cleared on reset)"),
      row("command", "position_kd", KANE_SIM_FIELD(command.position_kd), "N m s/rad", kGainRule)
          .reconfigure(operational("position_kd", 0.0, 1e3))
          .doc("position servo: derivative gain, on the measured speed u1"),
      row("command", "velocity_kp", KANE_SIM_FIELD(command.velocity_kp), "N m s/rad", kGainRule)
          .reconfigure(operational("velocity_kp", 0.0, 1e3))
          .doc("velocity servo: proportional gain"),
      row("command", "velocity_ki", KANE_SIM_FIELD(command.velocity_ki), "N m/rad", kGainRule)
          .reconfigure(operational("velocity_ki", 0.0, 1e4))
          .doc("velocity servo: integral gain"),
      // ---- frames ----------------------------------------------------------------------------
      row("frames", "prefix", KANE_SIM_FIELD(frames.prefix), "", {ValueRule::kAnyName})
          .doc("prepended to every frame name"),
      row("frames", "world", KANE_SIM_FIELD(frames.world), "", {ValueRule::kFrameName})
          .doc("the REP-105 world frame, z up")
          .crossRule("not one of the mechanism's own frames"),
      row("frames", "pivot_height", KANE_SIM_FIELD(frames.pivot_height), "m", kAny)
          .doc("height of O above the world origin"),
      row("frames", "publish_tf", KANE_SIM_FIELD(frames.publish_tf), "", kFlag)
          .doc("false: no tf from the node (robot_state_publisher computes it)"),
      // ---- diagnostics -----------------------------------------------------------------------
      row("diagnostics", "overrun_fraction", KANE_SIM_FIELD(diagnostics.overrun_fraction), "",
              {ValueRule::kRange, 0.0, 1.0, "(a fraction of the ticks of a 1 s window)"})
          .doc("a 1 s window is late when more than this fraction of its ticks overran (or "
              "lag was dropped)"),
      row("diagnostics", "late_windows", KANE_SIM_FIELD(diagnostics.late_windows), "windows",
              {ValueRule::kWholeRange, 1.0, 3600.0, "windows of 1 s"})
          .doc("`/diagnostics` says WARN after this many late windows in a row"),
      // ---- sensors: what joint_states carries when they are on (sim/ sensors) ----------------
      row("sensors", "enabled", KANE_SIM_FIELD(sensors.enabled), "", kFlag)
          .doc("joint_states carries the sensor view below (ground truth on "
              "joint_states_true and mechanism_state); false: the truth"),
      row("sensors", "seed", KANE_SIM_FIELD(sensors.seed), "", {ValueRule::kWholeRange, 0.0,
              2147483647.0, ""})
          .doc("seed of the sensors' random numbers: one seed, one sequence of readings"),
      row("sensors", "rate", KANE_SIM_FIELD(sensors.rate), "Hz", kNonNegative)
          .doc("readings per second on joint_states (0: simulation.publish_rate)")
          .crossRule("0 or a whole number of physics steps per reading"),
      row("sensors", "latency", KANE_SIM_FIELD(sensors.latency), "s", kLatencyRule)
          .doc("each reading reaches joint_states this much later (rounded to physics steps)"),
      row("sensors", "latency_jitter", KANE_SIM_FIELD(sensors.latency_jitter), "s", kLatencyRule)
          .doc("plus a delay uniform in [0, this] per reading; readings never overtake"),
      row("sensors", "command_latency", KANE_SIM_FIELD(sensors.command_latency), "s", kLatencyRule)
          .doc("a torque command is in force this much after it arrives (rounded to physics steps)"),
      // ---- estimator: the state estimator's trust in the model and its alarm (estimate/) -------
      row("estimator", "crank_acceleration_noise",
          KANE_SIM_FIELD(estimator.crank_acceleration_noise), "rad/s^2/sqrt(Hz)", kNoiseRule)
          .doc("estimator: how far u1' may stray from the model, as white noise (process noise)"),
      row("estimator", "slider4_acceleration_noise",
          KANE_SIM_FIELD(estimator.slider4_acceleration_noise), "m/s^2/sqrt(Hz)", kNoiseRule)
          .doc("estimator: how far u2' may stray from the model, as white noise (process noise)"),
      row("estimator", "alarm_window", KANE_SIM_FIELD(estimator.alarm_window), "s",
          {ValueRule::kRange, 0.01, 3600.0, "s"})
          .doc("estimator: the innovations of this much time are tested together (NIS)"),
      row("estimator", "false_alarms_per_hour", KANE_SIM_FIELD(estimator.false_alarms_per_hour),
          "1/h", {ValueRule::kRange, 1e-9, 1e3, "per hour"})
          .doc("estimator: ERROR's false-alarm rate on a rig that is its model (WARN: 100 times "
               "it)"),
      row("estimator", "restart_gap", KANE_SIM_FIELD(estimator.restart_gap), "s",
          {ValueRule::kRange, 1e-3, 60.0, "s"})
          .doc("estimator: readings further apart restart the filter from the later one"),
      row("estimator", "answer_timing_noise", KANE_SIM_FIELD(estimator.answer_timing_noise), "s",
          {ValueRule::kRange, 0.0, 1.0, "s"})
          .doc("estimator: how uncertain the instant a controller's answer to a reading takes "
               "effect (sigma; a ROS transport and scheduler beyond the sensors' jitter)"),
  };
  // clang-format on
  // The sections whose rows are all of one role say it here, once; any other row says its own
  // (parameterSchema() refuses a row without one, so a new section cannot go unclassified).
  const std::pair<const char*, ParameterRole> kSectionRoles[] = {
      {"simulation", ParameterRole::kOperational}, {"command", ParameterRole::kOperational},
      {"frames", ParameterRole::kOperational},     {"diagnostics", ParameterRole::kOperational},
      {"sensors", ParameterRole::kMeasurement},    {"estimator", ParameterRole::kOperational}};
  appendJointSensor<kCrankJoint>(&parameters);
  appendJointSensor<kCouplerJoint>(&parameters);
  appendJointSensor<kSlider3Joint>(&parameters);
  appendJointSensor<kSlider4Joint>(&parameters);
  for (ParameterSpec& p : parameters)
    for (const auto& [section, role] : kSectionRoles)
      if (p.role == ParameterRole::kUnset && std::string(p.section) == section) p.role = role;
  // The mechanism's rows (codegen/parameters.yaml) among these, sections in the config file's
  // order: each after the hand-written rows of its section.
  const std::vector<ParameterSpec> mechanism = mechanismParameterRows();
  parameters.insert(parameters.end(), mechanism.begin(), mechanism.end());
  appendUncertainties(mechanism, &parameters);
  const auto sectionIndex = [](const ParameterSpec& p) {
    const std::vector<SectionSpec>& sections = configSections();
    for (std::size_t i = 0; i < sections.size(); ++i)
      if (std::string(sections[i].name) == p.section) return i;
    throw std::logic_error("parameter schema: " + p.path() +
                           "'s section is not in configSections()");
  };
  std::stable_sort(parameters.begin(), parameters.end(),
                   [&](const ParameterSpec& a, const ParameterSpec& b) {
                     return sectionIndex(a) < sectionIndex(b);
                   });
  return parameters;
}

// A schema that breaks its own promises stops every program at its first use, naming the row.
void checkRoles(const std::vector<ParameterSpec>& schema) {
  for (const ParameterSpec& p : schema) {
    if (p.role == ParameterRole::kUnset)
      throw std::logic_error("parameter schema: " + p.path() + " has no role");
    if (inEquations(p.role) != (*p.equation_symbol != '\0'))
      throw std::logic_error("parameter schema: " + p.path() +
                             (inEquations(p.role) ? " needs" : " must not have") +
                             " an equation symbol");
    if (!inEquations(p.role)) continue;
    bool known = false;
    for (const char* symbol : generated::kConstantSymbols)
      known |= std::string(symbol) == p.equation_symbol;
    if (!known || !p.field.number)
      throw std::logic_error("parameter schema: " + p.path() + "'s equation symbol " +
                             p.equation_symbol + " is not a constant of the generated equations");
  }
}

#undef KANE_SIM_FIELD

std::string ruleText(const ValueRule& rule, const std::vector<std::string>& choices) {
  switch (rule.kind) {
    case ValueRule::kFinite:
      return "finite";
    case ValueRule::kPositive:
      return "> 0";
    case ValueRule::kNonNegative:
      return "≥ 0";
    case ValueRule::kRange:
      return "in [" + formatNumber(rule.lo) + ", " + formatNumber(rule.hi) + "]";
    case ValueRule::kZeroOrRange:
      return "0 or in [" + formatNumber(rule.lo) + ", " + formatNumber(rule.hi) + "]";
    case ValueRule::kWholeRange:
      return "whole number in [" + formatNumber(rule.lo) + ", " + formatNumber(rule.hi) + "]";
    case ValueRule::kFrameName:
      return "letters, digits, `_`, `/`; not starting with `/`";
    case ValueRule::kAnyName:
      return "empty, or letters, digits, `_`, `/`; not starting with `/`";
    case ValueRule::kChoice: {
      std::string text;
      for (const std::string& c : choices) text += (text.empty() ? "" : " or ") + c;
      return text;
    }
    case ValueRule::kFlag:
      return "true or false";
  }
  return "";
}

}  // namespace

bool inEquations(ParameterRole role) {
  switch (role) {
    case ParameterRole::kInertial:
    case ParameterRole::kGeometric:
    case ParameterRole::kGravity:
    case ParameterRole::kStiffness:
    case ParameterRole::kDissipative:
    case ParameterRole::kLoadShape:
      return true;
    default:
      return false;
  }
}

bool identifiable(ParameterRole role) {
  return role == ParameterRole::kInertial || role == ParameterRole::kStiffness ||
         role == ParameterRole::kDissipative;
}

bool identifiable(const ParameterSpec& spec) {
  return identifiable(spec.role) && spec.field.number != nullptr;
}

const char* roleName(ParameterRole role) {
  switch (role) {
    case ParameterRole::kUnset:
      return "unset";
    case ParameterRole::kInertial:
      return "inertial";
    case ParameterRole::kGeometric:
      return "geometric";
    case ParameterRole::kGravity:
      return "gravity";
    case ParameterRole::kStiffness:
      return "stiffness";
    case ParameterRole::kDissipative:
      return "dissipative";
    case ParameterRole::kLoadShape:
      return "load shape";
    case ParameterRole::kDrive:
      return "drive";
    case ParameterRole::kContact:
      return "contact";
    case ParameterRole::kInitialState:
      return "initial state";
    case ParameterRole::kOperational:
      return "operational";
    case ParameterRole::kMeasurement:
      return "measurement";
  }
  return "";
}

const std::vector<ParameterSpec>& parameterSchema() {
  static const std::vector<ParameterSpec> schema = [] {
    std::vector<ParameterSpec> rows = declareParameters();
    checkRoles(rows);
    return rows;
  }();
  return schema;
}

std::vector<const ParameterSpec*> parametersOfRole(ParameterRole role) {
  std::vector<const ParameterSpec*> rows;
  for (const ParameterSpec& p : parameterSchema())
    if (p.role == role) rows.push_back(&p);
  return rows;
}

const std::vector<SectionSpec>& configSections() {
  static const std::vector<SectionSpec> sections = {
      {"mechanism", true}, {"initial_state", true}, {"simulation", false},
      {"command", false},  {"damping", false},      {"friction", false},
      {"contact", false},  {"frames", false},       {"diagnostics", false},
      {"sensors", false},  {"estimator", false},    {"uncertainty", false}};
  return sections;
}

const ParameterSpec* findParameter(const std::string& section, const std::string& key) {
  for (const ParameterSpec& p : parameterSchema())
    if (section == p.section && key == p.key) return &p;
  return nullptr;
}

const ParameterSpec* findReconfigurable(const std::string& name) {
  for (const ParameterSpec& p : parameterSchema())
    if (p.reconfigurable() && name == p.reconfigure.name) return &p;
  return nullptr;
}

double numericValue(const ParameterSpec& spec, const Config& config) {
  // The accessors only name a member; reading through them does not modify the config.
  Config& c = const_cast<Config&>(config);
  const ConfigField& f = spec.field;
  if (f.number) return f.number(c);
  if (f.whole) return f.whole(c);
  if (f.flag) return f.flag(c) ? 1.0 : 0.0;
  if (f.get_choice) return f.get_choice(config);
  return std::nan("");
}

std::string valueText(const ParameterSpec& spec, const Config& config) {
  const ConfigField& f = spec.field;
  if (f.text) return f.text(const_cast<Config&>(config));
  if (f.flag) return numericValue(spec, config) != 0.0 ? "true" : "false";
  if (f.get_choice) return spec.choices.at(static_cast<std::size_t>(f.get_choice(config)));
  return formatNumber(numericValue(spec, config));
}

namespace {

struct ParameterRow {
  std::string key, symbol, unit, fallback, rule, role, reconfigure, meaning;
};

ParameterRow parameterRow(const ParameterSpec& p, const Config& defaults) {
  ParameterRow row;
  row.key = p.path();
  row.symbol = p.symbol;
  row.unit = p.unit;
  row.fallback = p.required        ? "required"
                 : *p.default_text ? p.default_text
                                   : valueText(p, defaults);
  if (row.fallback.empty()) row.fallback = "\"\"";
  // A value that is only read (finite) and then checked against others shows the latter.
  row.rule = ruleText(p.rule, p.choices);
  if (*p.cross_rule)
    row.rule = p.rule.kind == ValueRule::kFinite ? p.cross_rule : row.rule + "; " + p.cross_rule;
  row.role = roleName(p.role);
  row.reconfigure = p.reconfigurable() ? p.reconfigure.name : "";
  row.meaning = p.doc;
  return row;
}

std::string rowText(const ParameterRow& r) {
  std::string out = r.key + "\n";
  const auto field = [&out](const char* name, const std::string& value) {
    if (!value.empty()) out += std::string("  ") + name + ": " + value + "\n";
  };
  field("symbol", r.symbol);
  field("unit", r.unit);
  field("default", r.fallback);
  field("rule", r.rule);
  field("role", r.role);
  field("reconfigure", r.reconfigure.empty() ? "" : r.reconfigure + " (dynamic_reconfigure)");
  field("meaning", r.meaning);
  return out;
}

}  // namespace

std::string parameterTable() {
  const Config defaults;
  std::ostringstream table;
  table << "| key | symbol | unit | default | rule | role | reconfigure name | meaning |\n"
        << "|---|---|---|---|---|---|---|---|\n";
  for (const ParameterSpec& p : parameterSchema()) {
    const ParameterRow r = parameterRow(p, defaults);
    table << "| " << r.key << " | " << r.symbol << " | " << r.unit << " | " << r.fallback << " | "
          << r.rule << " | " << r.role << " | "
          << (r.reconfigure.empty() ? "" : "`" + r.reconfigure + "`") << " | " << r.meaning
          << " |\n";
  }
  return table.str();
}

std::string parameterText(const std::string& key) {
  const Config defaults;
  for (const ParameterSpec& p : parameterSchema())
    if (p.path() == key) return rowText(parameterRow(p, defaults));
  std::string known;
  for (const ParameterSpec& p : parameterSchema())
    if (p.path().find(key) != std::string::npos || key.find(p.key) != std::string::npos)
      known += (known.empty() ? "" : ", ") + p.path();
  throw std::invalid_argument("'" + key + "' is not a config key" +
                              (known.empty() ? " (config_info parameters --text lists them)"
                                             : "; did you mean " + known + "?"));
}

std::string parametersText() {
  const Config defaults;
  std::string out;
  for (const ParameterSpec& p : parameterSchema())
    out += (out.empty() ? "" : "\n") + rowText(parameterRow(p, defaults));
  return out;
}

}  // namespace kane_sim
