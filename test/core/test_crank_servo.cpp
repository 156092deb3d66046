// Servo modes (command.mode velocity | position, control/crank_servo.h run by SimDriver): the
// step response is the one the gains predict on analyze's linear model, the integral removes
// the steady error, the speed servo holds its mean speed, saturation is reported and the drive
// never sees more than the torque limit. Hostile setpoints are refused naming the value.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "kane_sim/analysis/linear_analysis.h"
#include "kane_sim/sim/sim_driver.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

Config servoConfig(CommandMode mode, Feedforward feedforward) {
  Config c = test::defaultConfig();
  c.command.mode = mode;
  c.command.feedforward = feedforward;
  return c;
}

// The static equilibrium with the crank at q1 (u = 0): the torque that holds it there, found on
// staticEquilibrium's stable branch by bisection (q1 rises with the torque on it).
State equilibriumAt(const MechanismModel& model, double q1, double* torque) {
  double lo = -40.0, hi = 40.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (staticEquilibrium(model, mid).q1 < q1 ? lo : hi) = mid;
  }
  *torque = 0.5 * (lo + hi);
  return staticEquilibrium(model, *torque);
}

// q1(t) of the linear closed loop about the equilibrium at `setpoint`: x' = (A + B K) x with K the
// servo's d M_m / d x (kp, kd and the feedforward's own slope), from the old equilibrium.
std::vector<double> linearResponse(const Config& config, const State& from, double setpoint,
                                   double dt, int steps) {
  const MechanismModel model = mechanismModel(config);
  double torque = 0.0;
  const State to = equilibriumAt(model, setpoint, &torque);
  const LinearModel lin = linearize(model, to, torque);
  const double h = 1e-6;
  const auto holding = [&](double dq1, double dq2) {
    return model.holdingMoment(State{to.q1 + dq1, to.q2 + dq2, 0, 0});
  };
  Eigen::RowVector4d gain;
  gain << -config.command.position_kp + (holding(h, 0) - holding(-h, 0)) / (2 * h),
      (holding(0, h) - holding(0, -h)) / (2 * h), -config.command.position_kd, 0.0;
  // Sampled like the servo: its torque computed at the start of each physics step and held over
  // it (a zero-order hold, which a continuous loop A + B K would miss by O(dt) of the step).
  const Eigen::Matrix4d& a = lin.A;
  Eigen::Vector4d x(from.q1 - to.q1, from.q2 - to.q2, 0, 0);
  std::vector<double> q1;
  for (int i = 0; i < steps; ++i) {  // rk4 on the linear system: exact to ~1e-12 here
    const Eigen::Vector4d b = lin.B * gain.dot(x);
    const Eigen::Vector4d k1 = a * x + b, k2 = a * (x + 0.5 * dt * k1) + b,
                          k3 = a * (x + 0.5 * dt * k2) + b, k4 = a * (x + dt * k3) + b;
    x += dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    q1.push_back(to.q1 + x[0]);
  }
  return q1;
}

// The largest |q1 - linear prediction| over 2 s after a setpoint step of `step` rad from the
// servo holding q1 = 1 rad at rest.
double stepResponseMismatch(double step, double* settle_time) {
  const Config config = servoConfig(CommandMode::kPosition, Feedforward::kHolding);
  SimDriver driver(config, {});
  double torque = 0.0;
  const State start = equilibriumAt(driver.simulator().model(), 1.0, &torque);
  EXPECT_TRUE(driver.setState(start).ok);
  EXPECT_EQ(driver.setpoint(1.0), TorqueCommand::Verdict::kAccepted);
  // Held: the feedforward is the equilibrium's torque, the PD terms zero.
  EXPECT_NEAR(driver.snapshot().servo.command, torque, 1e-8);
  EXPECT_EQ(driver.setpoint(1.0 + step), TorqueCommand::Verdict::kAccepted);
  const int steps = 2000;
  const std::vector<double> predicted =
      linearResponse(config, start, 1.0 + step, driver.simulator().stepSize(), steps);
  double worst = 0.0;
  *settle_time = 0.0;
  for (int i = 0; i < steps; ++i) {
    EXPECT_TRUE(driver.step());
    const double q1 = driver.simulator().state().q1;
    worst = std::max(worst, std::abs(q1 - predicted[i]));
    if (std::abs(q1 - (1.0 + step)) > 0.02 * std::abs(step)) *settle_time = driver.time();
    EXPECT_FALSE(driver.snapshot().servo.saturated);
  }
  return worst;
}

// The nonlinear response follows the linear model's to second order in the step: 1 % of the
// step at 0.01 rad, and doubling the step quadruples the mismatch (so it is the mechanism's
// curvature, not a wrong gain or a wrong sign, which would give a mismatch of the step's order).
TEST(CrankServo, PositionStepFollowsTheLinearModelsPrediction) {
  double settle_small = 0.0, settle_large = 0.0;
  const double small = stepResponseMismatch(0.01, &settle_small);
  const double large = stepResponseMismatch(0.02, &settle_large);
  EXPECT_LT(small, 0.01 * 0.01) << small;
  EXPECT_NEAR(large / small, 4.0, 0.6) << small << " " << large;
  // Settled to 2 % within the 2 s, the same time for both steps (a linear response's).
  EXPECT_GT(settle_small, 0.0);
  EXPECT_LT(settle_small, 1.5);
  EXPECT_NEAR(settle_large, settle_small, 0.02);
}

// Without feedforward a PD leaves the holding moment as error (error = holding / kp); the
// integral removes it.
TEST(CrankServo, IntegralRemovesTheSteadyError) {
  Config pd = servoConfig(CommandMode::kPosition, Feedforward::kNone);
  pd.mechanism.damping.slider4_joint = 20.0;  // slider 4 settles too: a steady state to compare
  Config pid = pd;
  pid.command.position_ki = 400.0;
  SimDriver a(pd, {}), b(pid, {});
  for (SimDriver* d : {&a, &b}) {
    ASSERT_EQ(d->setpoint(1.0), TorqueCommand::Verdict::kAccepted);
    for (int i = 0; i < 15000; ++i) ASSERT_TRUE(d->step());
  }
  const State& x = a.simulator().state();
  const double holding = a.simulator().model().holdingMoment(x);
  EXPECT_NEAR(1.0 - x.q1, holding / pd.command.position_kp, 1e-6);
  EXPECT_GT(std::abs(1.0 - x.q1), 0.01);  // a visible error to remove
  EXPECT_NEAR(b.simulator().state().q1, 1.0, 1e-6);
  EXPECT_NEAR(b.snapshot().servo.integral,
              b.simulator().model().holdingMoment(b.simulator().state()), 1e-4);
}

// The speed servo: the crank turns against gravity's pull, which changes every half turn, at the
// setpoint on average. Unsaturated, the integral is ki ∫(w - u1) dt, so the mean speed over T is
// w - ΔI / (ki T) exactly up to the integral's rectangle rule (O(dt) of the speed's change: 1e-3
// here), and ΔI is bounded by the limit: within 2 x 50 / (300 x 10) = 0.033 rad/s of w.
TEST(CrankServo, VelocityServoHoldsTheMeanSpeed) {
  const Config config = servoConfig(CommandMode::kVelocity, Feedforward::kHolding);
  SimDriver driver(config, {});
  const double w = 2.0;
  ASSERT_EQ(driver.setpoint(w), TorqueCommand::Verdict::kAccepted);
  for (int i = 0; i < 2000; ++i) ASSERT_TRUE(driver.step());
  const double q_start = driver.simulator().state().q1, t_start = driver.time();
  const double i_start = driver.snapshot().servo.integral;
  for (int i = 0; i < 10000; ++i) {
    ASSERT_TRUE(driver.step());
    ASSERT_FALSE(driver.snapshot().servo.saturated) << driver.time();
  }
  const double span = driver.time() - t_start;
  const double mean = (driver.simulator().state().q1 - q_start) / span;
  const double integral_change = driver.snapshot().servo.integral - i_start;
  EXPECT_NEAR(mean, w - integral_change / (config.command.velocity_ki * span), 1e-3);
  EXPECT_NEAR(mean, w, 2 * config.command.torque_limit / (config.command.velocity_ki * span));
  EXPECT_GT(span * mean, 3 * M_PI);  // turned over: through gravity's whole cycle
  EXPECT_EQ(driver.snapshot().servo.measured, driver.simulator().state().u1);
  EXPECT_EQ(driver.snapshot().servo.derivative, 0.0);
}

// A far step saturates: the output is reported beyond the limit, the drive is commanded the
// limit and delivers it (no motor line); the integral does not wind up meanwhile.
TEST(CrankServo, SaturationIsReportedAndTheLimitHolds) {
  Config config = servoConfig(CommandMode::kPosition, Feedforward::kNone);
  config.command.position_ki = 100.0;
  SimDriver driver(config, {});
  ASSERT_EQ(driver.setpoint(config.initial_state.q1 + 2.0), TorqueCommand::Verdict::kAccepted);
  ASSERT_TRUE(driver.step());
  Snapshot s = driver.snapshot();
  EXPECT_TRUE(s.servo.saturated);
  EXPECT_GT(s.servo.output, config.command.torque_limit);
  EXPECT_EQ(s.servo.command, config.command.torque_limit);
  EXPECT_EQ(s.torque, config.command.torque_limit);
  EXPECT_EQ(s.joints.effort[kCrankJoint], config.command.torque_limit);
  EXPECT_EQ(s.command.commanded, s.servo.output);
  const double integral = s.servo.integral;
  for (int i = 0; i < 50 && driver.snapshot().servo.saturated; ++i) ASSERT_TRUE(driver.step());
  EXPECT_LE(driver.snapshot().servo.integral, integral + 1e-12);  // stopped while saturated
  // With the motor line the delivered torque falls with speed below the command.
  Config line = config;
  line.mechanism.motor.no_load_speed = 10.0;
  SimDriver limited(line, {});
  limited.setpoint(line.initial_state.q1 + 2.0);
  for (int i = 0; i < 100; ++i) ASSERT_TRUE(limited.step());
  const Snapshot l = limited.snapshot();
  EXPECT_LT(std::abs(l.torque), std::abs(l.servo.command));
}

TEST(CrankServo, HostileSetpointsAndWrongModeCommandsAreRefused) {
  std::vector<SimEvent> events;
  const auto on_event = [&events](const SimEvent& e) { events.push_back(e); };
  SimDriver position(servoConfig(CommandMode::kPosition, Feedforward::kNone), on_event);
  const double held = position.snapshot().servo.setpoint;
  for (double bad : {std::nan(""), HUGE_VAL, -HUGE_VAL, 1e308, -1e7}) {
    events.clear();
    EXPECT_EQ(position.setpoint(bad), TorqueCommand::Verdict::kRejected) << bad;
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, SimEvent::Kind::kCommandRejected);
    EXPECT_NE(events[0].message.find("servo_setpoint"), std::string::npos) << events[0].message;
    EXPECT_EQ(position.snapshot().servo.setpoint, held);
  }
  events.clear();
  EXPECT_EQ(position.command(5.0), TorqueCommand::Verdict::kRejected);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_NE(events[0].message.find("command.mode is position"), std::string::npos);
  SimDriver velocity(servoConfig(CommandMode::kVelocity, Feedforward::kNone), on_event);
  EXPECT_EQ(velocity.setpoint(499.0), TorqueCommand::Verdict::kAccepted);
  events.clear();
  EXPECT_EQ(velocity.setpoint(501.0), TorqueCommand::Verdict::kRejected);  // > 0.5 rad per step
  EXPECT_NE(events.at(0).message.find("more than 0.5 rad per physics step"), std::string::npos);
  SimDriver effort(test::defaultConfig(), on_event);
  events.clear();
  EXPECT_EQ(effort.setpoint(1.0), TorqueCommand::Verdict::kRejected);
  EXPECT_NE(events.at(0).message.find("command.mode is effort"), std::string::npos);
}

// A reset puts the setpoint back where the run started and clears the integral; the servo holds
// the start (position) with no command needed: no timeout applies to a servo.
TEST(CrankServo, ResetRestoresTheSetpointAndClearsTheIntegral) {
  Config config = servoConfig(CommandMode::kPosition, Feedforward::kHolding);
  config.command.position_ki = 200.0;
  SimDriver driver(config, {});
  EXPECT_EQ(driver.snapshot().servo.setpoint, config.initial_state.q1);
  driver.setpoint(1.5);
  for (int i = 0; i < 3000; ++i) ASSERT_TRUE(driver.step());  // 3 s: past command.timeout
  EXPECT_NEAR(driver.simulator().state().q1, 1.5, 0.05);
  EXPECT_NE(driver.snapshot().servo.integral, 0.0);
  driver.reset();
  EXPECT_EQ(driver.snapshot().servo.setpoint, config.initial_state.q1);
  EXPECT_EQ(driver.snapshot().servo.integral, 0.0);
}

// The gains are reconfigurable (dynamic_reconfigure position_kp, ...): the next update uses them,
// the integral is kept.
TEST(CrankServo, ReconfiguredGainsApplyFromTheNextUpdate) {
  Config config = servoConfig(CommandMode::kPosition, Feedforward::kNone);
  config.command.position_ki = 50.0;
  SimDriver driver(config, {});
  driver.setpoint(config.initial_state.q1 + 0.05);
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(driver.step());
  const double integral = driver.snapshot().servo.integral;
  config.command.position_kp = 100.0;
  driver.reconfigure(config);
  const ServoStatus s = driver.snapshot().servo;
  EXPECT_DOUBLE_EQ(s.proportional, 100.0 * s.error);
  EXPECT_EQ(s.integral, integral);
  EXPECT_EQ(driver.simulator().torque(), s.command);
}

}  // namespace
}  // namespace kane_sim
