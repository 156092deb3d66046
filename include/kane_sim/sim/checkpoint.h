// A checkpoint of the simulation driver: everything it remembers beyond its config — the
// state, tick and energy ledger, the command in force with its timeout clock and the commands
// still delayed, the servo's setpoint and integral, the sensors' random state, biases and
// readings in flight, dopri5's step size — so that a driver built from the same config and
// restored from it steps on exactly as the original (bit for bit). The node publishes one on
// ~checkpoint; `simulate --replay` starts a bag from it.
//
// As text: "kane_sim checkpoint 1" then one "name value ..." line per field, doubles as
// hexadecimal floats (exact both ways).
#ifndef KANE_SIM_SIM_CHECKPOINT_H
#define KANE_SIM_SIM_CHECKPOINT_H

#include <cstdint>
#include <deque>
#include <stdexcept>
#include <string>

#include "kane_sim/control/crank_servo.h"
#include "kane_sim/sensors/joint_sensors.h"
#include "kane_sim/sim/simulator.h"
#include "kane_sim/sim/torque_command.h"

namespace kane_sim {

struct DelayedCommand {
  std::uint64_t due_tick = 0;
  double torque = 0.0;
};

struct DriverCheckpoint {
  Simulator::Dynamics simulator;
  TorqueCommand::Memory command;
  std::deque<DelayedCommand> delayed_commands;  // sensors.command_latency: not yet in force
  double setpoint = 0.0;                        // a servo's, [rad | rad/s]
  double servo_integral = 0.0;
  ServoStatus servo_status;
  JointSensors::Memory sensors;
};

struct CheckpointError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

std::string checkpointText(const DriverCheckpoint& checkpoint);
// Throws CheckpointError naming the line or field that is missing or does not parse.
DriverCheckpoint parseCheckpoint(const std::string& text);

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_CHECKPOINT_H
