// The reaction forces from Kane's method with auxiliary speeds (model/constraint_forces.h) against
// Newton-Euler free-body balances of each body, written out here by hand from the geometry
// (doc/theory/mechanism.md), and the power flow (model/power_flow.h) against the work-energy
// theorem.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "kane_sim/model/constraint_forces.h"
#include "kane_sim/model/power_flow.h"
#include "kane_sim/sim/config_check.h"
#include "kane_sim/sim/sim_driver.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

struct Vec2 {
  double x, y;
};
double cross(Vec2 r, Vec2 f) { return r.x * f.y - r.y * f.x; }  // (r × F) · k

// Residuals of m a = Σ F and I α = Σ M (about the mass center) for the four bodies: 10 numbers
// that are zero when the reactions are right.
std::vector<double> newtonEulerResiduals(const MechanismModel& model, const State& x,
                                         const SpeedVector& u_dot, double motor_torque,
                                         double contact_force, const ConstraintForces& f) {
  const MechanismParameters& p = model.parameters();
  const double L = p.rod_half_length, m = p.rod_mass, g = p.gravity, I = p.rod_inertia;
  const double c = std::cos(x.q1), s = std::sin(x.q1), u = x.u1, ud = u_dot[0];
  const Vec2 O{0, 0}, A{2 * L * c, 2 * L * s}, B{4 * L * c, 0}, C1{L * c, L * s},
      C2{3 * L * c, L * s};
  const Vec2 a1{L * (-s * ud - c * u * u), L * (c * ud - s * u * u)};
  const Vec2 a2{L * (-3 * s * ud - 3 * c * u * u), L * (c * ud - s * u * u)};
  const double aB = -4 * L * (s * ud + c * u * u), aC = u_dot[1];
  const double vB = -4 * L * s * u;
  const double e = model.springElongation(model.geometry(x.q1, x.q2));
  const double cO = p.damping.crank_joint, cA = p.damping.coupler_joint;
  // Coulomb friction, smoothed: F_c tanh(v / v_s) against each joint's rate.
  const JointFriction& fr = p.friction;
  const auto coulomb = [&fr](double force, double v) {
    return force * std::tanh(v / fr.velocity_scale);
  };
  // -c_A (w2 - w1) - F_A tanh((w2 - w1) / v_s), w2 = -u1
  const double coupler_on_rod2 = -cA * (-u - u) - coulomb(fr.coupler_joint, -u - u);
  const Vec2 RO{f.pin_o.x(), f.pin_o.y()}, RA{f.pin_a.x(), f.pin_a.y()},
      RB{f.pin_b.x(), f.pin_b.y()};
  const auto rel = [](Vec2 a, Vec2 b) { return Vec2{a.x - b.x, a.y - b.y}; };
  return {
      // rod 1: G1 + R_O - R_A; motor, crank damper, the coupler damper's reaction
      m * g + RO.x - RA.x - m * a1.x,
      RO.y - RA.y - m * a1.y,
      motor_torque - cO * u - coulomb(fr.crank_joint, u) - coupler_on_rod2 + cross(rel(O, C1), RO) +
          cross(rel(A, C1), Vec2{-RA.x, -RA.y}) - I * ud,
      // rod 2: G2 + R_A - R_B
      m * g + RA.x - RB.x - m * a2.x,
      RA.y - RB.y - m * a2.y,
      coupler_on_rod2 + cross(rel(A, C2), RA) + cross(rel(B, C2), Vec2{-RB.x, -RB.y}) - I * -ud,
      // slider 3: G3 - k e + dampers + R_B + N3 j - N (contact)
      p.slider3_mass * g - p.spring_stiffness * e - p.damping.slider3_joint * vB +
          p.damping.spring * (x.u2 - vB) - coulomb(fr.slider3_joint, vB) + RB.x - contact_force -
          p.slider3_mass * aB,
      RB.y + f.rail_slider3,
      // slider 4: G4 + k e + dampers + N4 j + N (contact)
      p.slider4_mass * g + p.spring_stiffness * e - p.damping.slider4_joint * x.u2 -
          p.damping.spring * (x.u2 - vB) - coulomb(fr.slider4_joint, x.u2) + contact_force -
          p.slider4_mass * aC,
      f.rail_slider4,
  };
}

Config dampedConfig() {
  Config config = test::defaultConfig();
  config.mechanism.damping = {0.3, 0.2, 1.5, 2.5, 0.8};   // c_O, c_A, c_B, c_C, c_S
  config.mechanism.friction = {0.2, 0.1, 1.0, 0.8, 0.3};  // F_O, F_A, F_B, F_C, v_s
  return config;
}

// Gravity reversed (towards -x, up the rail) and no spring: slider 4 falls onto slider 3, bounces
// and comes to rest on it (as in test_physics_options' resting-contact cases).
Config fallingUpConfig(double restitution) {
  Config config = test::defaultConfig();
  config.mechanism.contact = SliderContact{true, 0.07, restitution};
  config.mechanism.gravity = -9.81;
  config.mechanism.spring_stiffness = 0.0;
  return config;
}

// Random states over several crank turns (away from the toggle at cos q1 = 0, where the rail
// force is 1 / cos q1), random torques, with every damper on.
TEST(ConstraintForces, BalanceEveryBodyByNewtonEuler) {
  const MechanismModel model = mechanismModel(dampedConfig());
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> angle(-10, 10), speed(-20, 20), torque(-30, 30),
      stretch(-0.2, 0.2);
  int checked = 0;
  for (int i = 0; i < 500; ++i) {
    State x{angle(rng), 0, speed(rng), speed(rng)};
    if (std::abs(std::cos(x.q1)) < 0.05) continue;
    x.q2 = model.withSpringAtRest(x).q2 + stretch(rng);
    const double m_m = torque(rng);
    const SpeedVector u_dot = model.accelerations(x, m_m);
    const ConstraintForces f = constraintForces(model, x, u_dot, m_m, 0.0);
    ASSERT_TRUE(f.determinate);
    // Scale: the largest force or moment arm x force in play (~1e2 N); the balance holds to
    // rounding in the 8x8 solve (~1e-14 relative), 1e-9 leaves room for the toggle's growth.
    const double scale = 1 + f.pin_o.norm() + f.pin_a.norm() + f.pin_b.norm() +
                         std::abs(f.rail_slider3) + std::abs(f.spring);
    const std::vector<double> r = newtonEulerResiduals(model, x, u_dot, m_m, 0.0, f);
    for (size_t k = 0; k < r.size(); ++k)
      ASSERT_NEAR(r[k], 0.0, 1e-9 * scale) << "residual " << k << " at q1 = " << x.q1;
    EXPECT_NEAR(
        f.spring,
        model.parameters().spring_stiffness * model.springElongation(model.geometry(x.q1, x.q2)),
        1e-12);
    EXPECT_NEAR(f.rail_slider4, 0.0, 1e-12 * scale);  // slider 4's loads are all along the rail
    ++checked;
  }
  EXPECT_GT(checked, 450);
}

// Statics: at u = 0 under the holding moment u' = 0, and with the spring unstretched the ground
// holds up (along -x) the whole weight of the rods and slider 3 at pin O.
TEST(ConstraintForces, HoldingStillTheGroundCarriesTheWeightBetweenPinAndRail) {
  Config config = test::defaultConfig();
  const MechanismModel model = mechanismModel(config);
  const State x{0.7, model.withSpringAtRest(State{0.7, 0, 0, 0}).q2, 0, 0};
  const double hold = model.holdingMoment(x);
  const SpeedVector u_dot = model.accelerations(x, hold);
  ASSERT_NEAR(u_dot[0], 0.0, 1e-12);
  const ConstraintForces f = constraintForces(model, x, u_dot, hold, 0.0);
  const MechanismParameters& p = model.parameters();
  // Vertical (x) balance of rods and slider 3 with the spring unstretched: O_x carries it all
  // (the rails push only along y): O_x = -(2 m + M1) g. Horizontal: O_y + N3 = 0.
  EXPECT_NEAR(f.pin_o.x(), -(2 * p.rod_mass + p.slider3_mass) * p.gravity, 1e-10);
  EXPECT_NEAR(f.pin_o.y() + f.rail_slider3, 0.0, 1e-10);
  EXPECT_NEAR(f.spring, 0.0, 1e-12);
  // Slider 3 hangs on rod 2: B_x = -M1 g.
  EXPECT_NEAR(f.pin_b.x(), -p.slider3_mass * p.gravity, 1e-10);
}

// At q1 = 90° B sits on O and rod 2 is square to the rail: O_y and N3 act along one line at one
// point, the constraints cannot tell them apart. The answer is flagged and stays finite.
TEST(ConstraintForces, TogglePointIsFlaggedAndFinite) {
  const MechanismModel model = mechanismModel(test::defaultConfig());
  for (double q1 : {M_PI / 2, -M_PI / 2, 3 * M_PI / 2}) {
    const State x{q1, 1.0, 2.0, 0.0};
    const ConstraintForces f = constraintForces(model, x, model.accelerations(x, 1.0), 1.0, 0.0);
    EXPECT_FALSE(f.determinate) << q1;
    EXPECT_TRUE(f.allFinite()) << q1;
  }
  const State near{M_PI / 2 - 1e-3, 1.0, 2.0, 0.0};
  EXPECT_TRUE(constraintForces(model, near, model.accelerations(near, 1.0), 1.0, 0.0).determinate);
}

// Resting contact: the contact force is one more load on both sliders; the balance still holds.
TEST(ConstraintForces, BalanceWithTheSlidersRestingOnEachOther) {
  const MechanismModel model = mechanismModel(fallingUpConfig(0.5));
  const State x = model.onContact(State{0.4, 0, 0.5, 0});
  const RestingContact held = model.restingContact(x, model.accelerations(x, 2.0), 2.0);
  ASSERT_GT(held.force, 0.0);
  const ConstraintForces f = constraintForces(model, x, held.u_dot, 2.0, held.force);
  for (double r : newtonEulerResiduals(model, x, held.u_dot, 2.0, held.force, f))
    EXPECT_NEAR(r, 0.0, 1e-9 * (1 + f.pin_o.norm() + held.force));
}

// Σ load powers = dT/dt (Kane's equations dotted with u), and each load that declares a
// potential energy (gravity, the spring, the crank's torsional spring: LoadInfo::energy_column)
// has the power -dV/dt: a conservative load whose energy is left out or wrong fails here.
// Every other load is dissipative (power < 0), the motor, or the contact. Derivatives along the
// motion x' = (u, u') by central differences, h = 1e-6 s (truncation ~h² |T'''| ~ 1e-10 J/s,
// rounding ~1e-16 T / h ~ 1e-9 J/s).
TEST(PowerFlow, LoadPowersSumToTheKineticEnergysRate) {
  Config config = dampedConfig();
  config.mechanism.crank_spring_stiffness = 7.0;  // N m/rad
  config.mechanism.crank_spring_rest_angle = 0.3;
  const MechanismModel model = mechanismModel(config);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> angle(-4, 4), speed(-10, 10), torque(-20, 20);
  const double h = 1e-6;
  for (int i = 0; i < 200; ++i) {
    const State x{angle(rng), 1.0 + 0.1 * angle(rng), speed(rng), speed(rng)};
    const double m_m = torque(rng);
    const SpeedVector u_dot = model.accelerations(x, m_m);
    const auto along = [&](double dt) {
      return State{x.q1 + dt * x.u1, x.q2 + dt * x.u2, x.u1 + dt * u_dot[0], x.u2 + dt * u_dot[1]};
    };
    const EnergyTerms plus = model.energy(along(h)), minus = model.energy(along(-h));
    const MechanismKinematics k = model.kinematics(x);
    const LoadPowers p = loadPowers(model.loads(k, x, m_m), x);
    double size = 1.0;
    for (double power : p.by_name) size += std::abs(power);
    const double tol = 1e-7 * size;
    EXPECT_NEAR(p.total(), (plus.kinetic - minus.kinetic) / (2 * h), tol);
    for (int n = 0; n < kNumLoadNames; ++n) {
      const LoadInfo& load = kLoadInfo[n];
      if (load.energy_column) {
        EXPECT_NEAR(p.by_name[n], -(plus.potential[n] - minus.potential[n]) / (2 * h), tol)
            << load.name << ": its power is not -d(" << load.energy_column << ")/dt";
        EXPECT_NE(p.by_name[n], 0.0) << load.name << " is on in this config";
      } else if (load.dissipative) {
        EXPECT_LT(p.by_name[n], 0.0) << load.name << " takes power out";
      } else {
        EXPECT_TRUE(load.kind == LoadKind::kMotor || load.kind == LoadKind::kContact)
            << load.name << " is neither conservative (no energy declared) nor dissipative";
      }
    }
    EXPECT_NEAR(p[LoadName::kMotor], m_m * x.u1, 1e-12 * (1 + std::abs(m_m * x.u1)));
    double body_sum = 0;
    for (double t : bodyKineticEnergies(k, x)) body_sum += t;
    EXPECT_NEAR(body_sum, model.energy(x).kinetic, 1e-12 * (1 + body_sum));
  }
}

// A load that is off reports 0 W, not -0 W (what `rostopic echo` would print as "-0.0").
TEST(PowerFlow, LoadsThatAreOffReportPlusZero) {
  const MechanismModel model = mechanismModel(test::defaultConfig());  // no dampers
  const State x{0.5, 1.2, -3.0, -1.0};                                 // negative speeds
  const LoadPowers p = loadPowers(model.loads(model.kinematics(x), x, 0.0), x);
  for (int n = 0; n < kNumLoadNames; ++n) EXPECT_FALSE(std::signbit(p.by_name[n])) << n;
}

// The simulator's snapshot: contact on, no dampers: every joule dissipated is an impact's, and
// impact_energy books exactly that (then 0 again after a reset); while resting, the contact
// force does no work.
TEST(PowerFlow, ImpactEnergyIsTheDissipatedEnergyWithoutDampers) {
  SimDriver driver(fallingUpConfig(0.2), nullptr);
  bool rested = false;
  for (int i = 0; i < 4000; ++i) {
    ASSERT_TRUE(driver.step());
    const Snapshot s = driver.snapshot();
    ASSERT_TRUE(s.allFinite());
    if (s.resting_contact) {
      rested = true;
      EXPECT_NEAR(s.load_powers[LoadName::kContact], 0.0, 1e-9 * (1 + s.contact_force));
    }
  }
  const Snapshot s = driver.snapshot();
  ASSERT_GT(s.contact_impacts, 0u);
  EXPECT_GT(s.impact_energy, 0.0);
  EXPECT_EQ(s.impact_energy, s.dissipated_energy);
  EXPECT_TRUE(rested);
  driver.reset();
  EXPECT_EQ(driver.snapshot().impact_energy, 0.0);
}

}  // namespace
}  // namespace kane_sim
