#include "kane_sim/sim/config_check.h"

#include <cmath>
#include <sstream>

#include "kane_sim/analysis/stability.h"
#include "kane_sim/config/parameter_schema.h"
#include "kane_sim/format_number.h"
#include "kane_sim/sim/simulator.h"

namespace kane_sim {
namespace {

// The scale of the laws in use that have one (smoothed friction's, when friction is on): a
// larger one softens its law. nullptr when none.
const ParameterSpec* rateScaleInUse(const Config& c) {
  const generated::RateScale scale = generated::smallestRateScale(mechanismModel(c).constants());
  if (scale.constant < 0) return nullptr;
  const std::string key = generated::kConstantKeys[scale.constant];
  return findParameter(key.substr(0, key.find('.')), key.substr(key.find('.') + 1));
}

// ", or a larger <that scale's key>" when a law in use has a scale, else "".
std::string largerScale(const Config& c) {
  const ParameterSpec* scale = rateScaleInUse(c);
  return scale ? ", or a larger " + scale->path() : "";
}

// ", damping.spring 1e+308, friction.crank_joint 2" for every resistance that is on (schema
// order), and the scale of a law in use: what else can make the equations stiff or overflow.
std::string dampersOn(const Config& c) {
  std::string text;
  for (const ParameterSpec* p : parametersOfRole(ParameterRole::kDissipative))
    if (numericValue(*p, c) != 0.0)
      text += ", " + p->path() + " " + formatNumber(numericValue(*p, c));
  if (const ParameterSpec* scale = rateScaleInUse(c))
    text += ", " + scale->path() + " " + formatNumber(numericValue(*scale, c));
  return text;
}

// When the equations are not finite (`consequence` says where) and a constant of them is beyond
// the mechanism's scale (k = 1e308 makes u' overflow at any state), that constant is what to
// fix: refused naming it, not the state.
void refuseBeyondScale(const Config& c, const std::string& consequence) {
  for (const ParameterSpec& p : parameterSchema())
    if (inEquations(p.role) && p.field.number && !(std::abs(numericValue(p, c)) <= 1e100))
      throw ConfigError(p.path(), "= " + formatNumber(numericValue(p, c)) +
                                      " is beyond the mechanism's scale (at most 1e100): with "
                                      "it " +
                                      consequence);
}

// What to do when rk4 at the configured rate cannot follow the fastest rate: a physics_rate
// that can, or, when none within the rate's own limit can, dopri5 or a softer mechanism.
std::string rk4Remedy(double fastest_rate, const Config& c) {
  // A rate the config can take as it is: a whole number of publish periods (publish_rate must
  // divide it; 18362 Hz was once suggested, and then refused for that).
  const double publish = c.simulation.publish_rate;
  double needed = std::ceil(fastest_rate / kRk4StabilityLimit);
  if (publish > 0.0) needed = std::ceil(needed / publish) * publish;
  const double limit = findParameter("simulation", "physics_rate")->rule.hi;
  if (needed <= limit)
    return "use simulation.integrator dopri5 or a physics_rate of at least " +
           formatNumber(needed) + " Hz" + largerScale(c);
  const std::string dampers = dampersOn(c);  // ", damping.spring 1e+12, ..."
  return "no physics_rate up to its limit of " + formatNumber(limit) +
         " Hz is enough (it would "
         "take " +
         formatNumber(needed) +
         " Hz): use simulation.integrator dopri5, or a softer "
         "spring_stiffness, less damping or friction" +
         largerScale(c) + (dampers.empty() ? "" : " (" + dampers.substr(2) + ")");
}

// dopri5 adapts its sub-steps, up to kMaxSubstepsPerTick per physics step; with its stability
// bound of ~3.3 along the negative real axis (2.5 with a margin, as rk4's), a rate beyond this
// times h cannot be followed within one physics step.
constexpr double kDopri5RateSteps = kRk4StabilityLimit * Simulator::kMaxSubstepsPerTick;

void checkIntegrable(const Config& c) {
  const bool rk4 = c.simulation.integrator == IntegratorType::kRk4;
  // dopri5 adapts its step: only what no step can follow is refused (non-finite equations, or a
  // rate beyond its sub-step limit: a friction of 1 N over a velocity scale of 1e-9 m/s once ran
  // 1.8 s and
  // failed then, naming neither key).
  const double h = 1.0 / c.simulation.physics_rate;
  const MechanismModel model = mechanismModel(c);
  // The common case, a mechanism well within its integrator's reach, settled without the scan's
  // eigenvalues; otherwise the scan below finds what to say.
  if (ratesWithin(model, c.initial_state, h, rk4 ? kRk4StabilityLimit : kDopri5RateSteps)) return;
  StiffestConfiguration stiffest = stiffestConfiguration(model, c.initial_state);
  // The initial speeds add their own (centripetal) rates. A scan that found a non-finite rate
  // (NaN) stays refused: it once let the initial state's finite rate stand in for it, so
  // rod_mass 1e-300 passed while 1e-4 ... 1e-280 were refused.
  const double initial = fastestRate(model, c.initial_state, 0.0);
  if (std::isfinite(stiffest.rate) && !(initial <= stiffest.rate))
    stiffest = {initial, c.initial_state.q1, c.initial_state.u1};
  // What sets that rate, and the remedy that comes first: the initial speeds when the same
  // mechanism started at rest would pass (their energy swings it that fast; a speed typed into
  // the page's initial state was once blamed on physics_rate alone).
  const double limit = rk4 ? kRk4StabilityLimit : kDopri5RateSteps;
  const auto passesAtRest = [&] {
    State at_rest = c.initial_state;
    at_rest.u1 = at_rest.u2 = 0.0;
    return stiffestConfiguration(model, at_rest).rate * h <= limit;
  };
  const bool from_initial_speeds = std::isfinite(stiffest.rate) && !(stiffest.rate * h <= limit) &&
                                   (c.initial_state.u1 != 0.0 || c.initial_state.u2 != 0.0) &&
                                   passesAtRest();
  const std::string source =
      from_initial_speeds
          ? "the initial state's speeds (initial_state.u1 = " + formatNumber(c.initial_state.u1) +
                " rad/s, initial_state.u2 = " + formatNumber(c.initial_state.u2) + " m/s)"
          : "spring_stiffness, the masses, damping, friction" +
                (rateScaleInUse(c) ? " (F_c / " + rateScaleInUse(c)->path() + ")" : "") +
                " and the motor line";
  const std::string slower = from_initial_speeds ? "slower initial_state speeds, or " : "";
  if (!std::isfinite(stiffest.rate)) {
    refuseBeyondScale(
        c, "the equations of motion are not finite at q1 = " + formatNumber(stiffest.q1) + " rad");
    throw ConfigError(
        "mechanism",
        "gives equations of motion that are not finite at q1 = " + formatNumber(stiffest.q1) +
            " rad: the masses, lengths, stiffness, damping and friction are too far apart "
            "for double precision (rod_mass " +
            formatNumber(c.mechanism.rod_mass) + ", slider3_mass " +
            formatNumber(c.mechanism.slider3_mass) + ", slider4_mass " +
            formatNumber(c.mechanism.slider4_mass) + ", spring_stiffness " +
            formatNumber(c.mechanism.spring_stiffness) + dampersOn(c) + ")");
  }
  if (!rk4) {
    if (!(stiffest.rate * h <= kDopri5RateSteps))
      throw ConfigError(
          "simulation.physics_rate",
          "is too low even for dopri5 on this mechanism: its fastest rate (" +
              formatNumber(stiffest.rate) + " 1/s, from " + source + ") would take more than " +
              formatNumber(Simulator::kMaxSubstepsPerTick) + " sub-steps in each physics step of " +
              formatNumber(h) + " s" +
              (dampersOn(c).empty() ? "" : " (with " + dampersOn(c).substr(2) + ")") + ": " +
              slower + "a softer spring_stiffness, less damping or friction" + largerScale(c));
    return;
  }
  if (!(stiffest.rate * h <= kRk4StabilityLimit))
    throw ConfigError(
        "simulation.physics_rate",
        "is too low for rk4 on this mechanism: its fastest rate (" + formatNumber(stiffest.rate) +
            " 1/s at q1 = " + formatNumber(stiffest.q1) +
            " rad, u1 = " + formatNumber(stiffest.u1) + " rad/s, from " + source +
            ") needs rate × h <= " + formatNumber(kRk4StabilityLimit) + ", got " +
            formatNumber(stiffest.rate * h) + " at " + formatNumber(c.simulation.physics_rate) +
            " Hz" + (dampersOn(c).empty() ? "" : " (with " + dampersOn(c).substr(2) + ")") + "; " +
            slower + rk4Remedy(stiffest.rate, c));
}

}  // namespace

void checkSimulatable(const Config& config) {
  const Status usable = Simulator(config).checkUsable(config.initial_state);
  if (!usable.ok) {
    refuseBeyondScale(config, "the initial state " + usable.error);
    throw ConfigError("initial_state", "is not a state to start from: " + usable.error);
  }
  checkIntegrable(config);
}

LoadedConfig loadSimulationConfig(const YAML::Node& root) {
  LoadedConfig loaded = loadConfig(root);
  checkSimulatable(loaded.config);
  return loaded;
}

LoadedConfig loadSimulationConfigFile(const std::string& path) {
  return loadSimulationConfig(loadYamlFile(path));
}

}  // namespace kane_sim
