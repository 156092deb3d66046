// The generated equations (model/generated_equations.h, the integrators' default) against the
// generic Kane assembly, the oracle: the same rates at random states and random parameters for
// every option, and the same trajectories through the Simulator for 20 s.
#include <cmath>
#include <cstring>
#include <iostream>
#include <random>
#include <set>
#include <string>

#include <gtest/gtest.h>
#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>

#include "kane_sim/config/parameter_schema.h"
#include "kane_sim/model/generated_mechanism.h"
#include "kane_sim/model/rk4_step.h"
#include "kane_sim/sim/simulator.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

// One option at a time and all together, each with a motion that exercises it: a held torque
// the gravity moment can balance (regular motion), slider 4 thrown at slider 3 for contact.
struct OptionCase {
  const char* name;
  bool damping;
  bool motor_line;
  bool contact;
  bool friction;
  double torque;  // [N m] held for the trajectory test
  double u20;     // [m/s] slider 4's initial speed in the trajectory test (< 0: towards slider 3)
  double agreement;  // of the two paths' trajectories after 20 s, relative to 1 + |value|
};

// Agreement: 1e-12 for smooth motion (measured 6e-14 ... 9e-14, one damped impact included).
// Repeated undamped bounces are the exception: at each impact a difference δ in the state moves
// the touch instant by δ/v_approach and the post-impact state by the jump in acceleration times
// that, so differences grow by orders of magnitude over five impacts - measured 2.6e-12 and
// 1.3e-10 for two algebraically equal generated kernels (the sensitivity is the bounces', not
// the kernel's); 1e-9. Every option together: the states agree to 4e-14, the motor's work to
// 2e-12 of 1 + |W| (measured; the line's torque, the friction's tanh and an impact); 1e-11.
const OptionCase kCases[] = {{"textbook", false, false, false, false, 10.0, 0.0, 1e-12},
                             {"damping", true, false, false, false, 10.0, 0.0, 1e-12},
                             {"motor_line", false, true, false, false, 10.0, 0.0, 1e-12},
                             {"contact", false, false, true, false, 10.0, -6.0, 1e-9},
                             {"friction", false, false, false, true, 10.0, 0.0, 1e-12},
                             {"all", true, true, true, true, 10.0, -6.0, 1e-11}};

Config withOptions(Config c, const OptionCase& options) {
  if (options.damping) c.mechanism.damping = JointDamping{0.05, 0.02, 0.5, 0.5, 0.3};
  // w0 = 5 rad/s: the line limits the drive at the speeds of these motions.
  if (options.motor_line) c.mechanism.motor = MotorLine{50.0, 5.0};
  if (options.contact) c.mechanism.contact = SliderContact{true, 0.07, 0.5};
  // v_s 0.05: the tanh's knee is crossed at every reversal of these motions.
  if (options.friction) c.mechanism.friction = JointFriction{0.05, 0.02, 0.8, 0.6, 0.05};
  return c;
}

// The size of the terms each rate u_r' sums, Σ|term| / M_rr: two summation orders differ by
// rounding relative to this, not to the (possibly much smaller) sum. Every load's share of F_r
// through its partial velocities, the spring's with k (|q2| + |s0| + 4L) since the generated
// code expands e = s0 + 4L cos q1 - q2, and the velocity-product terms of F*_r.
SpeedVector termSizes(const MechanismModel& model, const State& x, double command) {
  const MechanismKinematics k = model.kinematics(x);
  const MechanismLoads l = model.loads(k, x, command);
  const MechanismParameters& p = model.parameters();
  SpeedVector sizes = SpeedVector::Zero();
  const double spring_size =
      p.spring_stiffness *
      (std::abs(x.q2) + std::abs(model.springRestLength()) + 4 * p.rod_half_length);
  for (const MechanismLoad& entry : l) {
    if (entry.name == LoadName::kSpring) {
      sizes += spring_size * entry.load.partials.row(0).transpose().cwiseAbs();
    } else {
      MechanismModel::Equations share;
      kane::addActiveForces(entry.load, &share);
      sizes += share.active_forces.cwiseAbs();
    }
  }
  const MechanismModel::Equations eq = MechanismModel::equations(k, l, x);
  sizes += eq.inertia_remainder.cwiseAbs();
  return sizes.cwiseQuotient(eq.mass_matrix.diagonal());
}

class GeneratedEquations : public ::testing::TestWithParam<OptionCase> {};

// Both paths compute the same sums in different orders, so they differ by rounding: 1e-13
// relative to the terms' size is ~500 ulp. Random parameters too (the generated code takes them
// at runtime), from 1/10 to 10 times the shipped ones, states over several turns and speeds
// well beyond the usual ones. q' = u and W' = M_m u1 must agree exactly.
TEST_P(GeneratedEquations, RatesMatchTheGenericAssemblyAtRandomStates) {
  const Config shipped = withOptions(test::defaultConfig(), GetParam());
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> scale_exp(-1.0, 1.0), angle(-10.0, 10.0),
      position(-2.0, 2.0), speed(-60.0, 60.0), torque(-50.0, 50.0), unit(0.0, 1.0);
  auto scaled = [&](double v) { return v * std::pow(10.0, scale_exp(rng)); };
  double worst = 0.0;
  for (int trial = 0; trial < 2000; ++trial) {
    Config drawn = shipped;
    MechanismParameters& p = drawn.mechanism;
    // Every constant of the equations the schema declares, by its role (a new parameter is
    // drawn here without editing this test): the masses, L, g and the stiffnesses from 1/10 to
    // 10 times the shipped ones (one that is 0 there, as the crank's torsional spring, on or off
    // at random); every resistance on or off at random, so that every variant of the generated
    // rates is compared; and the shape of the laws (friction's v_s, the spring's rest angle)
    // from 1/10 to 10 times its default.
    for (ParameterRole role : {ParameterRole::kInertial, ParameterRole::kGeometric,
                               ParameterRole::kGravity, ParameterRole::kStiffness})
      for (const ParameterSpec* spec : parametersOfRole(role)) {
        double& v = spec->field.number(drawn);
        v = v != 0.0 ? scaled(v) : unit(rng) < 0.3 ? 0.0 : 10 * unit(rng);
      }
    for (const ParameterSpec* spec : parametersOfRole(ParameterRole::kDissipative))
      spec->field.number(drawn) = unit(rng) < 0.3 ? 0.0 : 10 * unit(rng);
    for (const ParameterSpec* spec : parametersOfRole(ParameterRole::kLoadShape))
      spec->field.number(drawn) = scaled(std::max(spec->field.number(drawn), 0.05));
    const MechanismModel generic(p, position(rng));
    const GeneratedMechanism generated(generic);
    const State x{angle(rng), position(rng), speed(rng), speed(rng)};
    const double command = torque(rng);

    const OdeState want = generic.stateDerivative(x, command);
    const OdeState got = generated.stateDerivative(x, command);
    for (int i : {0, 1, 4}) EXPECT_EQ(got[i], want[i]) << "component " << i;
    const SpeedVector sizes = termSizes(generic, x, command);
    // D' = Σ c (joint rate)^2, all terms positive: relative to itself.
    const double scales[3] = {sizes[0], sizes[1], std::abs(want[5])};
    for (int j = 0; j < 3; ++j) {
      const int i = j == 2 ? 5 : 2 + j;
      const double error = std::abs(got[i] - want[i]);
      worst = std::max(worst, error / std::max(scales[j], 1e-300));
      ASSERT_LE(error, 1e-13 * scales[j])
          << GetParam().name << " component " << i << " trial " << trial << ": generated " << got[i]
          << " generic " << want[i] << " term size " << scales[j];
    }
  }
  std::cout << GetParam().name << ": worst difference / term size " << worst << "\n";
}

// The two paths through the Simulator, each by rk4 at 1 kHz: after 20 s of the case's motion
// the states agree to the case's `agreement` (relative to 1 + |value|), W and D too. Regular
// motions only: where the motion is chaotic (the crank spun over the top by a strong drive) any two
// summation orders part exponentially, and no tolerance would be meaningful.
TEST_P(GeneratedEquations, TrajectoriesOfBothPathsAgreeOver20Seconds) {
  Config c = withOptions(test::defaultConfig(), GetParam());
  c.initial_state.u2 = GetParam().u20;
  c.simulation.equations = EquationsSource::kGenerated;
  Simulator generated(c);
  c.simulation.equations = EquationsSource::kGeneric;
  Simulator generic(c);
  ASSERT_EQ(generated.equations(), EquationsSource::kGenerated);
  ASSERT_TRUE(generated.setTorque(GetParam().torque).ok);
  ASSERT_TRUE(generic.setTorque(GetParam().torque).ok);
  double worst = 0.0;
  for (int i = 0; i < 20000; ++i) {
    ASSERT_TRUE(generated.step().ok);
    ASSERT_TRUE(generic.step().ok);
    const State& a = generated.state();
    const State& b = generic.state();
    worst = std::max({worst, std::abs(a.q1 - b.q1) / (1 + std::abs(b.q1)),
                      std::abs(a.q2 - b.q2) / (1 + std::abs(b.q2)),
                      std::abs(a.u1 - b.u1) / (1 + std::abs(b.u1)),
                      std::abs(a.u2 - b.u2) / (1 + std::abs(b.u2))});
  }
  std::cout << GetParam().name << ": worst state difference over 20 s " << worst << ", "
            << generic.contactImpacts() << " impacts, W " << generic.motorWork() << " J, D "
            << generic.dissipatedEnergy() << " J\n";
  const double tolerance = GetParam().agreement;
  EXPECT_LE(worst, tolerance);
  if (GetParam().contact) {
    EXPECT_GT(generic.contactImpacts(), 0u) << "the case hit nothing";
  }
  EXPECT_EQ(generated.contactImpacts(), generic.contactImpacts());
  EXPECT_EQ(generated.sliderCrossings(), generic.sliderCrossings());
  EXPECT_NEAR(generated.motorWork(), generic.motorWork(),
              tolerance * (1 + std::abs(generic.motorWork())));
  EXPECT_NEAR(generated.dissipatedEnergy(), generic.dissipatedEnergy(),
              tolerance * (1 + generic.dissipatedEnergy()));
}

INSTANTIATE_TEST_SUITE_P(EveryOption, GeneratedEquations, ::testing::ValuesIn(kCases),
                         [](const auto& info) { return std::string(info.param.name); });

// The default is the generated path; the config key selects either by name.
TEST(EquationsSetting, DefaultIsGeneratedAndTheKeyIsRead) {
  EXPECT_EQ(test::defaultConfig().simulation.equations, EquationsSource::kGenerated);
  EXPECT_EQ(parseEquationsName("generic", "simulation.equations"), EquationsSource::kGeneric);
  EXPECT_EQ(parseEquationsName("generated", "simulation.equations"), EquationsSource::kGenerated);
  EXPECT_THROW(parseEquationsName("fast", "simulation.equations"), ConfigError);
}

}  // namespace
}  // namespace kane_sim

namespace kane_sim {
namespace {

// Every physical parameter of the schema (each row the equations hold by its role: masses, L,
// k, g, every resistance, the shape of their laws; and the motor line's no-load speed) changes
// the rates on both paths, one at a time: a field left out of MechanismParameters' fields()
// (equality), of the generated constants or of the variant choice (a damper once ran the
// undamped kernel) fails here. Rows are chosen by role, so a new section is not skipped; and
// every constant of the generated equations but the rest length (the initial state's) must be
// some row's. Contact's parameters act through impacts between steps, not through the rates.
TEST(EveryParameter, ChangesTheRatesOnBothPaths) {
  const State x{0.7, 1.2, 1.5, -0.4};
  const double torque = 7.0;
  const auto rates = [&](const Config& c) {
    const MechanismModel model = mechanismModel(c);
    return std::make_pair(GeneratedMechanism(model).stateDerivative(x, torque),
                          model.stateDerivative(x, torque));
  };
  std::set<std::string> symbols;
  for (const ParameterSpec& p : parameterSchema()) {
    const bool physical = inEquations(p.role) || p.role == ParameterRole::kDrive;
    if (!physical || !p.field.number) continue;
    SCOPED_TRACE(p.path());
    Config base = test::defaultConfig();
    // A law's shape changes nothing while its load is off, nor where it has saturated (tanh of
    // 1.5 / 0.01 is 1 to the bit): every resistance on, and the shape at the state's speeds.
    if (p.role == ParameterRole::kLoadShape) {
      for (ParameterRole role : {ParameterRole::kDissipative, ParameterRole::kStiffness})
        for (const ParameterSpec* r : parametersOfRole(role)) r->field.number(base) = 0.5;
      p.field.number(base) = 1.0;
    }
    Config changed = base;
    double& value = p.field.number(changed);
    value = value == 0.0 ? 0.7 : value * 1.3;
    EXPECT_FALSE(changed.mechanism == base.mechanism) << "equality misses it";
    const auto before = rates(base);
    const auto after = rates(changed);
    const auto differs = [](const OdeState& a, const OdeState& b) {
      return a[2] != b[2] || a[3] != b[3] || a[5] != b[5];
    };
    EXPECT_TRUE(differs(after.first, before.first)) << "the generated equations ignore it";
    EXPECT_TRUE(differs(after.second, before.second)) << "the generic assembly ignores it";
    EXPECT_NEAR(after.first[2], after.second[2], 1e-9 * (1 + std::abs(after.second[2])));
    if (*p.equation_symbol) {
      EXPECT_TRUE(symbols.insert(p.equation_symbol).second) << "twice";
    }
  }
  std::set<std::string> constants(std::begin(generated::kConstantSymbols),
                                  std::end(generated::kConstantSymbols));
  constants.erase("s0");  // x_C0 - x_B0, from the initial state
  EXPECT_EQ(symbols, constants) << "a constant of the generated equations no schema row sets";
}

// The rk4 step every path takes (model/rk4_step.h) is odeint's runge_kutta4, bit for bit: at
// random states, parameters, resistances and step sizes from 1e-5 s to 0.1 s, the generated
// equations stepped by both. (odeint adds its zero coefficients' terms, a signed zero; they
// differ only for a component of exactly -0, which no state here has.)
TEST(Rk4Step, IsOdeintsRungeKutta4BitForBit) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> scale_exp(-1.0, 1.0), angle(-10.0, 10.0),
      position(-2.0, 2.0), speed(-30.0, 30.0), torque(-50.0, 50.0), unit(0.0, 1.0),
      step_exp(-5.0, -1.0);
  boost::numeric::odeint::runge_kutta4<OdeState> odeint_rk4;
  int differing = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    Config drawn = test::defaultConfig();
    MechanismParameters& p = drawn.mechanism;
    for (double* v : {&p.rod_mass, &p.slider3_mass, &p.slider4_mass, &p.spring_stiffness})
      *v *= std::pow(10.0, scale_exp(rng));
    for (const ParameterSpec* spec : parametersOfRole(ParameterRole::kDissipative))
      spec->field.number(drawn) = unit(rng) < 0.5 ? 0.0 : unit(rng);
    const GeneratedMechanism generated(MechanismModel(p, position(rng)));
    const double command = torque(rng), h = std::pow(10.0, step_exp(rng));
    const auto f = [&](const OdeState& x, OdeState& dxdt) {
      dxdt = generated.stateDerivative(fromOdeState(x), command);
    };
    OdeState ours =
        toOdeState({angle(rng), position(rng), speed(rng), speed(rng)}, unit(rng), unit(rng));
    OdeState theirs = ours;
    rk4Step(f, ours, h);
    odeint_rk4.do_step([&](const OdeState& x, OdeState& dxdt, double) { f(x, dxdt); }, theirs, 0.0,
                       h);
    for (int i = 0; i < 6; ++i)
      if (std::memcmp(&ours[i], &theirs[i], sizeof(double)) != 0) ++differing;
  }
  EXPECT_EQ(differing, 0) << "components differing from odeint's runge_kutta4";
}

}  // namespace
}  // namespace kane_sim
