// The browser's live mechanism: one SimDriver driven the way a node drives it (a torque, or a
// servo's setpoint, commanded every frame), advanced by the page's clock, reconfigured through
// the schema as dynamic_reconfigure reconfigures the node, reset, stepped one physics step at a
// time; its rows are simulate's CSV columns. Plain C++: the page's Web Worker calls it through
// src/web/bindings.cpp; the unit tests call it directly.
#ifndef KANE_SIM_WEB_LIVE_SESSION_H
#define KANE_SIM_WEB_LIVE_SESSION_H

#include <deque>
#include <memory>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "kane_sim/config/config.h"
#include "kane_sim/config/load_config.h"
#include "kane_sim/description/robot_description.h"
#include "kane_sim/sim/sim_driver.h"
#include "kane_sim/web/outlines.h"

namespace kane_sim {
namespace web {

class LiveSession {
 public:
  // The most sim time one advance() covers [s]: a frame of a page running 1000x real time.
  static constexpr double kMaxAdvance = 60.0;
  // Events kept for the page between two takeEvents() (the oldest dropped beyond).
  static constexpr size_t kMaxEvents = 50;

  // Throws ConfigError, as runCase does, for a config the loader or the start-up check refuses.
  LiveSession(const std::string& yaml_text, const std::string& config_name);

  // Advances by `seconds` of sim time (whole physics steps; at least one when > 0) commanding
  // `value`: a torque [N m] in command.mode effort, else the servo's setpoint. Returns the CSV
  // rows sampled every `sample_every` steps (and the last), one after the other. A refused step
  // ends the advance early (the event says why). Throws std::invalid_argument naming the
  // argument for seconds outside [0, kMaxAdvance], a non-finite value or sample_every < 1.
  std::vector<double> advance(double seconds, double value, long sample_every);

  // The driver's reset: the config's initial state, the ledger from zero.
  void reset();
  // One reconfigurable parameter (its dynamic_reconfigure name); "" when accepted, else the
  // loader's refusal (nothing changed).
  std::string setParameter(const std::string& name, double value);
  // command.mode "effort" | "position" | "velocity": the driver rebuilt from the config with that
  // mode, going on from the old one's state, sim time and ledger. "" when accepted, else the
  // refusal (nothing changed).
  std::string setMode(const std::string& mode);
  // initial_state.<key> (q1, q2, u1, u2): the motion restarts there, at t = 0 with the ledger
  // from zero, through the loader's checks (the spring is unstretched at the new (q10, q20), as
  // the config says). "" when accepted, else the refusal naming the key (nothing changed).
  std::string setInitialState(const std::string& key, double value);

  std::vector<double> row() const;  // simulate's CSV row of this instant
  double time() const { return driver_->time(); }
  std::uint64_t ticks() const { return driver_->ticks(); }
  const Config& config() const { return config_; }
  // The config in force as YAML (the loaded text with every accepted change): what a share
  // link carries and what simulate runs for the same numbers.
  std::string configYaml() const;
  // The drawing now, or at joint values from elsewhere (a bag's joint_states, a CSV's q1, q2):
  // this session's mechanism posed by them.
  std::vector<LinkOutline> outlines() const { return outlinesAt(driver_->snapshot().joints); }
  std::vector<LinkOutline> outlinesAt(const JointValues& joints) const;
  std::vector<std::pair<std::string, Eigen::Vector2d>> origins() const {
    return originsAt(driver_->snapshot().joints);
  }
  std::vector<std::pair<std::string, Eigen::Vector2d>> originsAt(const JointValues& joints) const;
  // Joint values at (q1, q2) standing still, no torque: what a CSV's or a state's q gives.
  JointValues jointsAt(double q1, double q2) const;
  // The driver's events since the last call (warnings, refusals), each a sentence with its time.
  std::vector<std::string> takeEvents();

 private:
  explicit LiveSession(const YAML::Node& tree);
  LiveSession(const YAML::Node& tree, const LoadedConfig& loaded);
  void rebuild(const Config& config);  // a new driver (and drawing) from `config`

  YAML::Node tree_;
  Config config_;
  RobotDescription robot_;
  std::unique_ptr<SimDriver> driver_;
  std::deque<std::string> events_;
};

}  // namespace web
}  // namespace kane_sim

#endif  // KANE_SIM_WEB_LIVE_SESSION_H
