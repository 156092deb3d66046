// The generic Kane assembly against the textbook's printed results, eqs (13), (15) and (17),
// and the generated equations against the u' those results give.
//
// With the textbook inertia (I1z = I2z = m L^2/12, the textbook's script) eqs (13) and F_1 of (17)
// hold as printed (13 up to the truncated constant 6.1666). Two printed results are wrong; the
// tests below show by how much and check the corrected form:
//  - eq (17), F_2: gravity enters as -M2 g, but G4 = M2 g i and dv_C/du2 = i give +M2 g.
//  - eq (15): the printed F_eB multiplies q2 by 4L and flips the sign of the initial-length term.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "kane_sim/model/generated_mechanism.h"
#include "kane_sim/model/mechanism_model.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

struct RandomInstant {
  State x;
  SpeedVector u_dot;
  double torque;
};

class TextbookEquationsTest : public ::testing::Test {
 protected:
  TextbookEquationsTest() : config_(test::textbookConfig()), model_(mechanismModel(config_)) {}

  // Random states over several revolutions of the crank, both directions, fast and slow.
  std::vector<RandomInstant> randomInstants(int count) {
    std::mt19937 rng(20261121);
    std::uniform_real_distribution<double> angle(-2 * M_PI, 2 * M_PI), position(0.2, 1.8),
        speed(-20, 20), accel(-200, 200), torque(-50, 50);
    std::vector<RandomInstant> out;
    for (int i = 0; i < count; ++i) {
      RandomInstant r;
      r.x = {angle(rng), position(rng), speed(rng), speed(rng)};
      r.u_dot = SpeedVector(accel(rng), accel(rng));
      r.torque = torque(rng);
      out.push_back(r);
    }
    return out;
  }

  // The spring force on slider 3 (F_eB · i) as the model applies it.
  double springForceOnSlider3(const State& x) const {
    const MechanismKinematics k = model_.kinematics(x);
    return loadVector(model_.loads(k, x, 0.0), LoadName::kSpring, kSlider3).x();
  }

  Config config_;
  MechanismModel model_;
};

// Scale for comparisons: generalized forces here reach a few hundred N m or N, so 1e-12
// relative to that is a few ulps of accumulated rounding.
constexpr double kRelTol = 1e-12;

TEST_F(TextbookEquationsTest, Eq13GeneralizedInertiaForcesMatchAsPrinted) {
  const MechanismParameters& p = config_.mechanism;
  const double m = p.rod_mass, L = p.rod_half_length, M1 = p.slider3_mass, M2 = p.slider4_mass;
  // Printed: 6.1666, i.e. 6 (translation) + 2 * 1/12 (two rods' I_z = m L^2/12) = 37/6,
  // truncated to four decimals.
  const double c0 = 37.0 / 6.0;
  EXPECT_NEAR(c0, 6.1666, 1e-4);
  for (const RandomInstant& r : randomInstants(500)) {
    const double q1 = r.x.q1, u1 = r.x.u1;
    const double printed_f1 = (-c0 * m * L * L + 8 * M1 * L * L * (std::cos(2 * q1) - 1) +
                               4 * m * L * L * std::cos(2 * q1)) *
                                  r.u_dot[0] -
                              4 * L * L * (m + 2 * M1) * u1 * u1 * std::sin(2 * q1);
    const double printed_f2 = -M2 * r.u_dot[1];
    const SpeedVector inertia = model_.equations(r.x, r.torque).inertiaForces(r.u_dot);
    EXPECT_NEAR(inertia[0], printed_f1, kRelTol * (1 + std::abs(printed_f1)));
    EXPECT_NEAR(inertia[1], printed_f2, kRelTol * (1 + std::abs(printed_f2)));
  }
}

TEST_F(TextbookEquationsTest, Eq17F1MatchesAsPrinted) {
  const MechanismParameters& p = config_.mechanism;
  const double m = p.rod_mass, L = p.rod_half_length, M1 = p.slider3_mass, k = p.spring_stiffness,
               g = p.gravity, q10 = config_.initial_state.q1, q20 = config_.initial_state.q2;
  for (const RandomInstant& r : randomInstants(500)) {
    const double q1 = r.x.q1, q2 = r.x.q2;
    const double printed_f1 =
        r.torque - 4 * g * L * (m + M1) * std::sin(q1) +
        4 * k * L * (4 * L * std::cos(q1) - 4 * L * std::cos(q10) - q2 + q20) * std::sin(q1);
    const double f1 = model_.equations(r.x, r.torque).active_forces[0];
    EXPECT_NEAR(f1, printed_f1, kRelTol * (1 + std::abs(printed_f1)));
  }
}

// Printed eq (17): F_2 = -M2 g + 4kL(cos q1 - cos q10) - k(q2 - q20). Wrong sign of M2 g:
// G4 = M2 g i (eq 14) and dv_C/du2 = i, so gravity contributes +M2 g (it pulls q2 up, i.e. down).
TEST_F(TextbookEquationsTest, Eq17F2PrintedGravitySignIsWrong) {
  const MechanismParameters& p = config_.mechanism;
  const double L = p.rod_half_length, M2 = p.slider4_mass, k = p.spring_stiffness, g = p.gravity,
               q10 = config_.initial_state.q1, q20 = config_.initial_state.q2;
  for (const RandomInstant& r : randomInstants(500)) {
    const double q1 = r.x.q1, q2 = r.x.q2;
    const double spring = 4 * k * L * (std::cos(q1) - std::cos(q10)) - k * (q2 - q20);
    const double printed_f2 = -M2 * g + spring;
    const double corrected_f2 = M2 * g + spring;
    const double f2 = model_.equations(r.x, r.torque).active_forces[1];
    EXPECT_NEAR(f2, corrected_f2, kRelTol * (1 + std::abs(corrected_f2)));
    EXPECT_NEAR(f2 - printed_f2, 2 * M2 * g, 1e-9);
  }
}

// Printed eq (15): F_eB = k[-4L(cos q1 - q2) - (4L cos q10 - q20)] i. The definition on its
// left, -k[(r_B - r_C) - (r_B0 - r_C0)], gives k[-(4L cos q1 - q2) + (4L cos q10 - q20)] i:
// the printed form scales q2 by 4L and has the wrong sign on the initial separation.
TEST_F(TextbookEquationsTest, Eq15PrintedSpringForceIsWrong) {
  const MechanismParameters& p = config_.mechanism;
  const double L = p.rod_half_length, k = p.spring_stiffness, q10 = config_.initial_state.q1,
               q20 = config_.initial_state.q2;
  int printed_disagrees = 0;
  for (const RandomInstant& r : randomInstants(200)) {
    const double q1 = r.x.q1, q2 = r.x.q2;
    const double from_definition =
        -k * ((4 * L * std::cos(q1) - q2) - (4 * L * std::cos(q10) - q20));
    const double printed = k * (-4 * L * (std::cos(q1) - q2) - (4 * L * std::cos(q10) - q20));
    const double f_eb = springForceOnSlider3(r.x);
    EXPECT_NEAR(f_eb, from_definition, 1e-10 * (1 + std::abs(from_definition)));
    if (std::abs(printed - f_eb) > 1.0) ++printed_disagrees;  // > 1 N apart
  }
  EXPECT_EQ(printed_disagrees, 200);
  // At the initial configuration the spring is unstretched: the definition gives 0 there,
  // the printed form gives -2k(4L cos q10 - q20) + k(4L - 1) q20 ≠ 0.
  EXPECT_DOUBLE_EQ(springForceOnSlider3(config_.initial_state), 0.0);
}

// Eqs (8)-(9) use I_z = m L^2/12, but each rod is 2L long: m (2L)^2/12 = m L^2/3. With the
// physically correct default the constant 37/6 of eq (13) becomes 6 + 2/3 = 20/3.
TEST_F(TextbookEquationsTest, SlenderRodInertiaChangesOnlyTheConstantTerm) {
  const Config physical = test::defaultConfig();
  const MechanismParameters& p = physical.mechanism;
  EXPECT_DOUBLE_EQ(p.rod_inertia, p.rod_mass * p.rod_half_length * p.rod_half_length / 3.0);
  const MechanismModel model = mechanismModel(physical);
  const double m = p.rod_mass, L = p.rod_half_length, M1 = p.slider3_mass;
  for (const RandomInstant& r : randomInstants(100)) {
    const double q1 = r.x.q1;
    const double m11 = (20.0 / 3.0) * m * L * L - 8 * M1 * L * L * (std::cos(2 * q1) - 1) -
                       4 * m * L * L * std::cos(2 * q1);
    const auto forces = model.equations(r.x, r.torque);
    EXPECT_NEAR(forces.mass_matrix(0, 0), m11, 1e-14);
    EXPECT_NEAR(forces.mass_matrix(0, 1), 0.0, 1e-14);
    EXPECT_NEAR(forces.mass_matrix(1, 1), p.slider4_mass, 1e-14);
  }
}

// Eq (18): the solved accelerations make F*_r + F_r vanish.
TEST_F(TextbookEquationsTest, KaneEquationsHoldAtTheSolvedAccelerations) {
  for (const RandomInstant& r : randomInstants(200)) {
    const auto forces = model_.equations(r.x, r.torque);
    const SpeedVector u_dot = forces.solveAccelerations();
    const SpeedVector residual = forces.inertiaForces(u_dot) + forces.active_forces;
    EXPECT_LT(residual.norm(), 1e-12 * (1 + forces.active_forces.norm()));
  }
}

// The generated equations (the integrators' default) against the textbook's eqs (13) and (17)
// solved for u' as eq (18) says, with the textbook's inertia and F_2's gravity sign corrected:
// u1' = (F1 + F*1|u'=0) / M11 and u2' = F2 / M2 (M is diagonal).
TEST_F(TextbookEquationsTest, GeneratedEquationsSolveEq18FromTheTextbooksTerms) {
  const MechanismParameters& p = config_.mechanism;
  const double m = p.rod_mass, L = p.rod_half_length, M1 = p.slider3_mass, M2 = p.slider4_mass,
               k = p.spring_stiffness, g = p.gravity, q10 = config_.initial_state.q1,
               q20 = config_.initial_state.q2;
  const GeneratedMechanism generated(model_);
  for (const RandomInstant& r : randomInstants(500)) {
    const double q1 = r.x.q1, q2 = r.x.q2, u1 = r.x.u1;
    const double m11 = (37.0 / 6.0) * m * L * L - 8 * M1 * L * L * (std::cos(2 * q1) - 1) -
                       4 * m * L * L * std::cos(2 * q1);
    const double remainder1 = -4 * L * L * (m + 2 * M1) * u1 * u1 * std::sin(2 * q1);
    const double e = 4 * L * std::cos(q1) - 4 * L * std::cos(q10) - q2 + q20;
    const double f1 = r.torque - 4 * g * L * (m + M1) * std::sin(q1) + 4 * k * L * e * std::sin(q1);
    const double f2 = M2 * g + k * e;
    const OdeState dx = generated.stateDerivative(r.x, r.torque);
    const double u1_dot = (f1 + remainder1) / m11, u2_dot = f2 / M2;
    EXPECT_NEAR(dx[2], u1_dot, 1e-12 * (1 + std::abs(u1_dot)));
    EXPECT_NEAR(dx[3], u2_dot, 1e-12 * (1 + std::abs(u2_dot)));
  }
}

// Hand-checkable instants at the initial configuration (spring unstretched, at rest):
// slider 4 starts in free fall (u2' = g), and the static holding torque is 4 g L (m + M1) sin q1.
TEST_F(TextbookEquationsTest, InitialInstantByHand) {
  const MechanismParameters& p = config_.mechanism;
  const State& x0 = config_.initial_state;
  const SpeedVector free = model_.accelerations(x0, 0.0);
  EXPECT_NEAR(free[1], p.gravity, 1e-12);
  EXPECT_LT(free[0], 0.0);  // gravity swings the crank back toward q1 = 0
  const double holding =
      4 * p.gravity * p.rod_half_length * (p.rod_mass + p.slider3_mass) * std::sin(x0.q1);
  EXPECT_NEAR(model_.accelerations(x0, holding)[0], 0.0, 1e-12);
}

}  // namespace
}  // namespace kane_sim
