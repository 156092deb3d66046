#include "kane_sim/config/parameter_schema.h"

#include <cmath>
#include <sstream>

#include "kane_sim/format_number.h"
#include "kane_sim/model/joint_names.h"

namespace kane_sim {
namespace {

// Where a value lives: a captureless lambda per field (nested members have no member pointer).
#define KANE_SIM_NUMBER(member)                    \
  ConfigField {                                    \
    +[](Config& c) -> double& { return c.member; } \
  }
#define KANE_SIM_FLAG(member)                                      \
  ConfigField {                                                    \
    nullptr, nullptr, +[](Config& c) -> bool& { return c.member; } \
  }
#define KANE_SIM_TEXT(member)                                                      \
  ConfigField {                                                                    \
    nullptr, nullptr, nullptr, +[](Config& c) -> std::string& { return c.member; } \
  }

ConfigField wholeField(int& (*field)(Config&)) {
  ConfigField f;
  f.whole = field;
  return f;
}

constexpr ValueRule kAny{ValueRule::kFinite};
constexpr ValueRule kPositive{ValueRule::kPositive};
constexpr ValueRule kNonNegative{ValueRule::kNonNegative};
constexpr ValueRule kFlag{ValueRule::kFlag};
constexpr ValueRule kChoice{ValueRule::kChoice};

// Physical parameters are reconfigured at level 1 (their energy change is booked), the others 0.
constexpr ReconfigureSpec kFixed{};
constexpr ReconfigureSpec physical(const char* name, double gui_min, double gui_max) {
  return {name, 1, gui_min, gui_max};
}
constexpr ReconfigureSpec operational(const char* name, double gui_min, double gui_max) {
  return {name, 0, gui_min, gui_max};
}

// sensors.<joint>_*: four parameters per joint, each reaching its joint's settings.
template <int J>
double& positionNoise(Config& c) {
  return c.sensors.joints[J].position_noise;
}
template <int J>
double& velocityNoise(Config& c) {
  return c.sensors.joints[J].velocity_noise;
}
template <int J>
double& biasWalk(Config& c) {
  return c.sensors.joints[J].bias_walk;
}
template <int J>
double& encoderCounts(Config& c) {
  return c.sensors.joints[J].encoder_counts;
}

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

template <int J>
void appendJointSensor(std::vector<ParameterSpec>* out) {
  const JointSensorKeys& k = kJointSensorKeys[J];
  const auto number = [](double& (*field)(Config&)) {
    ConfigField f;
    f.number = field;
    return f;
  };
  const std::string joint = kJointNames[J];
  static const std::string docs[4] = {
      joint + ": σ of the white noise on position", joint + ": σ of the white noise on velocity",
      joint + ": position bias random walk (its σ grows as this × √t)",
      joint + ": encoder resolution; position rounded to whole counts"};
  out->push_back({"sensors",
                  k.position_noise,
                  "",
                  k.revolute ? "rad" : "m",
                  kNoiseRule,
                  number(&positionNoise<J>),
                  false,
                  docs[0].c_str(),
                  "",
                  "",
                  {},
                  "",
                  kFixed});
  out->push_back({"sensors",
                  k.velocity_noise,
                  "",
                  k.revolute ? "rad/s" : "m/s",
                  kNoiseRule,
                  number(&velocityNoise<J>),
                  false,
                  docs[1].c_str(),
                  "",
                  "",
                  {},
                  "",
                  kFixed});
  out->push_back({"sensors",
                  k.bias_walk,
                  "",
                  k.revolute ? "rad/√s" : "m/√s",
                  kNoiseRule,
                  number(&biasWalk<J>),
                  false,
                  docs[2].c_str(),
                  "",
                  "",
                  {},
                  "",
                  kFixed});
  out->push_back({"sensors",
                  k.encoder_counts,
                  "",
                  k.revolute ? "counts/turn" : "counts/m",
                  kCountsRule,
                  number(&encoderCounts<J>),
                  false,
                  docs[3].c_str(),
                  "",
                  "",
                  {},
                  "",
                  kFixed});
}

// The sensors section: what joint_states carries when they are on (sim/ sensors).
void appendSensorParameters(std::vector<ParameterSpec>* out) {
  constexpr ValueRule kLatencyRule{ValueRule::kRange, 0.0, 10.0, "s"};
  out->push_back({"sensors",
                  "enabled",
                  "",
                  "",
                  kFlag,
                  KANE_SIM_FLAG(sensors.enabled),
                  false,
                  "joint_states carries the sensor view below (ground truth on "
                  "joint_states_true and mechanism_state); false: the truth",
                  "",
                  "",
                  {},
                  "",
                  kFixed});
  out->push_back({"sensors",
                  "seed",
                  "",
                  "",
                  {ValueRule::kWholeRange, 0.0, 2147483647.0, ""},
                  wholeField([](Config& c) -> int& { return c.sensors.seed; }),
                  false,
                  "seed of the sensors' random numbers: one seed, one sequence of readings",
                  "",
                  "",
                  {},
                  "",
                  kFixed});
  out->push_back({"sensors",
                  "rate",
                  "",
                  "Hz",
                  kNonNegative,
                  KANE_SIM_NUMBER(sensors.rate),
                  false,
                  "readings per second on joint_states (0: simulation.publish_rate)",
                  "0 or a whole number of physics steps per reading",
                  "",
                  {},
                  "",
                  kFixed});
  out->push_back({"sensors",
                  "latency",
                  "",
                  "s",
                  kLatencyRule,
                  KANE_SIM_NUMBER(sensors.latency),
                  false,
                  "each reading reaches joint_states this much later (rounded to physics steps)",
                  "",
                  "",
                  {},
                  "",
                  kFixed});
  out->push_back({"sensors",
                  "latency_jitter",
                  "",
                  "s",
                  kLatencyRule,
                  KANE_SIM_NUMBER(sensors.latency_jitter),
                  false,
                  "plus a delay uniform in [0, this] per reading; readings never overtake",
                  "",
                  "",
                  {},
                  "",
                  kFixed});
  out->push_back({"sensors",
                  "command_latency",
                  "",
                  "s",
                  kLatencyRule,
                  KANE_SIM_NUMBER(sensors.command_latency),
                  false,
                  "a torque command is in force this much after it arrives (rounded to physics "
                  "steps)",
                  "",
                  "",
                  {},
                  "",
                  kFixed});
  appendJointSensor<kCrankJoint>(out);
  appendJointSensor<kCouplerJoint>(out);
  appendJointSensor<kSlider3Joint>(out);
  appendJointSensor<kSlider4Joint>(out);
}

std::vector<ParameterSpec> declareParameters() {
  ConfigField integrator;
  integrator.get_choice = [](const Config& c) { return static_cast<int>(c.simulation.integrator); };
  integrator.set_choice = [](Config& c, int i) {
    c.simulation.integrator = static_cast<IntegratorType>(i);
  };
  ConfigField equations;
  equations.get_choice = [](const Config& c) { return static_cast<int>(c.simulation.equations); };
  equations.set_choice = [](Config& c, int i) {
    c.simulation.equations = static_cast<EquationsSource>(i);
  };
  ConfigField lockstep_fallback;
  lockstep_fallback.get_choice = [](const Config& c) {
    return static_cast<int>(c.simulation.lockstep_fallback);
  };
  lockstep_fallback.set_choice = [](Config& c, int i) {
    c.simulation.lockstep_fallback = static_cast<LockstepFallback>(i);
  };
  ConfigField command_mode;
  command_mode.get_choice = [](const Config& c) { return static_cast<int>(c.command.mode); };
  command_mode.set_choice = [](Config& c, int i) { c.command.mode = static_cast<CommandMode>(i); };
  ConfigField feedforward;
  feedforward.get_choice = [](const Config& c) { return static_cast<int>(c.command.feedforward); };
  feedforward.set_choice = [](Config& c, int i) {
    c.command.feedforward = static_cast<Feedforward>(i);
  };
  const std::vector<std::string> command_modes = {commandModeName(CommandMode::kEffort),
                                                  commandModeName(CommandMode::kVelocity),
                                                  commandModeName(CommandMode::kPosition)};
  const std::vector<std::string> feedforwards = {feedforwardName(Feedforward::kNone),
                                                 feedforwardName(Feedforward::kHolding)};
  // Gains up to 1e6: every servo term stays finite for any finite error the physics allows.
  constexpr ValueRule kGainRule{ValueRule::kRange, 0.0, 1e6, ""};
  const std::vector<std::string> lockstep_fallbacks = {
      lockstepFallbackName(LockstepFallback::kHold), lockstepFallbackName(LockstepFallback::kZero)};
  const std::vector<std::string> integrators = {integratorName(IntegratorType::kRk4),
                                                integratorName(IntegratorType::kDopri5)};
  const std::vector<std::string> equation_sources = {equationsName(EquationsSource::kGenerated),
                                                     equationsName(EquationsSource::kGeneric)};

  // section, key, symbol, unit, rule, field, required, doc, cross_rule, default_text, choices,
  // choice_noun, reconfigure
  std::vector<ParameterSpec> parameters = {
      // ---- mechanism: the textbook's parameters --------------------------------------------
      {"mechanism",
       "rod_mass",
       "m",
       "kg",
       kPositive,
       KANE_SIM_NUMBER(mechanism.rod_mass),
       true,
       "mass of each rod (OA and AB)",
       "",
       "",
       {},
       "",
       physical("rod_mass", 0.0, 1e3)},
      {"mechanism",
       "rod_half_length",
       "L",
       "m",
       kPositive,
       KANE_SIM_NUMBER(mechanism.rod_half_length),
       true,
       "half the length of each rod (2L long)",
       "",
       "",
       {},
       "",
       kFixed},
      {"mechanism",
       "slider3_mass",
       "M1",
       "kg",
       kPositive,
       KANE_SIM_NUMBER(mechanism.slider3_mass),
       true,
       "mass of slider 3 at B",
       "",
       "",
       {},
       "",
       physical("slider3_mass", 0.0, 1e3)},
      {"mechanism",
       "slider4_mass",
       "M2",
       "kg",
       kPositive,
       KANE_SIM_NUMBER(mechanism.slider4_mass),
       true,
       "mass of slider 4 at C",
       "",
       "",
       {},
       "",
       physical("slider4_mass", 0.0, 1e3)},
      {"mechanism",
       "spring_stiffness",
       "k",
       "N/m",
       kNonNegative,
       KANE_SIM_NUMBER(mechanism.spring_stiffness),
       true,
       "stiffness of the spring between B and C",
       "",
       "",
       {},
       "",
       physical("spring_stiffness", 0.0, 1e7)},
      {"mechanism",
       "gravity",
       "g",
       "m/s²",
       kAny,
       KANE_SIM_NUMBER(mechanism.gravity),
       true,
       "gravity along +i (down the rail)",
       "",
       "",
       {},
       "",
       physical("gravity", -100.0, 100.0)},
      {"mechanism",
       "rod_inertia",
       "I1z = I2z",
       "kg m²",
       kPositive,
       KANE_SIM_NUMBER(mechanism.rod_inertia),
       false,
       "central moment of inertia of each rod about k",
       "",
       "m (2L)²/12",
       {},
       "",
       kFixed},
      // ---- initial_state: where the motion starts; the spring is unstretched there ---------
      {"initial_state",
       "q1",
       "q10",
       "rad",
       kAny,
       KANE_SIM_NUMBER(initial_state.q1),
       true,
       "crank angle",
       "",
       "",
       {},
       "",
       kFixed},
      {"initial_state",
       "q2",
       "q20",
       "m",
       kAny,
       KANE_SIM_NUMBER(initial_state.q2),
       true,
       "x of slider 4 (C); the spring is unstretched at (q10, q20)",
       "",
       "",
       {},
       "",
       kFixed},
      {"initial_state",
       "u1",
       "u10",
       "rad/s",
       kAny,
       KANE_SIM_NUMBER(initial_state.u1),
       true,
       "crank speed",
       "",
       "",
       {},
       "",
       kFixed},
      {"initial_state",
       "u2",
       "u20",
       "m/s",
       kAny,
       KANE_SIM_NUMBER(initial_state.u2),
       true,
       "speed of slider 4",
       "",
       "",
       {},
       "",
       kFixed},
      // ---- simulation ------------------------------------------------------------------------
      // Below 1 Hz a "physics step" is not a simulation; above 1 MHz a step nears double's
      // useful resolution of time.
      {"simulation",
       "physics_rate",
       "",
       "Hz",
       {ValueRule::kRange, 1.0, 1e6, "Hz"},
       KANE_SIM_NUMBER(simulation.physics_rate),
       false,
       "physics steps per second of sim time (one step is 1/physics_rate)",
       "with rk4, fast enough for the motion's fastest rate: \\|λ\\| h ≤ 2.5 over a sampled turn "
       "of the crank, at rest and as fast as the initial energy lets it swing, with the dampers "
       "and the motor line (as a crank damper of torque_limit/ω0) counted; checked at start-up "
       "and at every reconfiguration",
       "",
       {},
       "",
       kFixed},
      {"simulation", "integrator", "", "", kChoice, integrator, false,
       "rk4: one fixed step; dopri5: error-controlled Dormand–Prince inside each step", "", "",
       integrators, "an unknown integrator", kFixed},
      {"simulation", "equations", "", "", kChoice, equations, false,
       "generated (from SymPy, the fast path) or generic (the Kane assembly term by term); same "
       "physics to rounding",
       "", "", equation_sources, "unknown equations", kFixed},
      {"simulation",
       "absolute_tolerance",
       "",
       "",
       kPositive,
       KANE_SIM_NUMBER(simulation.absolute_tolerance),
       false,
       "dopri5's absolute error tolerance",
       "",
       "",
       {},
       "",
       kFixed},
      {"simulation",
       "relative_tolerance",
       "",
       "",
       kPositive,
       KANE_SIM_NUMBER(simulation.relative_tolerance),
       false,
       "dopri5's relative error tolerance",
       "",
       "",
       {},
       "",
       kFixed},
      {"simulation",
       "publish_rate",
       "",
       "Hz",
       kAny,
       KANE_SIM_NUMBER(simulation.publish_rate),
       false,
       "joint_states, tf and mechanism_state per second",
       "in [physics_rate / 10⁵, physics_rate] and divides physics_rate",
       "",
       {},
       "",
       kFixed},
      {"simulation",
       "real_time_factor",
       "",
       "",
       {ValueRule::kZeroOrRange, 1e-3, 1e6, "(or 0 = as fast as possible)"},
       KANE_SIM_NUMBER(simulation.real_time_factor),
       false,
       "sim time per wall time; 0 = as fast as possible",
       "",
       "",
       {},
       "",
       operational("real_time_factor", 0.0, 1e6)},
      {"simulation",
       "publish_clock",
       "",
       "",
       kFlag,
       KANE_SIM_FLAG(simulation.publish_clock),
       false,
       "the node owns /clock (sim.launch's `publish_clock` arg sets it)",
       "",
       "",
       {},
       "",
       kFixed},
      {"simulation",
       "start_paused",
       "",
       "",
       kFlag,
       KANE_SIM_FLAG(simulation.start_paused),
       false,
       "wait for `unpause` or `step`",
       "",
       "",
       {},
       "",
       kFixed},
      {"simulation",
       "lockstep",
       "",
       "",
       kFlag,
       KANE_SIM_FLAG(simulation.lockstep),
       false,
       "step past a published state only when a torque_command_stamped answers its stamp "
       "(sim.launch's `lockstep` arg)",
       "",
       "",
       {},
       "",
       kFixed},
      {"simulation",
       "lockstep_timeout",
       "",
       "s",
       {ValueRule::kRange, 1e-3, 3600.0, "s (wall)"},
       KANE_SIM_NUMBER(simulation.lockstep_timeout),
       false,
       "wall time lockstep waits for an answer before its fallback (counted in /diagnostics)",
       "",
       "",
       {},
       "",
       kFixed},
      {"simulation",
       "realtime_priority",
       "",
       "",
       {ValueRule::kWholeRange, 0.0, 99.0, "(0 = off, else a SCHED_FIFO priority)"},
       wholeField([](Config& c) -> int& { return c.simulation.realtime_priority; }),
       false,
       "the node's physics loop at this SCHED_FIFO priority with its memory locked (needs "
       "privileges; refused with a warning otherwise; ignored with real_time_factor 0)",
       "",
       "",
       {},
       "",
       kFixed},
      {"simulation", "lockstep_fallback", "", "", kChoice, lockstep_fallback, false,
       "without an answer in time: hold the last command, or zero (0 N m)", "", "",
       lockstep_fallbacks, "an unknown lockstep fallback", kFixed},
      // ---- command: the driver moment M_m ----------------------------------------------------
      {"command",
       "torque_limit",
       "",
       "N m",
       kNonNegative,
       KANE_SIM_NUMBER(command.torque_limit),
       false,
       "\\|M_m\\| is clamped to this; the motor line's stall torque",
       "",
       "",
       {},
       "",
       operational("torque_limit", 0.0, 1e4)},
      {"command",
       "timeout",
       "",
       "s",
       kNonNegative,
       KANE_SIM_NUMBER(command.timeout),
       false,
       "no command for this long (sim time) → torque 0; 0 disables",
       "",
       "",
       {},
       "",
       operational("command_timeout", 0.0, 3600.0)},
      {"command", "mode", "", "", kChoice, command_mode, false,
       "effort: torque_command is M_m; velocity / position: servo_setpoint [rad/s | rad] is held "
       "by the drive's servo (gains below), whose torque goes through torque_limit and the motor "
       "line",
       "", "", command_modes, "an unknown command mode", kFixed},
      {"command", "feedforward", "", "", kChoice, feedforward, false,
       "servo modes: none, or holding: add the moment that balances gravity and the spring at "
       "the present configuration (-F_1 at u = 0, from the model's equations)",
       "", "", feedforwards, "an unknown feedforward", kFixed},
      {"command",
       "position_kp",
       "",
       "N m/rad",
       kGainRule,
       KANE_SIM_NUMBER(command.position_kp),
       false,
       "position servo: proportional gain",
       "",
       "",
       {},
       "",
       operational("position_kp", 0.0, 1e4)},
      {"command",
       "position_ki",
       "",
       "N m/(rad s)",
       kGainRule,
       KANE_SIM_NUMBER(command.position_ki),
       false,
       "position servo: integral gain (the integral stops while the output saturates, cleared "
       "on reset)",
       "",
       "",
       {},
       "",
       operational("position_ki", 0.0, 1e4)},
      {"command",
       "position_kd",
       "",
       "N m s/rad",
       kGainRule,
       KANE_SIM_NUMBER(command.position_kd),
       false,
       "position servo: derivative gain, on the measured speed u1",
       "",
       "",
       {},
       "",
       operational("position_kd", 0.0, 1e3)},
      {"command",
       "velocity_kp",
       "",
       "N m s/rad",
       kGainRule,
       KANE_SIM_NUMBER(command.velocity_kp),
       false,
       "velocity servo: proportional gain",
       "",
       "",
       {},
       "",
       operational("velocity_kp", 0.0, 1e3)},
      {"command",
       "velocity_ki",
       "",
       "N m/rad",
       kGainRule,
       KANE_SIM_NUMBER(command.velocity_ki),
       false,
       "velocity servo: integral gain",
       "",
       "",
       {},
       "",
       operational("velocity_ki", 0.0, 1e4)},
      {"command",
       "motor_no_load_speed",
       "ω0",
       "rad/s",
       kNonNegative,
       KANE_SIM_NUMBER(mechanism.motor.no_load_speed),
       false,
       "the motor's torque–speed line (below); 0 = off",
       "",
       "",
       {},
       "",
       physical("motor_no_load_speed", 0.0, 1e5)},
      // ---- damping: viscous, at the joints joint_states names, and beside the spring ----------
      {"damping",
       "crank_joint",
       "c_O",
       "N m s/rad",
       kNonNegative,
       KANE_SIM_NUMBER(mechanism.damping.crank),
       false,
       "pin O: −c_O u1 on rod 1",
       "",
       "",
       {},
       "",
       physical("crank_damping", 0.0, 1e4)},
      {"damping",
       "coupler_joint",
       "c_A",
       "N m s/rad",
       kNonNegative,
       KANE_SIM_NUMBER(mechanism.damping.coupler),
       false,
       "pin A: on the relative rate of rods 2 and 1",
       "",
       "",
       {},
       "",
       physical("coupler_damping", 0.0, 1e4)},
      {"damping",
       "slider3_joint",
       "c_B",
       "N s/m",
       kNonNegative,
       KANE_SIM_NUMBER(mechanism.damping.slider3),
       false,
       "slider 3 on the rail",
       "",
       "",
       {},
       "",
       physical("slider3_damping", 0.0, 1e4)},
      {"damping",
       "slider4_joint",
       "c_C",
       "N s/m",
       kNonNegative,
       KANE_SIM_NUMBER(mechanism.damping.slider4),
       false,
       "slider 4 on the rail",
       "",
       "",
       {},
       "",
       physical("slider4_damping", 0.0, 1e4)},
      {"damping",
       "spring",
       "c_S",
       "N s/m",
       kNonNegative,
       KANE_SIM_NUMBER(mechanism.damping.spring),
       false,
       "beside the spring: −c_S (v_C − v_B) on slider 4, the opposite on slider 3",
       "",
       "",
       {},
       "",
       physical("spring_damping", 0.0, 1e4)},
      // ---- contact between the sliders -------------------------------------------------------
      {"contact",
       "enabled",
       "",
       "",
       kFlag,
       KANE_SIM_FLAG(mechanism.contact.enabled),
       false,
       "slider impacts and resting contact (below)",
       "",
       "",
       {},
       "",
       kFixed},
      {"contact",
       "gap",
       "",
       "m",
       kNonNegative,
       KANE_SIM_NUMBER(mechanism.contact.gap),
       false,
       "x_C − x_B at touch",
       "the initial state must be at least this far apart",
       "",
       {},
       "",
       kFixed},
      {"contact",
       "restitution",
       "e",
       "",
       {ValueRule::kRange, 0.0, 1.0, "(0 plastic, 1 elastic)"},
       KANE_SIM_NUMBER(mechanism.contact.restitution),
       false,
       "separating speed / approaching speed",
       "",
       "",
       {},
       "",
       kFixed},
      // ---- frames ----------------------------------------------------------------------------
      {"frames",
       "prefix",
       "",
       "",
       {ValueRule::kAnyName},
       KANE_SIM_TEXT(frames.prefix),
       false,
       "prepended to every frame name",
       "",
       "",
       {},
       "",
       kFixed},
      {"frames",
       "world",
       "",
       "",
       {ValueRule::kFrameName},
       KANE_SIM_TEXT(frames.world),
       false,
       "the REP-105 world frame, z up",
       "not one of the mechanism's own frames",
       "",
       {},
       "",
       kFixed},
      {"frames",
       "pivot_height",
       "",
       "m",
       kAny,
       KANE_SIM_NUMBER(frames.pivot_height),
       false,
       "height of O above the world origin",
       "",
       "",
       {},
       "",
       kFixed},
      {"frames",
       "publish_tf",
       "",
       "",
       kFlag,
       KANE_SIM_FLAG(frames.publish_tf),
       false,
       "false: no tf from the node (robot_state_publisher computes it)",
       "",
       "",
       {},
       "",
       kFixed},
      // ---- diagnostics -----------------------------------------------------------------------
      {"diagnostics",
       "overrun_fraction",
       "",
       "",
       {ValueRule::kRange, 0.0, 1.0, "(a fraction of the ticks of a 1 s window)"},
       KANE_SIM_NUMBER(diagnostics.overrun_fraction),
       false,
       "a 1 s window is late when more than this fraction of its ticks overran (or lag was "
       "dropped)",
       "",
       "",
       {},
       "",
       kFixed},
      {"diagnostics",
       "late_windows",
       "",
       "windows",
       {ValueRule::kWholeRange, 1.0, 3600.0, "windows of 1 s"},
       wholeField([](Config& c) -> int& { return c.diagnostics.late_windows; }),
       false,
       "`/diagnostics` says WARN after this many late windows in a row",
       "",
       "",
       {},
       "",
       kFixed},
  };
  appendSensorParameters(&parameters);
  return parameters;
}

#undef KANE_SIM_NUMBER
#undef KANE_SIM_FLAG
#undef KANE_SIM_TEXT

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

const std::vector<ParameterSpec>& parameterSchema() {
  static const std::vector<ParameterSpec> schema = declareParameters();
  return schema;
}

const std::vector<SectionSpec>& configSections() {
  static const std::vector<SectionSpec> sections = {
      {"mechanism", true}, {"initial_state", true}, {"simulation", false},
      {"command", false},  {"damping", false},      {"contact", false},
      {"frames", false},   {"diagnostics", false},  {"sensors", false}};
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
  std::string key, symbol, unit, fallback, rule, reconfigure, meaning;
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
  field("reconfigure", r.reconfigure.empty() ? "" : r.reconfigure + " (dynamic_reconfigure)");
  field("meaning", r.meaning);
  return out;
}

}  // namespace

std::string parameterTable() {
  const Config defaults;
  std::ostringstream table;
  table << "| key | symbol | unit | default | rule | reconfigure name | meaning |\n"
        << "|---|---|---|---|---|---|---|\n";
  for (const ParameterSpec& p : parameterSchema()) {
    const ParameterRow r = parameterRow(p, defaults);
    table << "| " << r.key << " | " << r.symbol << " | " << r.unit << " | " << r.fallback << " | "
          << r.rule << " | " << (r.reconfigure.empty() ? "" : "`" + r.reconfigure + "`") << " | "
          << r.meaning << " |\n";
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
