// Linear analysis (analyze): equilibria, A and B, natural frequencies, damping ratios.
#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/Dense>
#include <unsupported/Eigen/MatrixFunctions>

#include "kane_sim/analysis/linear_analysis.h"
#include "kane_sim/sim/simulator.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

// At zero torque the crank hangs at q1 = 0 where the two modes decouple (M12 = 0, K12 = 0):
// w1 = sqrt(4 g L (m + M1 + M2) / (2 I + 2 m L^2)) (gravity on all four bodies through the
// crank, whose inertia there is both rods'), w2 = sqrt(k / M2) (slider 4 on the spring).
TEST(LinearAnalysis, FrequenciesAtZeroTorqueMatchTheClosedForm) {
  for (const Config& c : {test::defaultConfig(), test::textbookConfig()}) {
    const MechanismParameters& p = c.mechanism;
    const MechanismModel model = mechanismModel(c);
    const State eq = staticEquilibrium(model, 0.0);
    EXPECT_NEAR(eq.q1, 0.0, 1e-12);
    const ModalAnalysis modal = modalAnalysis(linearize(model, eq, 0.0));
    const double L = p.rod_half_length, m = p.rod_mass;
    const double w_crank = std::sqrt(4 * p.gravity * L * (m + p.slider3_mass + p.slider4_mass) /
                                     (2 * p.rod_inertia + 2 * m * L * L));
    const double w_slider = std::sqrt(p.spring_stiffness / p.slider4_mass);
    std::vector<double> expected = {w_crank / (2 * M_PI), w_slider / (2 * M_PI)};
    std::sort(expected.begin(), expected.end());
    ASSERT_EQ(modal.modes.size(), 2u);
    for (int i = 0; i < 2; ++i) {
      EXPECT_NEAR(modal.modes[i].natural_frequency_hz, expected[i], 1e-9 * expected[i]);
      EXPECT_EQ(modal.modes[i].damping_ratio, 0.0);
    }
  }
}

// Damping ratios per mode against the decoupled closed forms at q1 = 0 (crank damper c_O on the
// crank mode, slider-4 damper c_C on the slider mode): zeta_crank = c_O / (2 sqrt(K11 M11)),
// zeta_slider = c_C / (2 sqrt(k M2)), under- and overdamped. Overdamped modes have two real
// eigenvalues each; pairing them by magnitude across modes gave 1.0026 / 1.0726 where the closed
// forms are 2.578 / 3.953.
TEST(LinearAnalysis, DampingRatiosPerModeMatchTheDecoupledClosedForms) {
  const double pairs[][2] = {{0.05, 0.4}, {10.0, 100.0}, {1.0, 100.0}, {10.0, 0.4}};
  for (const auto& c_pair : pairs) {
    Config c = test::defaultConfig();
    c.mechanism.damping.crank_joint = c_pair[0];
    c.mechanism.damping.slider4_joint = c_pair[1];
    const MechanismParameters& p = c.mechanism;
    const MechanismModel model = mechanismModel(c);
    const ModalAnalysis modal = modalAnalysis(linearize(model, staticEquilibrium(model, 0.0), 0.0));
    const double L = p.rod_half_length, m = p.rod_mass;
    const double k11 = 4 * p.gravity * L * (m + p.slider3_mass + p.slider4_mass);
    const double m11 = 2 * p.rod_inertia + 2 * m * L * L;
    const double zeta_crank = p.damping.crank_joint / (2 * std::sqrt(k11 * m11));
    const double zeta_slider =
        p.damping.slider4_joint / (2 * std::sqrt(p.spring_stiffness * p.slider4_mass));
    // Modes ascend in frequency: the crank's 1.85 Hz, then the slider's 2.52 Hz.
    EXPECT_NEAR(modal.modes[0].damping_ratio, zeta_crank, 1e-8 * zeta_crank) << c_pair[0];
    EXPECT_NEAR(modal.modes[1].damping_ratio, zeta_slider, 1e-8 * zeta_slider) << c_pair[1];
    EXPECT_FALSE(modal.modes[0].neutral || modal.modes[1].neutral);
  }
}

// Friction at rest linearizes as the damper of its slope, F_c / v_s: a crank friction of 0.5 N m
// over v_s 0.1 rad/s is a crank damper of 5 N m s/rad to the linear model (the same ratios as
// that damper, 1e-6: the stencil's step is 1/100 of v_s), with v_s 1e-4 too (the step follows
// v_s), and analyze says what that leaves out.
TEST(LinearAnalysis, FrictionAtRestIsTheDamperOfItsSlope) {
  for (const double v_s : {0.1, 1e-4}) {
    Config rubbing = test::defaultConfig(), damped = rubbing;
    rubbing.mechanism.friction.crank_joint = 0.5 * v_s / 0.1;
    rubbing.mechanism.friction.slider4_joint = 2.0 * v_s / 0.1;
    rubbing.mechanism.friction.velocity_scale = v_s;
    damped.mechanism.damping.crank_joint = 5.0;
    damped.mechanism.damping.slider4_joint = 20.0;
    const MechanismModel with_friction = mechanismModel(rubbing),
                         with_dampers = mechanismModel(damped);
    const LinearModel a = linearize(with_friction, staticEquilibrium(with_friction, 0.0), 0.0);
    const LinearModel b = linearize(with_dampers, staticEquilibrium(with_dampers, 0.0), 0.0);
    const ModalAnalysis fa = modalAnalysis(a), fb = modalAnalysis(b);
    for (int i = 0; i < 2; ++i)
      EXPECT_NEAR(fa.modes[i].damping_ratio, fb.modes[i].damping_ratio,
                  1e-6 * fb.modes[i].damping_ratio)
          << "v_s " << v_s << " mode " << i;
    ASSERT_EQ(a.notes.size(), 1u);
    EXPECT_NE(a.notes[0].find("friction.velocity_scale"), std::string::npos) << a.notes[0];
    EXPECT_TRUE(b.notes.empty());
  }
}

// Gravity 0: nothing restores the crank. The equilibrium is neutral along the crank's mode
// (frequency 0, no damping ratio), not a mode of 3.9e-6 Hz from the differences' noise; the
// slider's mode is still sqrt(k / M2).
TEST(LinearAnalysis, WithoutGravityTheCranksModeIsNeutral) {
  Config c = test::defaultConfig();
  c.mechanism.gravity = 0.0;
  const MechanismModel model = mechanismModel(c);
  const ModalAnalysis modal = modalAnalysis(linearize(model, staticEquilibrium(model, 0.0), 0.0));
  EXPECT_TRUE(modal.modes[0].neutral);
  EXPECT_EQ(modal.modes[0].natural_frequency_hz, 0.0);
  EXPECT_TRUE(std::isnan(modal.modes[0].damping_ratio));
  EXPECT_FALSE(modal.modes[1].neutral);
  const double w = std::sqrt(c.mechanism.spring_stiffness / c.mechanism.slider4_mass);
  EXPECT_NEAR(modal.modes[1].natural_frequency_hz, w / (2 * M_PI), 1e-5 * w);
  try {
    staticEquilibrium(model, 1.0);
    ADD_FAILURE() << "a torque has no equilibrium without gravity";
  } catch (const AnalysisError& e) {
    EXPECT_NE(std::string(e.what()).find("mechanism.gravity 0"), std::string::npos) << e.what();
  }
}

// The holding limit is 4 g L (m + M1 + M2) at q1 = pi/2 (F_1 = M_m - that sin q1 with slider 4
// balanced); a larger torque has no equilibrium and the error names the limit.
TEST(LinearAnalysis, UnholdableTorqueIsRefusedNamingTheLimit) {
  const Config c = test::defaultConfig();
  const MechanismParameters& p = c.mechanism;
  const double limit =
      4 * p.gravity * p.rod_half_length * (p.rod_mass + p.slider3_mass + p.slider4_mass);
  const MechanismModel model = mechanismModel(c);
  EXPECT_NEAR(maxHoldingTorque(model).torque, limit, 1e-9 * limit);
  EXPECT_NEAR(staticEquilibrium(model, 0.5 * limit).q1, std::asin(0.5), 1e-12);
  EXPECT_NEAR(staticEquilibrium(model, -0.5 * limit).q1, -std::asin(0.5), 1e-12);
  try {
    staticEquilibrium(model, 1.01 * limit);
    FAIL() << "an unholdable torque was accepted";
  } catch (const AnalysisError& e) {
    EXPECT_NE(std::string(e.what()).find("beyond what gravity can hold: at most 22.563 N m"),
              std::string::npos)
        << e.what();
  }
}

// Around the whole turn: at 0 N m the crank hangs (q1 = 0, stable) or stands upright (q1 = pi,
// unstable, growing at sqrt(K11 / M11): K11 = 4 g L (m + M1 + M2), M11 = 2 I + 2 m L^2 there as
// at q1 = 0); under half the holding limit, at asin(1/2) (stable) and pi - asin(1/2) (unstable).
TEST(Equilibria, HangingIsStableUprightUnstableAroundTheTurn) {
  const Config c = test::defaultConfig();
  const MechanismParameters& p = c.mechanism;
  const MechanismModel model = mechanismModel(c);
  const double L = p.rod_half_length, m = p.rod_mass;
  const double k11 = 4 * p.gravity * L * (m + p.slider3_mass + p.slider4_mass);
  const double m11 = 2 * p.rod_inertia + 2 * m * L * L;
  const std::vector<Equilibrium> at_rest = equilibria(model, 0.0);
  ASSERT_EQ(at_rest.size(), 2u);
  EXPECT_NEAR(at_rest[0].state.q1, 0.0, 1e-12);
  EXPECT_EQ(at_rest[0].stability, "stable");
  EXPECT_NEAR(at_rest[1].state.q1, M_PI, 1e-12);
  EXPECT_EQ(at_rest[1].stability, "unstable");
  EXPECT_NEAR(at_rest[1].largest_real_eigenvalue, std::sqrt(k11 / m11),
              1e-9 * std::sqrt(k11 / m11));
  const std::vector<Equilibrium> pushed = equilibria(model, 0.5 * k11);
  ASSERT_EQ(pushed.size(), 2u);
  EXPECT_NEAR(pushed[0].state.q1, std::asin(0.5), 1e-12);
  EXPECT_EQ(pushed[0].stability, "stable");
  EXPECT_NEAR(pushed[1].state.q1, M_PI - std::asin(0.5), 1e-12);
  EXPECT_EQ(pushed[1].stability, "unstable");
  EXPECT_TRUE(equilibria(model, 1.01 * k11).empty());  // beyond the limit: it turns over
  // equilibriumAt: the holding moment at any angle, 0 upright and the limit at pi/2.
  EXPECT_NEAR(equilibriumAt(model, M_PI).torque, 0.0, 1e-12 * k11);
  EXPECT_NEAR(equilibriumAt(model, M_PI / 2).torque, k11, 1e-12 * k11);
  EXPECT_NEAR(equilibriumAt(model, -2.5).torque, k11 * std::sin(-2.5), 1e-12 * k11);
  EXPECT_THROW(equilibriumAt(model, std::nan("")), AnalysisError);
  EXPECT_THROW(equilibria(model, INFINITY), AnalysisError);
}

// A torsional spring at the crank (k_t, rest q1_0) moves the equilibria off 0 and pi: every one
// found is one (u' = 0 there under the torque), within its bisection's 1e-12 rad.
TEST(Equilibria, EveryOneFoundHoldsWithACrankSpring) {
  Config c = test::defaultConfig();
  c.mechanism.crank_spring_stiffness = 40.0;
  c.mechanism.crank_spring_rest_angle = 1.0;
  const MechanismModel model = mechanismModel(c);
  for (double torque : {0.0, 5.0, -12.0}) {
    const std::vector<Equilibrium> found = equilibria(model, torque);
    ASSERT_FALSE(found.empty()) << torque;
    for (const Equilibrium& e : found) {
      const OdeState d = model.stateDerivative(e.state, torque);
      EXPECT_NEAR(d[2], 0.0, 1e-9) << torque << " at q1 " << e.state.q1;
      EXPECT_NEAR(d[3], 0.0, 1e-9) << torque << " at q1 " << e.state.q1;
    }
  }
}

// A small perturbation about the equilibrium under 8 N m: the nonlinear simulation (dopri5,
// 1e-12) follows exp(A t) x0 to second order in the amplitude (1e-4 rad, 1e-4 m): the gap after
// 2 s must be below 1 % of the amplitude (the neglected terms are ~1e-4 of it).
TEST(LinearAnalysis, LinearModelPredictsTheNonlinearResponse) {
  Config c = test::defaultConfig();
  c.mechanism.damping.crank_joint = 0.1;  // with damping, so the damped eigenvalues are exercised
  c.simulation.integrator = IntegratorType::kDopri5;
  c.simulation.absolute_tolerance = c.simulation.relative_tolerance = 1e-12;
  const double torque = 8.0;
  const MechanismModel model = mechanismModel(c);
  const State eq = staticEquilibrium(model, torque);
  const LinearModel linear = linearize(model, eq, torque);
  const Eigen::Vector4d dx0(1e-4, 1e-4, 0, 0);
  Simulator sim(c);  // set_state keeps the spring's rest length (a new config would move it)
  ASSERT_TRUE(sim.setState(State{eq.q1 + dx0[0], eq.q2 + dx0[1], 0, 0}).ok);
  ASSERT_TRUE(sim.setTorque(torque).ok);
  for (int i = 0; i < 2000; ++i) ASSERT_TRUE(sim.step().ok);
  const Eigen::Vector4d predicted = (linear.A * 2.0).exp() * dx0;
  const State& x = sim.state();
  const Eigen::Vector4d actual(x.q1 - eq.q1, x.q2 - eq.q2, x.u1, x.u2);
  EXPECT_LT((actual - predicted).norm(), 1e-2 * dx0.norm())
      << "actual " << actual.transpose() << "\npredicted " << predicted.transpose();
  EXPECT_GT(predicted.norm(), 0.3 * dx0.norm());  // still moving: not a trivially small check
  // B: the torque's effect on u1' is M^-1 (1, 0): the crank's row of the inverse mass matrix.
  const Eigen::Vector2d minv = linear.mass.inverse().col(0);
  EXPECT_NEAR(linear.B[2], minv[0], 1e-9 * std::abs(minv[0]));
  EXPECT_NEAR(linear.B[3], minv[1], 1e-9 * (1 + std::abs(minv[1])));
  const ModalAnalysis modal = modalAnalysis(linear);
  EXPECT_GT(modal.modes[0].damping_ratio, 0.0);
  for (const auto& lambda : modal.eigenvalues) EXPECT_LT(lambda.real(), 0.0);
}

}  // namespace
}  // namespace kane_sim
