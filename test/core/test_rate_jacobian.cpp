// The generated exact Jacobian d(u1', u2')/d(q1, q2, u1, u2, M_m) (codegen's symbolic
// derivatives of the generated rates) against central differences of the generic Kane assembly
// (MechanismModel: a second road to the same equations), on random mechanisms with every load on.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>

#include <gtest/gtest.h>

#include "kane_sim/config/parameter_schema.h"
#include "kane_sim/model/generated_mechanism.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

// Five-point central difference of u' along coordinate j of (q1, q2, u1, u2, M_m): truncation
// ~ h^4 f''''' / 30, rounding ~ eps |u'| / h.
SpeedVector fivePoint(const MechanismModel& model, const State& x, double command, int j,
                      double h) {
  const auto at = [&](double delta) {
    double v[5] = {x.q1, x.q2, x.u1, x.u2, command};
    v[j] += delta;
    const OdeState d = model.stateDerivative(State{v[0], v[1], v[2], v[3]}, v[4]);
    return SpeedVector(d[2], d[3]);
  };
  const SpeedVector result = ((at(-2 * h) - at(2 * h)) + 8.0 * (at(h) - at(-h))) / (12.0 * h);
  return result;
}

// The same with one Richardson step (h and h/2, truncation O(h^6)), the step quartered until
// the two agree to 1e-11 of `scale` (at most 10 times): friction's tanh(4 L sin q1 u1 / v_s)
// bends within ~v_s / (4 L u1) of a zero rate in q1 too (4e-4 rad for v_s 0.005, u1 10), where
// a step of 1e-3 rad saw 3e-4 of the slope wrong.
SpeedVector difference(const MechanismModel& model, const State& x, double command, int j, double h,
                       double scale) {
  SpeedVector result = SpeedVector::Zero();
  for (int i = 0; i < 10; ++i, h /= 4) {
    const SpeedVector coarse = fivePoint(model, x, command, j, h);
    const SpeedVector fine = fivePoint(model, x, command, j, h / 2);
    result = fine + (fine - coarse) / 15.0;
    if ((fine - coarse).cwiseAbs().maxCoeff() / 15.0 <= 1e-11 * scale) break;
  }
  return result;
}

Config randomMechanism(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> scale_exp(-1.0, 1.0), unit(0.0, 1.0);
  const auto scaled = [&](double v) { return v * std::pow(10.0, scale_exp(rng)); };
  Config drawn = test::defaultConfig();
  // Every constant the schema declares, by role (a new parameter is drawn without editing this
  // test): the masses, L, g and the stiffnesses from 1/10 to 10 times the shipped ones (0 there,
  // as the crank's spring: 0.1 to 10); every resistance on; the laws' shapes (v_s, the spring's
  // rest angle) from 1/10 to 10 times their defaults.
  for (ParameterRole role : {ParameterRole::kInertial, ParameterRole::kGeometric,
                             ParameterRole::kGravity, ParameterRole::kStiffness})
    for (const ParameterSpec* spec : parametersOfRole(role)) {
      double& v = spec->field.number(drawn);
      v = v != 0.0 ? scaled(v) : 0.1 + 9.9 * unit(rng);
    }
  for (const ParameterSpec* spec : parametersOfRole(ParameterRole::kDissipative))
    spec->field.number(drawn) = 0.1 + 9.9 * unit(rng);
  for (const ParameterSpec* spec : parametersOfRole(ParameterRole::kLoadShape))
    spec->field.number(drawn) = scaled(std::max(spec->field.number(drawn), 0.05));
  drawn.mechanism.motor.no_load_speed = 0.0;  // the line's corner: MotorLineSlopes below
  return drawn;
}

// 1000 random states of random mechanisms: each entry within 1e-8 of itself plus 1e-10 of its
// row's largest (an entry that is structurally ~0 meets the differences' rounding there).
TEST(RateJacobian, MatchesCentralDifferencesOfTheKaneAssemblyWithEveryLoad) {
  std::mt19937_64 rng(20261127);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), position(-1.0, 1.0),
      speed(-10.0, 10.0), torque(-50.0, 50.0);
  double worst = 0.0;
  for (int trial = 0; trial < 1000; ++trial) {
    const Config c = randomMechanism(rng);
    const MechanismModel model(c.mechanism, position(rng));
    const GeneratedMechanism generated(model);
    const State x{angle(rng), position(rng), speed(rng), speed(rng)};
    const double command = torque(rng);
    const generated::RateJacobian exact =
        generated::rateJacobian(generated.constants(), x.q1, x.q2, x.u1, x.u2, command);
    const double values[5] = {x.q1, x.q2, x.u1, x.u2, command};
    const double v_s = c.mechanism.friction.velocity_scale;
    for (int j = 0; j < 5; ++j) {
      double h = 1e-3 * (1.0 + std::abs(values[j]));
      if (j == 2 || j == 3) h = std::min(h, 1e-2 * v_s);  // inside tanh's bend
      double rows = 0.0;
      for (int i = 0; i < 2; ++i)
        for (int k = 0; k < 5; ++k) rows = std::max(rows, std::abs(exact.d[i][k]));
      const SpeedVector fd = difference(model, x, command, j, h, rows);
      for (int i = 0; i < 2; ++i) {
        double row = 0.0;
        for (int k = 0; k < 5; ++k) row = std::max(row, std::abs(exact.d[i][k]));
        const double error = std::abs(exact.d[i][j] - fd[i]);
        const double allowed = 1e-8 * std::abs(exact.d[i][j]) + 1e-10 * row;
        worst = std::max(worst, error / allowed);
        ASSERT_LE(error, allowed) << "trial " << trial << " d u" << i + 1 << "'/d column " << j
                                  << ": exact " << exact.d[i][j] << " differences " << fd[i];
      }
    }
  }
  std::cout << "worst error / allowed " << worst << "\n";
}

// The motor line's slopes chained in: where the line limits the command, B = 0 and u1's column
// gains d u1'/d M_m times the line's slope; elsewhere the command passes (B = d u'/d M_m).
TEST(RateJacobian, MotorLineSlopesChainIntoAAndB) {
  Config c = test::defaultConfig();
  c.mechanism.motor.no_load_speed = 20.0;
  c.mechanism.motor.torque_limit = 10.0;
  const MechanismModel model = mechanismModel(c);
  const GeneratedMechanism generated(model);
  const State x{0.3, model.withSpringAtRest(State{0.3, 0, 0, 0}).q2, 5.0, 0.1};
  // Limited: 8 N m asked at u1 = 5 where 10 (1 - 5/20) = 7.5 is available.
  const auto limited = generated.linearization(x, 8.0);
  const auto free_run = generated.linearization(x, 8.0 * 0.5);
  EXPECT_EQ(limited.B[2], 0.0);
  EXPECT_EQ(limited.B[3], 0.0);
  const double du1_dm = free_run.B[2];
  EXPECT_GT(du1_dm, 0.0);
  // Limited, d u1'/d u1 gains du1'/dM_m * (-torque_limit / no_load_speed) = -0.5 du1_dm;
  // differences of the generic assembly at u1 +- h within the limited side confirm it.
  const double h = 1e-4;
  const auto rate = [&](double u1) {
    return model.stateDerivative(State{x.q1, x.q2, u1, x.u2}, 8.0)[2];
  };
  const double slope = (rate(x.u1 + h) - rate(x.u1 - h)) / (2 * h);
  EXPECT_NEAR(limited.A(2, 2), slope, 1e-6 * std::abs(slope));
  EXPECT_NEAR(limited.A(2, 2) - free_run.A(2, 2), -0.5 * du1_dm, 1e-12 * du1_dm);
}

}  // namespace
}  // namespace kane_sim
