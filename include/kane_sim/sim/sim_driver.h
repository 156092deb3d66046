// The one simulation driver: the Simulator plus the command handling, stepped the same way by
// the node, by `simulate` and by the tests. It reports what a user must hear about as events;
// the node logs them with rosconsole, `simulate` prints them on stderr.
#ifndef KANE_SIM_SIM_SIM_DRIVER_H
#define KANE_SIM_SIM_SIM_DRIVER_H

#include <cstdint>
#include <deque>
#include <functional>
#include <string>

#include "kane_sim/config/config.h"
#include "kane_sim/control/crank_servo.h"
#include "kane_sim/sensors/joint_sensors.h"
#include "kane_sim/sim/checkpoint.h"
#include "kane_sim/sim/simulator.h"
#include "kane_sim/sim/snapshot.h"
#include "kane_sim/sim/torque_command.h"

namespace kane_sim {

// What kFirstSliderCrossing says (the batched simulator's lanes say it too).
extern const char* const kSliderCrossingReport;

struct SimEvent {
  enum class Kind {
    kCommandRejected,      // a non-finite torque command was ignored (every time)
    kCommandClamped,       // a torque command beyond command.torque_limit (every time)
    kCommandTimedOut,      // no command for command.timeout: 0 N m from now on (once per lapse)
    kFirstSliderCrossing,  // slider 4 passed through slider 3 (once per start or reset)
    kStepTooCoarse,        // rk4 no longer resolves the crank's motion (once per start or reset)
    kStepRefused,          // the step would have gone non-finite; state kept (every time)
  };
  Kind kind;
  double time;          // [s] sim time
  std::string message;  // a full sentence naming the values and, where there is one, the fix
};

// An input as the driver received it (refused ones too), at the tick it arrived: what the node
// publishes on ~input_log and `simulate --replay` feeds to a fresh driver (SimDriver::apply).
struct DriverInput {
  enum class Kind { kTorque = 0, kSetpoint = 1, kReset = 2, kSetState = 3 };
  Kind kind = Kind::kTorque;
  std::uint64_t tick = 0;
  double value = 0.0;  // kTorque [N m], kSetpoint [rad | rad/s]
  State state;         // kSetState: as requested
};

class SimDriver {
 public:
  using EventHandler = std::function<void(const SimEvent&)>;
  using InputHandler = std::function<void(const DriverInput&)>;

  // on_event is called synchronously from command() and step(); it may be empty.
  SimDriver(const Config& config, EventHandler on_event);

  // A torque command [N m] arriving at the current sim time: in force from this instant on,
  // i.e. held over the next step; with sensors.command_latency, that many steps later (a
  // non-finite one is refused at once, a clamp is reported when it takes effect).
  TorqueCommand::Verdict command(double torque);

  // command.mode velocity | position: the servo's setpoint [rad/s | rad], in force at once (the
  // servo runs in the drive at every step). Refused (kRejected, reported) when not finite, beyond
  // what the integrator can follow, or in effort mode.
  TorqueCommand::Verdict setpoint(double value);
  // Why setpoint(value) would be refused, or "" (the check alone: nothing is recorded).
  std::string setpointProblem(double value) const;
  bool servoMode() const { return config_.command.mode != CommandMode::kEffort; }
  const Config& config() const { return config_; }  // the config in force (reconfigured)

  // One physics step with the command in force (0 N m after a timeout). False when the step
  // was refused: the last good state is kept. Afterwards the torque in force is that of the
  // new instant (the command may have timed out).
  bool step();

  // What ~step_with_command does, ROS-free: `steps` physics steps with `torque` held (a command
  // stream re-sent before the command timeout could lapse, through the same clamp and motor line
  // as command()). `stop_reason` is asked every kHeldStepsCheckEvery steps; a reason ends the
  // call there. A bad request (effort mode only; torque finite; steps in [1, kMaxHeldSteps]) is
  // refused before anything moves. `message` says what happened, for the caller's answer.
  struct HeldSteps {
    bool refused = false;   // nothing ran
    bool finished = false;  // every step ran
    std::string message;
  };
  static constexpr std::uint64_t kMaxHeldSteps = 1000000;  // a typo such as 4e9 is refused
  static constexpr long kHeldStepsCheckEvery = 64;
  HeldSteps stepHeld(double torque, std::uint64_t steps,
                     const std::function<std::string()>& stop_reason);

  // Initial state, motor work 0, command forgotten (and any still delayed); sim time runs on.
  // Sensor readings in flight are dropped: they show the state before.
  void reset();

  // A chosen state (Simulator::setState): the command in force is kept. Refused with the
  // reason when a value is not finite.
  Status setState(const State& state);

  // Runtime reconfiguration from a validated config: new mechanism parameters (at the current
  // state, from the next step on) and command settings. Initial state, rates and integrator
  // stay those the driver was built with.
  void reconfigure(const Config& config);

  Snapshot snapshot() const;  // the physics of this instant and the command status

  // Everything the driver remembers beyond its config (sim/checkpoint.h). restore() into a
  // driver built from the same config (the config in force: reconfigured values included)
  // makes it step on exactly as this one; refused (CheckpointError, nothing changed) when the
  // checkpoint cannot belong to such a driver (readings in flight with the sensors off, say).
  DriverCheckpoint checkpoint() const;
  void restore(const DriverCheckpoint& checkpoint);

  // Called with every input, before it is applied (empty: none).
  void setInputHandler(InputHandler on_input) { on_input_ = std::move(on_input); }
  // The call that `input` records (its tick is the caller's to match).
  void apply(const DriverInput& input);

  // Sensors (config sensors:): the oldest reading due by now, taken off the queue; false when
  // none is due or the sensors are off. Readings are sampled at every step on their grid.
  bool takeSensorReading(SensorReading* reading) { return sensors_.takeDue(ticks(), reading); }
  bool sensorsEnabled() const { return sensors_.enabled(); }
  const JointSensors& sensors() const { return sensors_; }

  const Simulator& simulator() const { return sim_; }
  double time() const { return sim_.time(); }
  std::uint64_t ticks() const { return sim_.ticks(); }

 private:
  void applyCommand();  // the command handling's torque at the current time -> the simulator
  TorqueCommand::Verdict receive(double torque);  // a command reaching the drive now
  void deliverDelayedCommands();                  // those whose command_latency has passed
  void updateServo(double dt);  // servo modes: the servo's command at this instant -> simulator
  double initialSetpoint() const;
  void sampleSensors() {
    sensors_.onTick(sim_.ticks(), sim_.time(), [this] { return sim_.joints(); });
  }
  void report(SimEvent::Kind kind, std::string message) const;
  void record(DriverInput::Kind kind, double value = 0.0, const State& state = State{}) const {
    if (on_input_) on_input_(DriverInput{kind, sim_.ticks(), value, state});
  }

  Config config_;
  Simulator sim_;
  TorqueCommand command_;
  EventHandler on_event_;
  InputHandler on_input_;
  JointSensors sensors_;
  CrankServo servo_;
  double setpoint_;
  std::uint64_t command_latency_ticks_;
  std::deque<DelayedCommand> delayed_commands_;  // in arrival order, so in due order
};

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_SIM_DRIVER_H
