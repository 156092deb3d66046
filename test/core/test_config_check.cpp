// What the loader cannot judge from the values alone (sim/config_check.h): an initial state the
// simulator cannot start from, and with rk4 a mechanism too stiff for the physics rate. Each error
// names the key and says what to change.
#include <algorithm>
#include <cmath>
#include <random>
#include <utility>

#include <gtest/gtest.h>

#include "kane_sim/analysis/stability.h"
#include "kane_sim/sim/config_check.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

YAML::Node defaultYaml() { return YAML::LoadFile(test::configPath("mechanism.yaml")); }

// Expects loadSimulationConfig(root) to throw a ConfigError for `key` whose message contains
// `text`, while loadConfig (which integrates nothing) accepts it.
void expectError(const YAML::Node& root, const std::string& key, const std::string& text) {
  EXPECT_NO_THROW(loadConfig(root)) << key;
  try {
    loadSimulationConfig(root);
    ADD_FAILURE() << "no error for " << key;
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.key(), key) << e.what();
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  }
}

// With contact on, the sliders must start at least the gap apart (slider 4 below slider 3).
TEST(ConfigCheck, ContactRefusesSlidersStartingWithinTheGap) {
  YAML::Node root = defaultYaml();
  root["contact"]["enabled"] = true;
  root["initial_state"]["q2"] = 0.9;  // x_B = 4 L cos(pi/6) = 0.866: 3.4 cm apart
  expectError(root, "initial_state", "closer than contact.gap 0.07 m");
  root["contact"]["enabled"] = false;
  EXPECT_NO_THROW(loadSimulationConfig(root));
}

// A damper rk4 cannot follow: c_C / M2 = 5000 /s at 1 kHz (h |lambda| = 5 > 2.78).
TEST(ConfigCheck, DampingTooStrongForRk4IsRefused) {
  YAML::Node root = defaultYaml();
  root["damping"]["slider4_joint"] = 4000.0;
  expectError(root, "simulation.physics_rate", "is too low for rk4 on this mechanism");
}

// Friction's hostile values. The loader names the key for a value outside its rule (negative,
// NaN, ±inf; v_s 0, 1e-300 or 1e308 outside [1e-9, 1e3]); a value within the rule that rk4
// cannot follow (F_C / v_s too stiff for 1 kHz: 1 N over v_s 1e-6 m/s on 0.8 kg, or a 1e308 N
// coefficient) is refused by the physics-rate check, which names the friction keys.
TEST(ConfigCheck, FrictionHostileValuesAreRefusedNamingTheKey) {
  const std::pair<const char*, const char*> refused_by_rule[] = {
      {"slider4_joint", "-1"},     {"slider4_joint", ".nan"},   {"crank_joint", ".inf"},
      {"coupler_joint", "-.inf"},  {"velocity_scale", "0"},     {"velocity_scale", "1e-300"},
      {"velocity_scale", "1e308"}, {"velocity_scale", "-0.01"}, {"velocity_scale", ".nan"},
      {"slider3_joint", "'text'"}};
  for (const auto& [key, value] : refused_by_rule) {
    YAML::Node root = defaultYaml();
    root["friction"][key] = YAML::Load(value);
    try {
      loadConfig(root);
      ADD_FAILURE() << "friction." << key << " " << value << " accepted";
    } catch (const ConfigError& e) {
      EXPECT_EQ(e.key(), std::string("friction.") + key) << e.what();
    }
  }
  for (const double coefficient : {1.0, 1e308}) {
    YAML::Node root = defaultYaml();
    root["friction"]["slider4_joint"] = coefficient;
    root["friction"]["velocity_scale"] = coefficient == 1.0 ? 1e-6 : 0.01;
    SCOPED_TRACE(coefficient);
    try {
      loadSimulationConfig(root);
      ADD_FAILURE() << "accepted";
    } catch (const ConfigError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("friction.slider4_joint"), std::string::npos) << what;
      if (coefficient == 1.0) {  // stiff: both friction's keys are what to change
        EXPECT_NE(what.find("friction.velocity_scale"), std::string::npos) << what;
      } else {  // beyond any mechanism's scale: the coefficient is the key to fix
        EXPECT_EQ(e.key(), "friction.slider4_joint") << what;
      }
    }
  }
  // dopri5 adapts its step, but not beyond 1e5 sub-steps a physics step: 1 N over v_s 1e-9 m/s
  // (a rate of 1.25e9 1/s) and a 1e308 N coefficient are refused at start-up, naming friction
  // (they once ran, and failed mid-run with a message that named neither).
  for (const auto& [coefficient, v_s] : {std::pair<double, double>{1.0, 1e-9}, {1e308, 0.01}}) {
    YAML::Node root = defaultYaml();
    root["simulation"]["integrator"] = "dopri5";
    root["friction"]["slider4_joint"] = coefficient;
    root["friction"]["velocity_scale"] = v_s;
    SCOPED_TRACE(coefficient);
    try {
      loadSimulationConfig(root);
      ADD_FAILURE() << "accepted";
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("friction.slider4_joint"), std::string::npos)
          << e.what();
    }
  }
  // What dopri5 can follow, slowly: 100 N over 1e-6 m/s.
  {
    YAML::Node root = defaultYaml();
    root["simulation"]["integrator"] = "dopri5";
    root["friction"]["slider4_joint"] = 100.0;
    root["friction"]["velocity_scale"] = 1e-6;
    EXPECT_NO_THROW(loadSimulationConfig(root));
  }
  // A v_s rk4 can follow: the same 1 N over 2e-3 m/s.
  YAML::Node root = defaultYaml();
  root["friction"]["slider4_joint"] = 1.0;
  root["friction"]["velocity_scale"] = 2e-3;
  EXPECT_NO_THROW(loadSimulationConfig(root));
}

// An initial speed that alone makes the motion too fast for the step (u1 = 1e6 rad/s: its
// centripetal terms) is named as the cause, with its value, and slowing it is the first remedy;
// the same mechanism at rest passes.
TEST(ConfigCheck, InitialSpeedsThatSetTheFastestRateAreNamed) {
  for (const char* integrator : {"rk4", "dopri5"}) {
    YAML::Node root = defaultYaml();
    root["simulation"]["integrator"] = integrator;
    root["initial_state"]["u1"] = integrator == std::string("rk4") ? 1e6 : 1e12;
    try {
      loadSimulationConfig(root);
      ADD_FAILURE() << integrator << ": no error";
    } catch (const ConfigError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("from the initial state's speeds (initial_state.u1 = 1e+"),
                std::string::npos)
          << what;
      EXPECT_NE(what.find("slower initial_state speeds, or "), std::string::npos) << what;
    }
  }
  YAML::Node root = defaultYaml();
  root["mechanism"]["spring_stiffness"] = 1e9;  // the mechanism, not its start, sets the rate
  try {
    loadSimulationConfig(root);
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("from spring_stiffness, the masses"), std::string::npos)
        << e.what();
    EXPECT_EQ(std::string(e.what()).find("initial_state"), std::string::npos) << e.what();
  }
}

// A finite initial state whose energy is not (V_g = -M2 g q2 overflows).
TEST(ConfigCheck, InitialStateWithNonFiniteEnergyIsRefused) {
  YAML::Node root = defaultYaml();
  root["initial_state"]["q2"] = 1e308;
  expectError(root, "initial_state", "gives a non-finite energy");
}

// A constant of the equations beyond the mechanism's scale (k = 1e308: u' overflows at a good
// initial state) is named as what to fix, not the initial state (dynparam set spring_stiffness
// 1e308 was refused naming initial_state); the crank's torsional spring likewise.
TEST(ConfigCheck, AnOverflowingConstantIsNamedNotTheInitialState) {
  for (const char* key : {"spring_stiffness", "crank_spring_stiffness"}) {
    YAML::Node root = defaultYaml();
    root["mechanism"][key] = 1e308;
    expectError(root, std::string("mechanism.") + key, "= 1e+308 is beyond the mechanism's scale");
  }
}

// The crank's torsional spring, attacked: every non-finite or negative stiffness and every
// non-finite rest angle is refused naming its key; a rest angle beyond the mechanism's scale is
// harmless while the spring is off and named once it is on.
TEST(ConfigCheck, TorsionalSpringHostileValuesAreRefusedNamingTheKey) {
  const std::pair<const char*, const char*> refused[] = {
      {"crank_spring_stiffness", "-1"},    {"crank_spring_stiffness", ".nan"},
      {"crank_spring_stiffness", ".inf"},  {"crank_spring_stiffness", "'stiff'"},
      {"crank_spring_rest_angle", ".nan"}, {"crank_spring_rest_angle", "-.inf"},
      {"crank_spring_rest_angle", "''"}};
  for (const auto& [key, value] : refused) {
    YAML::Node root = defaultYaml();
    root["mechanism"][key] = YAML::Load(value);
    try {
      loadConfig(root);
      ADD_FAILURE() << key << " " << value << " accepted";
    } catch (const ConfigError& e) {
      EXPECT_EQ(e.key(), std::string("mechanism.") + key) << e.what();
    }
  }
  YAML::Node root = defaultYaml();
  root["mechanism"]["crank_spring_rest_angle"] = 1e200;
  EXPECT_NO_THROW(loadSimulationConfig(root)) << "off: its rest plays no part";
  root["mechanism"]["crank_spring_stiffness"] = 5.0;
  expectError(root, "mechanism.crank_spring_rest_angle",
              "= 1e+200 is beyond the mechanism's scale");
}

// k = 1e9 N/m on the 0.8 kg slider: a mode near 43 000 rad/s, so rk4 at 1 kHz (ω h ≈ 43, far
// past its stability limit 2.78) would diverge within milliseconds. Refused at start-up with
// the limit and the fix; dopri5 or a fast enough rate are accepted.
TEST(ConfigCheck, StiffMechanismIsRefusedForRk4AtTooLowARate) {
  YAML::Node root = defaultYaml();
  root["mechanism"]["spring_stiffness"] = 1e9;
  expectError(root, "simulation.physics_rate",
              "use simulation.integrator dopri5 or a physics_rate of at least 18400 Hz");
}

TEST(ConfigCheck, StiffMechanismIsFineWithDopri5OrAFastEnoughRate) {
  YAML::Node root = defaultYaml();
  root["mechanism"]["spring_stiffness"] = 1e9;
  root["simulation"]["integrator"] = "dopri5";
  EXPECT_NO_THROW(loadSimulationConfig(root));
  root["simulation"]["integrator"] = "rk4";
  root["simulation"]["physics_rate"] = 20000;
  root["simulation"]["publish_rate"] = 100;
  EXPECT_NO_THROW(loadSimulationConfig(root));
}

// The check's shortcut (ratesWithin: a cheap upper bound of each sampled rate, the eigenvalues
// only where it does not settle) gives the scan's own answer, max(stiffest, initial) h <= limit,
// over a family of random mechanisms (masses, k over seven decades, dampers, friction and its
// velocity scale, moving starts) with the step a hair either side of each one's boundary and
// well inside it. A bound below a true rate would pass the step just beyond the boundary.
TEST(ConfigCheck, TheShortcutGivesTheScansAnswerEitherSideOfEveryBoundary) {
  std::mt19937 rng(11);
  const auto uniform = [&rng](double lo, double hi) {
    return std::uniform_real_distribution<double>(lo, hi)(rng);
  };
  const Config base = loadConfig(defaultYaml()).config;
  int settled_inside = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Config c = base;
    MechanismParameters& m = c.mechanism;
    m.rod_mass *= uniform(0.5, 2.0);
    m.slider3_mass *= uniform(0.5, 2.0);
    m.slider4_mass *= uniform(0.5, 2.0);
    m.spring_stiffness = std::pow(10.0, uniform(0.0, 7.0));
    if (trial % 2) m.damping.slider4_joint = uniform(0.0, 50.0);
    if (trial % 3 == 0) m.damping.crank_joint = uniform(0.0, 5.0);
    if (trial % 4 == 1) {
      m.friction.slider3_joint = uniform(0.0, 5.0);
      m.friction.velocity_scale = std::pow(10.0, uniform(-4.0, -1.0));
    }
    c.initial_state.q1 = uniform(-3.0, 3.0);
    c.initial_state.u1 = uniform(-20.0, 20.0);
    const MechanismModel model = mechanismModel(c);
    const double scan = stiffestConfiguration(model, c.initial_state).rate;
    const double exact = std::max(scan, fastestRate(model, c.initial_state, 0.0));
    ASSERT_TRUE(std::isfinite(exact)) << trial;
    for (double factor : {1.0 - 1e-9, 1.0 + 1e-9, 0.5, 0.1, 2.0}) {
      const double h = kRk4StabilityLimit / exact * factor;
      EXPECT_EQ(ratesWithin(model, c.initial_state, h, kRk4StabilityLimit),
                exact * h <= kRk4StabilityLimit)
          << "trial " << trial << " factor " << factor << " rate " << exact;
    }
    settled_inside +=
        ratesWithin(model, c.initial_state, 0.1 * kRk4StabilityLimit / exact, kRk4StabilityLimit);
  }
  EXPECT_EQ(settled_inside, 300);
}

TEST(ConfigCheck, TheShippedConfigsCanBeSimulated) {
  for (const char* file : {"mechanism.yaml", "textbook.yaml"})
    EXPECT_NO_THROW(loadSimulationConfigFile(test::configPath(file))) << file;
}

}  // namespace
}  // namespace kane_sim
