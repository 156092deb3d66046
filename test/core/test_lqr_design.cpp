// Controllers from the model: the Riccati solver against closed forms, LQR at the hanging and the
// upright crank (the law holds the nonlinear mechanism), its file, and what they refuse.
#include <cmath>
#include <limits>
#include <sstream>

#include <gtest/gtest.h>

#include "kane_sim/design/lqr.h"
#include "kane_sim/design/lqr_file.h"
#include "kane_sim/design/riccati.h"
#include "kane_sim/model/generated_mechanism.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

// The double integrator x'' = u with Q = I, R = 1: P = [[sqrt 3, 1], [1, sqrt 3]], K = [1, sqrt 3]
// (the textbook closed form).
TEST(Riccati, DoubleIntegratorMatchesTheClosedForm) {
  Eigen::MatrixXd A(2, 2), B(2, 1), Q = Eigen::MatrixXd::Identity(2, 2), R(1, 1);
  A << 0, 1, 0, 0;
  B << 0, 1;
  R << 1;
  const Eigen::MatrixXd P = solveContinuousRiccati(A, B, Q, R);
  EXPECT_NEAR(P(0, 0), std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(P(0, 1), 1.0, 1e-12);
  EXPECT_NEAR(P(1, 0), 1.0, 1e-12);
  EXPECT_NEAR(P(1, 1), std::sqrt(3.0), 1e-12);
  EXPECT_LT(riccatiResidual(A, B, Q, R, P), 1e-14);
}

// A scalar unstable plant x' = a x + b u: P = (a + sqrt(a^2 + b^2 q / r)) r / b^2.
TEST(Riccati, ScalarPlantsMatchTheClosedForm) {
  for (double a : {-3.0, 0.0, 0.5, 40.0})
    for (double q : {1e-6, 1.0, 1e6}) {
      Eigen::MatrixXd A(1, 1), B(1, 1), Q(1, 1), R(1, 1);
      A << a, B << 2.0, Q << q, R << 0.3;
      const double want = (a + std::sqrt(a * a + 4.0 * q / 0.3)) * 0.3 / 4.0;
      EXPECT_NEAR(solveContinuousRiccati(A, B, Q, R)(0, 0), want, 1e-10 * want) << a << " " << q;
    }
}

TEST(Riccati, RefusesWhatHasNoStabilizingSolutionInWords) {
  Eigen::MatrixXd A(2, 2), B(2, 1), Q = Eigen::MatrixXd::Identity(2, 2), R(1, 1);
  A << 1, 0, 0, -1;  // the unstable mode is not reached by B
  B << 0, 1;
  R << 1;
  try {
    solveContinuousRiccati(A, B, Q, R);
    FAIL() << "an unstabilizable pair was accepted";
  } catch (const RiccatiError& e) {
    EXPECT_NE(std::string(e.what()).find("not stabilizable"), std::string::npos) << e.what();
  }
  const double nan = std::nan("");
  Eigen::MatrixXd bad = Q;
  bad(0, 0) = nan;
  EXPECT_THROW(solveContinuousRiccati(A, B, bad, R), RiccatiError);
  bad(0, 0) = -1.0;
  EXPECT_THROW(solveContinuousRiccati(A, B, bad, R), RiccatiError);
  EXPECT_THROW(solveContinuousRiccati(A, B, Q, Eigen::MatrixXd::Zero(1, 1)), RiccatiError);
  EXPECT_THROW(solveContinuousRiccati(A, B, Q, Eigen::MatrixXd::Constant(1, 1, -1)), RiccatiError);
  EXPECT_THROW(solveContinuousRiccati(A, B, Eigen::MatrixXd::Identity(3, 3), R), RiccatiError);
  bad = Q;
  bad(0, 1) = 0.5;  // not symmetric
  EXPECT_THROW(solveContinuousRiccati(A, B, bad, R), RiccatiError);
}

// rk4 of the generic Kane assembly under the law, every 1 ms, the law sampled at each step.
State closedLoop(const MechanismModel& model, const StateFeedback& law, State x, double seconds) {
  const double h = 1e-3;
  for (int i = 0; i < static_cast<int>(seconds / h); ++i) {
    const double torque = law.command(x);
    const auto rate = [&](const State& s) { return model.stateDerivative(s, torque); };
    const auto add = [](const State& s, const OdeState& d, double f) {
      return State{s.q1 + f * d[0], s.q2 + f * d[1], s.u1 + f * d[2], s.u2 + f * d[3]};
    };
    const OdeState k1 = rate(x), k2 = rate(add(x, k1, h / 2)), k3 = rate(add(x, k2, h / 2)),
                   k4 = rate(add(x, k3, h));
    for (int j = 0; j < 4; ++j) {
      const double d = (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]) / 6 * h;
      (j == 0 ? x.q1 : j == 1 ? x.q2 : j == 2 ? x.u1 : x.u2) += d;
    }
  }
  return x;
}

// Upright (q1 = pi) is unstable open loop; the LQR gain holds it. There the crank's lever on the
// spring (4 L sin q1) is 0: slider 4's oscillation, +-i sqrt(k / M2), is out of the crank's reach
// and stays in the closed loop (2 controllable states: the crank's); the others move into the left
// half plane. The nonlinear mechanism started 0.1 rad off (and a turn away: periodic) returns to
// upright, slider 4 oscillating about its place by what the transient gave it (undamped), or
// settling there with a damper beside it.
TEST(LqrDesign, HoldsTheUprightCrankOfTheNonlinearMechanism) {
  for (double slider_damping : {0.0, 2.0}) {
    Config c = test::defaultConfig();
    c.mechanism.damping.slider4_joint = slider_damping;
    const MechanismModel model = mechanismModel(c);
    const LqrDesign d = designLqr(model, M_PI, defaultLqrWeights(c, model));
    EXPECT_GT(d.open_loop.back().real(), 1.0);  // unstable: sqrt(K11 / M11) ~ 11.6 rad/s
    EXPECT_EQ(d.controllable_basis.cols(), 2);  // the crank's q1 and u1
    ASSERT_FALSE(d.notes.empty());
    EXPECT_NE(d.notes.back().find("cannot be moved by the crank"), std::string::npos);
    const double slider = std::sqrt(c.mechanism.spring_stiffness / c.mechanism.slider4_mass);
    int on_axis = 0;
    for (const auto& lambda : d.closed_loop) {
      if (std::abs(lambda.real()) < 1e-9 * slider) {
        ++on_axis;
        EXPECT_NEAR(std::abs(lambda.imag()), slider, 1e-9 * slider);
      } else {
        EXPECT_LT(lambda.real(), -1e-3) << lambda;
      }
    }
    EXPECT_EQ(on_axis, slider_damping == 0.0 ? 2 : 0);
    EXPECT_LT(d.riccati_residual, 1e-12);
    EXPECT_NEAR(d.equilibrium.torque, 0.0, 1e-9);  // upright needs no holding moment
    for (double turn : {0.0, -2 * M_PI}) {
      State start = d.equilibrium.state;
      start.q1 += 0.1 + turn;
      const State end = closedLoop(model, d.feedback, start, 5.0);
      EXPECT_NEAR(std::remainder(end.q1 - M_PI, 2 * M_PI), 0.0, 1e-4) << turn;
      EXPECT_NEAR(end.u1, 0.0, 1e-4);
      EXPECT_NEAR(end.q2, d.equilibrium.state.q2, slider_damping > 0 ? 1e-5 : 2e-3);
    }
  }
}

// At an angle that needs a holding moment, the law's constant part is that moment and the held
// state is an equilibrium under it.
TEST(LqrDesign, HoldsAnyAngleWithItsHoldingMoment) {
  const Config c = test::defaultConfig();
  const MechanismModel model = mechanismModel(c);
  const LqrDesign d = designLqr(model, 1.0, defaultLqrWeights(c, model));
  const OdeState at_rest = model.stateDerivative(d.equilibrium.state, d.equilibrium.torque);
  EXPECT_NEAR(at_rest[2], 0.0, 1e-10);
  EXPECT_NEAR(at_rest[3], 0.0, 1e-10);
  State start = d.equilibrium.state;
  start.q1 -= 0.2;
  const State end = closedLoop(model, d.feedback, start, 5.0);
  EXPECT_NEAR(end.q1, 1.0, 1e-4);
}

TEST(LqrDesign, TheFileRoundTripsTheLawAndRefusesBadFieldsByName) {
  const Config c = test::defaultConfig();
  const MechanismModel model = mechanismModel(c);
  const LqrDesign d = designLqr(model, M_PI, defaultLqrWeights(c, model));
  std::ostringstream text;
  writeLqrYaml(text, d, "config/mechanism.yaml");
  const StateFeedback read = stateFeedbackFromYaml(text.str());
  EXPECT_EQ(read.K, d.feedback.K);  // shortest exact decimal: the same doubles
  EXPECT_EQ(read.state, d.feedback.state);
  EXPECT_EQ(read.torque, d.feedback.torque);
  EXPECT_EQ(read.periodic, d.feedback.periodic);
  const std::pair<std::string, std::string> bad[] = {
      {"", "no state_feedback"},
      {"{", "not YAML"},
      {"state_feedback: 3", "no state_feedback"},
      {"state_feedback: {state: [0, 0, 0], torque: 0, K: [1, 2, 3, 4], periodic: true}",
       "state_feedback.state must be a list of 4"},
      {"state_feedback: {state: [0, 0, 0, 0], torque: .nan, K: [1, 2, 3, 4], periodic: true}",
       "state_feedback.torque = .nan is not finite"},
      {"state_feedback: {state: [0, 0, 0, 0], torque: 0, K: [1, x, 3, 4], periodic: true}",
       "state_feedback.K[1] = 'x' is not a number"},
      {"state_feedback: {state: [0, 0, 0, 0], torque: 1e400, K: [1, 2, 3, 4], periodic: true}",
       "state_feedback.torque"},
      {"state_feedback: {state: [0, 0, 0, 0], torque: 0, K: [1, 2, 3, 4], periodic: maybe}",
       "state_feedback.periodic must be true or false"},
      {"state_feedback: {state: [0, 0, 0, 0], K: [1, 2, 3, 4], periodic: true}",
       "state_feedback.torque is missing"},
  };
  for (const auto& [yaml, words] : bad) {
    try {
      stateFeedbackFromYaml(yaml);
      ADD_FAILURE() << "accepted: " << yaml;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << yaml << " -> " << e.what();
    }
  }
  EXPECT_THROW(readStateFeedbackFile("/dev/zero"), std::invalid_argument);
  EXPECT_THROW(readStateFeedbackFile("/no/such/file.yaml"), std::invalid_argument);
}

TEST(LqrDesign, RefusesAnAngleThatIsNotOne) {
  const Config c = test::defaultConfig();
  const MechanismModel model = mechanismModel(c);
  const double inf = std::numeric_limits<double>::infinity();
  for (double q1 : {std::nan(""), inf, -inf, 1e308})
    EXPECT_THROW(designLqr(model, q1, defaultLqrWeights(c, model)), AnalysisError) << q1;
}

}  // namespace
}  // namespace kane_sim
