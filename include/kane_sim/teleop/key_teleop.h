// What teleop_key does with a key, in the spirit of turtle_teleop_key: in torque mode the
// arrows step the crank torque M_m; in setpoint mode they step the crank angle the PD
// controller holds. ROS-free: the node only reads the terminal and publishes what this says.
//
//   right / d   + step          up / w     step x 2
//   left  / a   - step          down / s   step / 2
//   space       torque 0 (torque mode) / setpoint 0 (setpoint mode)
//   t           torque mode     p          setpoint mode (starts at the crank's angle)
//   h / ?       help            q          quit (torque 0 first)
#ifndef KANE_SIM_TELEOP_KEY_TELEOP_H
#define KANE_SIM_TELEOP_KEY_TELEOP_H

#include <optional>
#include <string>

#include "kane_sim/teleop/key_decoder.h"

namespace kane_sim {

enum class TeleopMode { kTorque, kSetpoint };

struct TeleopSettings {
  TeleopMode mode = TeleopMode::kTorque;  // the mode at start
  double torque_step = 0.5;               // [N m] per key press
  double torque_limit = 20.0;             // [N m] |torque| never exceeds it
  double setpoint_step = 0.1;             // [rad] per key press
};

// Checks finite and > 0 steps and limit; throws std::invalid_argument naming the field and value.
void validate(const TeleopSettings& settings);

enum class TeleopEvent {
  kNone,             // a key with no meaning here (ignored)
  kTorqueChanged,    // publish torque()
  kSetpointChanged,  // publish setpoint()
  kStepChanged,      // nothing to publish; show status()
  kModeChanged,      // publish what the new mode commands (torque 0, or the setpoint)
  kHelp,             // show help()
  kQuit,             // publish torque 0 if in torque mode, then stop
};

class KeyTeleop {
 public:
  explicit KeyTeleop(const TeleopSettings& settings);

  TeleopEvent press(const Key& key);
  // The crank angle q1 last read from joint_states: setpoint mode starts there, so switching
  // to it does not yank the crank.
  void setCrankAngle(double q1) { crank_angle_ = q1; }

  TeleopMode mode() const { return mode_; }
  double torque() const { return torque_; }      // [N m] M_m to command (torque mode)
  double setpoint() const { return setpoint_; }  // [rad] q1 to hold (setpoint mode)
  std::string status() const;                    // one line: mode, value, step
  static std::string help();

 private:
  double& step();
  double initialStep() const;
  void nudge(double direction);

  TeleopSettings settings_;
  TeleopMode mode_;
  double torque_ = 0.0;
  double setpoint_ = 0.0;
  double torque_step_;
  double setpoint_step_;
  std::optional<double> crank_angle_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_TELEOP_KEY_TELEOP_H
