// Everything config/mechanism.yaml holds, as plain structs. The node (through rosparam), the
// offline tools and the tests all fill it through config/load_config.h. Optional settings carry
// their default here (the loader keeps it when the key is absent); required ones (mechanism,
// initial_state) come only from the file.
#ifndef KANE_SIM_CONFIG_CONFIG_H
#define KANE_SIM_CONFIG_CONFIG_H

#include <array>
#include <cmath>
#include <string>

#include "kane_sim/config/choices.h"
#include "kane_sim/model/joint_names.h"
#include "kane_sim/model/mechanism_model.h"
#include "kane_sim/model/mechanism_parameters.h"
#include "kane_sim/model/state.h"

namespace kane_sim {

// The physics steps in one period of `rate` when `rate` divides physics_rate into a whole number
// of steps, else 0. Within 1e-9 relative: a rate written in text (3 Hz of 999 Hz) is not exact.
// Outputs must sit on the physics grid: publish_rate here, simulate's --output-rate.
inline double wholeStepsPerPeriod(double physics_rate, double rate) {
  const double ratio = physics_rate / rate;
  const double whole = std::round(ratio);
  return std::abs(ratio - whole) <= 1e-9 * ratio ? whole : 0.0;
}

struct SimulationSettings {
  double physics_rate = 1000.0;  // [Hz], one physics step is 1/physics_rate of sim time
  IntegratorType integrator = IntegratorType::kRk4;
  EquationsSource equations = EquationsSource::kGenerated;
  double absolute_tolerance = 1e-9;  // dopri5 only
  double relative_tolerance = 1e-9;  // dopri5 only
  double publish_rate = 100.0;       // [Hz] joint_states, tf, mechanism_state
  double real_time_factor = 1.0;     // sim time per wall time; 0 = as fast as possible
  bool publish_clock = false;        // true: the node owns /clock
  bool start_paused = false;         // true: the node waits for `unpause` or `step`
  // Lockstep: the node steps past a published state only once a torque_command_stamped with that
  // state's stamp arrived (or lockstep_timeout wall seconds passed: then the fallback).
  bool lockstep = false;
  double lockstep_timeout = 1.0;  // [s] wall
  LockstepFallback lockstep_fallback = LockstepFallback::kHold;
  // > 0: the node's physics loop runs SCHED_FIFO at this priority with its memory locked.
  int realtime_priority = 0;
};

struct CommandSettings {
  double torque_limit = 50.0;  // [N m] |M_m| is clamped to this
  double timeout = 0.5;        // [s] no command for this long -> torque 0; 0 disables
  CommandMode mode = CommandMode::kEffort;
  Feedforward feedforward = Feedforward::kNone;
  double position_kp = 500.0;  // [N m/rad]
  double position_ki = 0.0;    // [N m/(rad s)]
  double position_kd = 30.0;   // [N m s/rad], on the measured speed (no kick on a step)
  double velocity_kp = 30.0;   // [N m s/rad]
  double velocity_ki = 300.0;  // [N m/rad]
};

struct FrameSettings {
  std::string prefix;           // prepended to every frame name
  std::string world = "world";  // REP-105 world frame, z up
  double pivot_height = 2.0;    // [m] height of O above the world origin
  // false: the node publishes no tf and leaves the tree to robot_state_publisher, which
  // computes it from robot_description and joint_states.
  bool publish_tf = true;
};

// When /diagnostics says the physics loop is behind (WARN): see LoopHealth.
struct DiagnosticsSettings {
  double overrun_fraction = 0.05;  // a 1 s window is late past this fraction of overrun ticks
  int late_windows = 3;            // WARN after this many consecutive late windows
};

// One joint's sensor as joint_states reports it (sensors.<joint>_*): the true value, plus a bias
// that walks, plus white noise, rounded to the encoder's counts. Units are the joint's: rad for
// crank and coupler, m for the sliders.
struct JointSensorSettings {
  double position_noise = 0.0;  // σ of the white noise on position [rad | m]
  double velocity_noise = 0.0;  // σ of the white noise on velocity [rad/s | m/s]
  double bias_walk = 0.0;       // position bias random walk: σ grows as this × √t [rad|m /√s]
  double encoder_counts = 0.0;  // counts per turn (rad joints) or per metre (sliders); 0: exact
};

// What joint_states carries when the sensors are on: the joints as sensors see them, sampled at
// `rate`, each message delayed as a whole by latency + U(0, latency_jitter) (never reordered).
// The torque path gets command_latency. All seeded: one seed, one sequence. Off: the truth.
struct SensorSettings {
  bool enabled = false;
  int seed = 1;
  double rate = 0.0;             // [Hz] readings per second; 0: simulation.publish_rate
  double latency = 0.0;          // [s] sample -> joint_states, rounded to physics steps
  double latency_jitter = 0.0;   // [s] extra delay, uniform in [0, this], in physics steps
  double command_latency = 0.0;  // [s] torque command -> in force, rounded to physics steps
  std::array<JointSensorSettings, kNumJoints> joints{};  // joint_states' order
};

// How the estimator (`observer`, estimate/) trusts the model and when it raises its alarm; the
// sensors' noise model above is its measurement model.
struct EstimatorSettings {
  double crank_acceleration_noise = 0.05;     // [rad/s^2/sqrt(Hz)] model error on u1'
  double slider4_acceleration_noise = 0.005;  // [m/s^2/sqrt(Hz)] model error on u2'
  double alarm_window = 0.5;                  // [s] readings per test of the innovations
  double false_alarms_per_hour = 0.001;       // ERROR's rate on a rig that is its model
  double restart_gap = 1.0;                   // [s] a longer silence restarts the filter
  // [s] how uncertain the instant a controller's answer to a reading takes effect, beyond the
  // sensors' jitter: a ROS transport and scheduler (0 for a drive that applies it at a known tick)
  double answer_timing_noise = 0.002;
};

// At most this many parameters a recorded motion can tell (the schema's identifiable rows: 15).
constexpr int kMaxIdentifiable = 24;

struct Config {
  MechanismParameters mechanism;
  State initial_state;  // q10, q20, u10, u20; the spring is unstretched at (q10, q20)
  SimulationSettings simulation;
  CommandSettings command;
  FrameSettings frames;
  DiagnosticsSettings diagnostics;
  SensorSettings sensors;
  EstimatorSettings estimator;
  // uncertainty.<section.key>: each identifiable parameter's standard error (identify writes
  // it), in the schema's order of those parameters; 0 = known exactly. The estimator takes the
  // model as uncertain by this much.
  std::array<double, kMaxIdentifiable> uncertainty{};
};

// Sensor readings per second of sim time: sensors.rate, or simulation.publish_rate when it is 0;
// none with the sensors off.
inline double sensorReadingRate(const Config& config) {
  if (!config.sensors.enabled) return 0.0;
  return config.sensors.rate > 0 ? config.sensors.rate : config.simulation.publish_rate;
}

// The most sensor readings a config may keep in flight ((latency + latency_jitter) x reading
// rate): each is ~150 bytes, so at most ~15 MB (1 MHz readings 10 s late once took 1.2 GB).
constexpr double kMaxReadingsInFlight = 1e5;

// The model a config describes: its parameters, the spring unstretched at the initial state.
inline MechanismModel mechanismModel(const Config& config) {
  const State& x0 = config.initial_state;
  return MechanismModel(
      config.mechanism,
      mechanismGeometry(config.mechanism.rod_half_length, x0.q1, x0.q2).sliderSeparation());
}

}  // namespace kane_sim

#endif  // KANE_SIM_CONFIG_CONFIG_H
