#include "kane_sim/identify/regressor.h"

#include <algorithm>
#include <stdexcept>

#include "kane_sim/config/parameter_schema.h"
#include "kane_sim/model/power_flow.h"

namespace kane_sim {
namespace {

// Fitted unless the caller names the parameters: all of them. (The rod inertia once followed m
// through the base's radius of gyration, and friction was fitted only when named: a rig whose
// rod or friction differed from the base then pushed its difference into the masses and the
// dampers unmarked. What the motion cannot tell apart is named and kept at the base instead.)
// Except the coupler's friction: it acts on the crank's rate alone, as the crank's does
// (omega2 = -omega1), apart only within friction's velocity scale of rest; fitted together the two
// trade off freely (one rig's least squares gave the coupler 11.5 N m). Named, it is fitted.
// And the crank's torsional spring: a rig has one only by design, and over a small swing its
// torque -k_t (q1 - q1_0) trades off against gravity's; named, it is fitted.
bool byDefault(const ParameterSpec& spec) {
  return spec.path() != "friction.coupler_joint" &&
         spec.path() != "mechanism.crank_spring_stiffness";
}

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// F*_r + F_r of `model` at (x, u') with the driver moment `torque` (eqs 12, 16, 18).
SpeedVector kaneResidual(const MechanismModel& model, const State& x, const SpeedVector& u_dot,
                         double torque) {
  const MechanismModel::Equations eq = model.equations(x, torque);
  return eq.inertiaForces(u_dot) + eq.active_forces;
}

// E = T + V_g + V_s and the non-conservative power (motor and dampers) of `model` at x.
void energyAndPower(const MechanismModel& model, const State& x, double torque, double* energy,
                    double* power) {
  const MechanismKinematics k = model.kinematics(x);
  *energy = model.energy(k, x).total();
  const LoadPowers p = loadPowers(model.loads(k, x, torque), x);
  *power = p[LoadName::kMotor] + p.dissipative();
}

MechanismModel modelOf(const Config& config, double rest_length) {
  return MechanismModel(config.mechanism, rest_length);
}

}  // namespace

const std::vector<IdentifiableParameter>& identifiableParameters() {
  static const std::vector<IdentifiableParameter> all = [] {
    std::vector<IdentifiableParameter> list;
    for (const ParameterSpec& spec : parameterSchema())
      if (identifiable(spec))
        list.push_back({spec.path(), spec.unit, spec.symbol, byDefault(spec)});
    list.push_back({kSpringRestLength, "m", "s0", false});
    list.push_back({kTorqueOffset, "N m", "", true});
    return list;
  }();
  return all;
}

namespace {

void checkKnown(const std::string& name) {
  const auto& all = identifiableParameters();
  if (std::none_of(all.begin(), all.end(), [&](const auto& p) { return p.name == name; })) {
    std::string valid;
    for (const auto& p : all) valid += (valid.empty() ? "" : ", ") + p.name;
    throw std::invalid_argument("params: '" + name + "' is not an identifiable parameter (" +
                                valid + ")");
  }
}

}  // namespace

void checkIdentifiedNames(const std::vector<std::string>& names) {
  std::vector<std::string> seen;
  for (const std::string& name : names) {
    checkKnown(name);
    if (contains(seen, name)) throw std::invalid_argument("params: '" + name + "' named twice");
    seen.push_back(name);
  }
  if (contains(names, kSpringRestLength) && !contains(names, "mechanism.spring_stiffness"))
    throw std::invalid_argument(
        "params: spring_rest_length is identified through k s0: name mechanism.spring_stiffness "
        "too");
}

Regressor::Regressor(const Config& base, const std::vector<std::string>& identified)
    : names_(identified), known_(modelOf(base, mechanismModel(base).springRestLength())) {
  checkIdentifiedNames(identified);
  const double rest = mechanismModel(base).springRestLength();
  const bool preload = contains(names_, kSpringRestLength);
  // The rod's radius of gyration squared, I / m: the rod's shape, measured with L. When the
  // inertia is not identified it follows m through it (as the loader's default m (2L)^2 / 12).
  const bool inertia_free = contains(names_, "mechanism.rod_inertia");
  const double gyration_sq = base.mechanism.rod_inertia / base.mechanism.rod_mass;

  Config known = base, zero = base;
  known.mechanism.motor.no_load_speed = 0.0;  // the data's torque is the delivered one
  zero.mechanism.motor.no_load_speed = 0.0;
  for (const ParameterSpec& spec : parameterSchema()) {
    if (!identifiable(spec)) continue;
    spec.field.number(zero) = 0.0;
    if (contains(names_, spec.path())) spec.field.number(known) = 0.0;
  }
  if (contains(names_, "mechanism.rod_mass") && !inertia_free) known.mechanism.rod_inertia = 0.0;
  known_ = modelOf(known, rest);

  for (const std::string& name : names_) {
    Config on = zero, off = zero;
    double on_rest = rest, off_rest = rest, command = 0.0;
    if (name == kTorqueOffset) {
      command = 1.0;
    } else if (name == kSpringRestLength) {  // the preload k s0: (k = 1, s0 = 1) - (k = 1, s0 = 0)
      on.mechanism.spring_stiffness = off.mechanism.spring_stiffness = 1.0;
      on_rest = 1.0;
      off_rest = 0.0;
    } else {
      const auto dot = name.find('.');
      findParameter(name.substr(0, dot), name.substr(dot + 1))->field.number(on) = 1.0;
      if (name == "mechanism.rod_mass" && !inertia_free) on.mechanism.rod_inertia = gyration_sq;
      if (name == "mechanism.spring_stiffness" && preload) on_rest = 0.0;
    }
    columns_.push_back({modelOf(on, on_rest), modelOf(off, off_rest), command});
  }
}

void Regressor::equationRows(const State& x, const SpeedVector& u_dot, double torque,
                             Eigen::Ref<Eigen::Matrix<double, kNumSpeeds, Eigen::Dynamic>> y,
                             Eigen::Ref<SpeedVector> y0) const {
  for (int j = 0; j < size(); ++j) {
    const Column& c = columns_[j];
    y.col(j) = kaneResidual(c.on, x, u_dot, c.command_on) - kaneResidual(c.off, x, u_dot, 0.0);
  }
  y0 = kaneResidual(known_, x, u_dot, torque);
}

void Regressor::energyRow(const State& x, double torque, Eigen::Ref<Eigen::RowVectorXd> energy,
                          Eigen::Ref<Eigen::RowVectorXd> power, double* e0, double* p0) const {
  for (int j = 0; j < size(); ++j) {
    const Column& c = columns_[j];
    double e_on, p_on, e_off, p_off;
    energyAndPower(c.on, x, c.command_on, &e_on, &p_on);
    energyAndPower(c.off, x, 0.0, &e_off, &p_off);
    energy[j] = e_on - e_off;
    power[j] = p_on - p_off;
  }
  energyAndPower(known_, x, torque, e0, p0);
}

double identificationBaseValue(const Config& config, const std::string& name) {
  checkKnown(name);
  if (name == kTorqueOffset) return 0.0;
  if (name == kSpringRestLength) return mechanismModel(config).springRestLength();
  const auto dot = name.find('.');
  return numericValue(*findParameter(name.substr(0, dot), name.substr(dot + 1)), config);
}

}  // namespace kane_sim
