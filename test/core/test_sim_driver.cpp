// The one simulation driver: commands, stepping and the events it reports, without a master.
// The same events reach the node's log and `simulate`'s stderr (test/tools/test_simulate_cli,
// test/node/test_robustness and test_commands).
#include <cmath>
#include <limits>
#include <vector>

#include <tuple>

#include <gtest/gtest.h>

#include "kane_sim/model/generated_mechanism.h"
#include "kane_sim/sim/sim_driver.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

using Kind = SimEvent::Kind;

class SimDriverTest : public ::testing::Test {
 protected:
  SimDriver makeDriver(const Config& config) {
    return SimDriver(config, [this](const SimEvent& e) { events_.push_back(e); });
  }
  int count(Kind kind) const {
    int n = 0;
    for (const SimEvent& e : events_) n += e.kind == kind;
    return n;
  }
  const SimEvent* first(Kind kind) const {
    for (const SimEvent& e : events_)
      if (e.kind == kind) return &e;
    return nullptr;
  }
  std::vector<SimEvent> events_;
};

TEST_F(SimDriverTest, CommandIsInForceFromThisInstantAndShowsInTheSnapshot) {
  SimDriver driver = makeDriver(test::defaultConfig());
  EXPECT_EQ(driver.command(3.0), TorqueCommand::Verdict::kAccepted);
  Snapshot s = driver.snapshot();
  EXPECT_EQ(s.torque, 3.0);
  EXPECT_EQ(s.command.commanded, 3.0);
  EXPECT_EQ(s.command.torque_limit, 50.0);
  EXPECT_FALSE(s.command.timed_out);
  EXPECT_EQ(s.joints.effort[kCrankJoint], 3.0);
  // F_1 carries M_m: the snapshot is consistent with the torque it reports.
  const double q1 = s.state.q1;
  ASSERT_TRUE(driver.step());
  EXPECT_GT(driver.snapshot().state.q1, q1 - 1e-3);
  EXPECT_TRUE(events_.empty());
}

// ~step_with_command's work: refusals name the value and move nothing; a held torque runs the
// steps through the same clamp; a stop reason ends the call where it was asked.
TEST_F(SimDriverTest, StepHeldRefusesBadRequestsAndAccountsForWhatRan) {
  SimDriver driver = makeDriver(test::defaultConfig());
  const auto never = [] { return std::string(); };
  const State before = driver.simulator().state();
  for (const auto& [torque, steps, why] :
       {std::tuple<double, std::uint64_t, const char*>{std::nan(""), 10,
                                                       "torque = nan is not finite"},
        {INFINITY, 10, "torque = inf is not finite"},
        {1.0, 0, "steps = 0 must be in [1, 1000000]"},
        {1.0, 4000000000ULL, "steps = 4000000000 must be in [1, 1000000]"}}) {
    const SimDriver::HeldSteps r = driver.stepHeld(torque, steps, never);
    EXPECT_TRUE(r.refused);
    EXPECT_FALSE(r.finished);
    EXPECT_NE(r.message.find(why), std::string::npos) << r.message;
    EXPECT_NE(r.message.find("nothing changed"), std::string::npos) << r.message;
  }
  EXPECT_EQ(driver.ticks(), 0u);
  EXPECT_EQ(driver.simulator().state().q1, before.q1);

  const SimDriver::HeldSteps done = driver.stepHeld(80.0, 100, never);  // beyond the 50 N m limit
  EXPECT_TRUE(done.finished);
  EXPECT_EQ(driver.ticks(), 100u);
  EXPECT_EQ(driver.snapshot().torque, 50.0);
  EXPECT_NE(done.message.find("advanced 100 physics steps from t = 0 s to 0.1 s"),
            std::string::npos)
      << done.message;
  EXPECT_NE(done.message.find("torque 80 N m clamped to the limit 50 N m"), std::string::npos)
      << done.message;

  int asked = 0;
  const SimDriver::HeldSteps stopped =
      driver.stepHeld(1.0, 1000, [&asked] { return ++asked == 2 ? "enough" : ""; });
  EXPECT_FALSE(stopped.finished);
  EXPECT_FALSE(stopped.refused);
  // Asked at ticks 128 and 192 (every kHeldStepsCheckEvery = 64 ticks): 92 steps ran.
  EXPECT_EQ(driver.ticks(), 3u * SimDriver::kHeldStepsCheckEvery);
  EXPECT_NE(stopped.message.find("stopped after 92 of 1000 physics steps"), std::string::npos)
      << stopped.message;
  EXPECT_NE(stopped.message.find(": enough; the state there is answered"), std::string::npos)
      << stopped.message;

  Config servo = test::defaultConfig();
  servo.command.mode = CommandMode::kVelocity;
  SimDriver servo_driver = makeDriver(servo);
  const SimDriver::HeldSteps r = servo_driver.stepHeld(1.0, 10, never);
  EXPECT_TRUE(r.refused);
  EXPECT_NE(r.message.find("command.mode is velocity"), std::string::npos) << r.message;
}

TEST_F(SimDriverTest, NonFiniteCommandsAreRejectedAndClampingReportedEveryTime) {
  SimDriver driver = makeDriver(test::defaultConfig());
  driver.command(5.0);
  for (double bad : {std::nan(""), std::numeric_limits<double>::infinity()})
    EXPECT_EQ(driver.command(bad), TorqueCommand::Verdict::kRejected);
  EXPECT_EQ(driver.snapshot().torque, 5.0);
  EXPECT_EQ(driver.command(80.0), TorqueCommand::Verdict::kClamped);
  EXPECT_EQ(driver.command(-80.0), TorqueCommand::Verdict::kClamped);
  EXPECT_EQ(driver.snapshot().torque, -50.0);
  EXPECT_EQ(count(Kind::kCommandRejected), 2);
  EXPECT_EQ(count(Kind::kCommandClamped), 2);
  EXPECT_NE(first(Kind::kCommandRejected)->message.find("ignored, applying 5 N m"),
            std::string::npos)
      << first(Kind::kCommandRejected)->message;
  EXPECT_NE(first(Kind::kCommandClamped)->message.find("command.torque_limit 50"),
            std::string::npos);
}

// command.timeout is 0.5 s in config/mechanism.yaml: the command lapses once, at the first
// instant more than 0.5 s after it, and the torque drops to 0 from that instant on.
TEST_F(SimDriverTest, TimeoutIsReportedOnceAndTheNextCommandResumes) {
  SimDriver driver = makeDriver(test::defaultConfig());
  driver.command(4.0);
  for (int i = 0; i < 1000; ++i) ASSERT_TRUE(driver.step());
  ASSERT_EQ(count(Kind::kCommandTimedOut), 1);
  EXPECT_NEAR(first(Kind::kCommandTimedOut)->time, 0.501, 1e-9);
  EXPECT_NE(first(Kind::kCommandTimedOut)->message.find("command.timeout"), std::string::npos);
  Snapshot s = driver.snapshot();
  EXPECT_EQ(s.torque, 0.0);
  EXPECT_TRUE(s.command.timed_out);
  EXPECT_EQ(s.command.commanded, 4.0);
  driver.command(2.0);
  EXPECT_EQ(driver.snapshot().torque, 2.0);
  EXPECT_FALSE(driver.snapshot().command.timed_out);
}

// A reset forgets the command and clears the timeout latch: no "timed out" carried into the new
// run, and a command after it lapses (and is reported) afresh; sim time runs on.
TEST_F(SimDriverTest, ResetClearsTheTimeoutLatchAndKeepsTime) {
  SimDriver driver = makeDriver(test::defaultConfig());
  driver.command(4.0);
  for (int i = 0; i < 1000; ++i) ASSERT_TRUE(driver.step());
  ASSERT_TRUE(driver.snapshot().command.timed_out);
  const double before = driver.time();
  driver.reset();
  EXPECT_EQ(driver.time(), before);
  Snapshot s = driver.snapshot();
  EXPECT_FALSE(s.command.timed_out);
  EXPECT_EQ(s.command.commanded, 0.0);
  EXPECT_EQ(s.torque, 0.0);
  for (int i = 0; i < 1000; ++i) ASSERT_TRUE(driver.step());
  EXPECT_EQ(count(Kind::kCommandTimedOut), 1) << "no command since the reset: nothing lapses";
  driver.command(1.0);
  for (int i = 0; i < 1000; ++i) ASSERT_TRUE(driver.step());
  EXPECT_EQ(count(Kind::kCommandTimedOut), 2);
}

// Driven at the limit the crank spins up until the sliders cross and rk4 at 1 kHz no longer
// follows it; each is reported once, and again after a reset.
TEST_F(SimDriverTest, SliderCrossingAndCoarseStepAreReportedOncePerStartOrReset) {
  Config c = test::defaultConfig();
  c.command.timeout = 0;
  SimDriver driver = makeDriver(c);
  driver.command(50.0);
  for (int i = 0; i < 20000 && count(Kind::kStepTooCoarse) == 0; ++i) ASSERT_TRUE(driver.step());
  for (int i = 0; i < 1000; ++i) ASSERT_TRUE(driver.step());
  EXPECT_GE(driver.simulator().sliderCrossings(), 2u);
  EXPECT_EQ(count(Kind::kFirstSliderCrossing), 1);
  EXPECT_EQ(count(Kind::kStepTooCoarse), 1);
  EXPECT_NE(first(Kind::kStepTooCoarse)->message.find("dopri5"), std::string::npos);
  EXPECT_NE(first(Kind::kFirstSliderCrossing)->message.find("passed through slider 3"),
            std::string::npos);

  driver.reset();
  EXPECT_EQ(driver.snapshot().torque, 0.0);
  driver.command(50.0);
  for (int i = 0; i < 20000 && count(Kind::kStepTooCoarse) < 2; ++i) ASSERT_TRUE(driver.step());
  EXPECT_EQ(count(Kind::kFirstSliderCrossing), 2);
  EXPECT_EQ(count(Kind::kStepTooCoarse), 2);
}

TEST_F(SimDriverTest, RefusedStepIsReportedAndTheStateKept) {
  Config c = test::defaultConfig();
  c.command.torque_limit = 1e300;
  SimDriver driver = makeDriver(c);
  driver.command(1e300);
  bool refused = false;
  for (int i = 0; i < 50 && !refused; ++i) refused = !driver.step();
  ASSERT_TRUE(refused);
  ASSERT_EQ(count(Kind::kStepRefused), 1);
  EXPECT_NE(first(Kind::kStepRefused)->message.find("state kept"), std::string::npos);
  EXPECT_TRUE(driver.snapshot().state.isFinite());
}

TEST_F(SimDriverTest, SnapshotIsConsistentWithTheModel) {
  const Config c = test::defaultConfig();
  SimDriver driver = makeDriver(c);
  driver.command(2.0);
  for (int i = 0; i < 250; ++i) ASSERT_TRUE(driver.step());
  const Snapshot s = driver.snapshot();
  const MechanismModel model = mechanismModel(c);
  const MechanismGeometry g = model.geometry(s.state.q1, s.state.q2);
  EXPECT_EQ(s.geometry.pin_a, g.pin_a);
  EXPECT_EQ(s.geometry.point_c, g.point_c);
  EXPECT_EQ(s.slider_separation, g.sliderSeparation());
  EXPECT_EQ(s.spring_elongation, model.springElongation(g));
  // u' from the equations the integrators step (generated by default), the assembly's to rounding.
  const OdeState dx = GeneratedMechanism(model).stateDerivative(s.state, 2.0);
  EXPECT_EQ(s.u_dot, SpeedVector(dx[2], dx[3]));
  EXPECT_LT((s.u_dot - model.accelerations(s.state, 2.0)).norm(), 1e-12 * (1 + s.u_dot.norm()));
  EXPECT_DOUBLE_EQ(s.energy.total(), model.energy(s.state).total());
  EXPECT_EQ(s.joints.position[kCrankJoint], s.state.q1);
  EXPECT_EQ(s.joints.position[kSlider4Joint], s.state.q2);
  EXPECT_EQ(s.joints.velocity[kSlider4Joint], s.state.u2);
  EXPECT_LT((s.inertia_forces + s.active_forces).norm(), 1e-12);
}

// set_state: the state and its physics, command kept, work restarted; bad values refused.
TEST_F(SimDriverTest, SetStateKeepsTheCommandAndRefusesNonFiniteValues) {
  const Config config = test::defaultConfig();
  SimDriver driver = makeDriver(config);
  driver.command(4.0);
  for (int i = 0; i < 100; ++i) driver.step();
  const State target{1.0, 1.5, -3.0, 0.25};
  ASSERT_TRUE(driver.setState(target).ok);
  Snapshot s = driver.snapshot();
  EXPECT_EQ(s.state.q1, 1.0);
  EXPECT_EQ(s.state.u2, 0.25);
  EXPECT_EQ(s.torque, 4.0);
  EXPECT_EQ(s.motor_work, 0.0);
  const SpeedVector expected = mechanismModel(config).accelerations(target, 4.0);
  EXPECT_LT((s.u_dot - expected).norm(), 1e-12 * expected.norm());

  const Status refused = driver.setState(State{0.0, std::nan(""), 0.0, 0.0});
  EXPECT_FALSE(refused.ok);
  EXPECT_NE(refused.error.find("q2"), std::string::npos) << refused.error;
  EXPECT_EQ(driver.snapshot().state.q1, 1.0);
  EXPECT_FALSE(driver.setState(State{1e300, 0.0, 1e300, 0.0}).ok) << "energy overflows";
}

// Reconfiguration: a new limit clamps the command in force; a new physical parameter changes
// u' from the next step and its energy jump lands in parameter_energy, so that
// E - W - parameter_energy stays constant across it (rk4 at 1 kHz: ~1e-8 J over 2 s, as
// without a change; a missing jump would show as ~1 J).
TEST_F(SimDriverTest, ReconfigureClampsAnewAndKeepsTheEnergyLedger) {
  Config config = test::defaultConfig();
  SimDriver driver = makeDriver(config);
  driver.command(20.0);
  Config next = config;
  next.command.torque_limit = 5.0;
  driver.reconfigure(next);
  EXPECT_EQ(driver.snapshot().torque, 5.0);
  EXPECT_EQ(driver.snapshot().command.commanded, 20.0);
  driver.command(0.0);

  auto ledger = [](const Snapshot& s) {
    return s.energy.total() - s.motor_work - s.parameter_energy;
  };
  for (int i = 0; i < 1000; ++i) driver.step();
  const double before = ledger(driver.snapshot());
  const double energy_before = driver.snapshot().energy.total();
  next.mechanism.slider4_mass = 1.6;
  next.mechanism.gravity = 5.0;
  next.mechanism.spring_stiffness = 350.0;
  driver.reconfigure(next);
  const Snapshot changed = driver.snapshot();
  EXPECT_EQ(changed.parameter_changes, 1u);
  EXPECT_NE(changed.energy.total(), energy_before);
  EXPECT_NEAR(changed.parameter_energy, changed.energy.total() - energy_before, 1e-12);
  const SpeedVector expected =
      MechanismModel(next.mechanism, mechanismModel(config).springRestLength())
          .accelerations(changed.state, 0.0);
  EXPECT_LT((changed.u_dot - expected).norm(), 1e-12 * expected.norm());
  for (int i = 0; i < 1000; ++i) driver.step();
  EXPECT_NEAR(ledger(driver.snapshot()), before, 1e-6);
}

}  // namespace
}  // namespace kane_sim

namespace kane_sim {
namespace {

// Drives `driver` one step with the test's command stream: a new command every 37 ticks
// (a torque, or a servo setpoint in the servo modes), so that commands, timeouts, delayed
// commands and the servo's integral all move.
void commandedStep(SimDriver* driver) {
  const std::uint64_t k = driver->ticks();
  if (k % 37 == 0) {
    const double v = std::sin(0.013 * static_cast<double>(k));
    if (driver->servoMode())
      driver->setpoint(0.6 + 0.4 * v);
    else
      driver->command(40.0 * v);
  }
  ASSERT_TRUE(driver->step());
}

struct CheckpointCase {
  const char* name;
  void (*adjust)(Config*);
};

// A driver restored from a checkpoint (through its text) steps on exactly as the original:
// every state, sensor reading and the final checkpoint bit for bit, for every option that
// keeps state between steps.
TEST(Checkpoint, ARestoredDriverStepsOnBitForBit) {
  const CheckpointCase cases[] = {
      {"rk4 effort", [](Config*) {}},
      {"dopri5", [](Config* c) { c->simulation.integrator = IntegratorType::kDopri5; }},
      {"generic equations", [](Config* c) { c->simulation.equations = EquationsSource::kGeneric; }},
      {"sensors, command latency",
       [](Config* c) {
         const Config s = loadConfigFile(test::configPath("mechanism.yaml")).config;
         c->sensors = s.sensors;
         c->sensors.enabled = true;
         c->sensors.rate = 100.0;
         c->sensors.latency = 0.004;
         c->sensors.latency_jitter = 0.005;
         c->sensors.command_latency = 0.003;
         c->sensors.joints[0].position_noise = 0.002;
         c->sensors.joints[0].velocity_noise = 0.05;
         c->sensors.joints[0].bias_walk = 0.001;
         c->sensors.joints[0].encoder_counts = 4096;
       }},
      {"position servo",
       [](Config* c) {
         c->command.mode = CommandMode::kPosition;
         c->command.feedforward = Feedforward::kHolding;
         c->command.position_ki = 200.0;
       }},
      {"velocity servo", [](Config* c) { c->command.mode = CommandMode::kVelocity; }},
      {"contact, damping, motor line",
       [](Config* c) {
         c->mechanism.contact.enabled = true;
         c->mechanism.damping.crank_joint = 0.2;
         c->mechanism.damping.slider4_joint = 1.0;
         c->mechanism.motor.no_load_speed = 30.0;
       }},
  };
  for (const CheckpointCase& test_case : cases) {
    SCOPED_TRACE(test_case.name);
    Config config = test::defaultConfig();
    config.command.timeout = 0.05;  // lapses between some commands
    test_case.adjust(&config);
    SimDriver original(config, {});
    for (int i = 0; i < 700; ++i) commandedStep(&original);
    const std::string text = checkpointText(original.checkpoint());
    SimDriver restored(config, {});
    restored.restore(parseCheckpoint(text));
    EXPECT_EQ(checkpointText(restored.checkpoint()), text);
    for (int i = 0; i < 1300; ++i) {
      commandedStep(&original);
      commandedStep(&restored);
      const Snapshot a = original.snapshot(), b = restored.snapshot();
      ASSERT_EQ(a.state.q1, b.state.q1) << "step " << i;
      ASSERT_EQ(a.state.u2, b.state.u2) << "step " << i;
      ASSERT_EQ(a.torque, b.torque) << "step " << i;
      ASSERT_EQ(a.energyBalance(), b.energyBalance()) << "step " << i;
      SensorReading ra, rb;
      while (original.takeSensorReading(&ra)) {
        ASSERT_TRUE(restored.takeSensorReading(&rb)) << "step " << i;
        ASSERT_EQ(ra.joints.position, rb.joints.position) << "step " << i;
        ASSERT_EQ(ra.joints.velocity, rb.joints.velocity) << "step " << i;
      }
      ASSERT_FALSE(restored.takeSensorReading(&rb)) << "step " << i;
    }
    EXPECT_EQ(checkpointText(restored.checkpoint()), checkpointText(original.checkpoint()));
  }
}

// A checkpoint that does not parse, or that belongs to another config, is refused by name and
// changes nothing.
TEST(Checkpoint, DamagedOrForeignCheckpointsAreRefusedByName) {
  Config config = test::defaultConfig();
  SimDriver driver(config, {});
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(driver.step());
  const std::string good = checkpointText(driver.checkpoint());
  const auto refused = [](const std::string& text, const std::string& expected) {
    try {
      parseCheckpoint(text);
      ADD_FAILURE() << "accepted: " << expected;
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  refused("", "not a kane_sim checkpoint");
  refused(good + "junk 1 2 3\n", "checkpoint field 'junk' is not one of");
  refused(good + std::string(70 << 20, '#'), "larger than any driver's");
  refused("garbage\nstate 1 2 3 4\n", "not a kane_sim checkpoint");
  std::string no_state = good;
  no_state.erase(no_state.find("state "),
                 no_state.find('\n', no_state.find("state ")) - no_state.find("state ") + 1);
  refused(no_state, "checkpoint field 'state' is missing");
  std::string bad_number = good;
  bad_number.replace(bad_number.find("ticks ") + 6, 2, "x1");
  refused(bad_number, "checkpoint field 'ticks'");
  std::string bad_random = good;
  bad_random.replace(bad_random.find("sensors_random ") + 15, 5, "zzzzz");
  SimDriver other(config, {});
  EXPECT_THROW(other.restore(parseCheckpoint(bad_random)), CheckpointError);
  EXPECT_EQ(other.ticks(), 0u) << "nothing changed";
  // Sensor readings in flight cannot go into a driver without sensors.
  Config with_sensors = config;
  with_sensors.sensors.enabled = true;
  with_sensors.sensors.latency = 0.02;
  SimDriver sensing(with_sensors, {});
  for (int i = 0; i < 15; ++i) ASSERT_TRUE(sensing.step());
  ASSERT_GT(sensing.sensors().pending(), 0u);
  EXPECT_THROW(other.restore(sensing.checkpoint()), CheckpointError);
  EXPECT_EQ(other.ticks(), 0u);
}

}  // namespace
}  // namespace kane_sim
