#include "kane_sim/web/live_session.h"

#include <cmath>
#include <stdexcept>

#include "kane_sim/config/load_config.h"
#include "kane_sim/config/parameter_schema.h"
#include "kane_sim/format_number.h"
#include "kane_sim/sim/config_check.h"
#include "kane_sim/sim/csv_format.h"
#include "kane_sim/sim/profile_commands.h"
#include "kane_sim/sim/reconfiguration.h"

namespace kane_sim {
namespace web {

LiveSession::LiveSession(const std::string& yaml_text, const std::string& config_name)
    : LiveSession(loadYamlText(yaml_text, config_name)) {}

LiveSession::LiveSession(const YAML::Node& tree) : LiveSession(tree, loadSimulationConfig(tree)) {}

LiveSession::LiveSession(const YAML::Node& tree, const LoadedConfig& loaded)
    : tree_(tree), config_(loaded.config), robot_(describeRobot(loaded.config)) {
  for (const std::string& warning : loaded.warnings) events_.push_back(warning);
  rebuild(config_);
}

void LiveSession::rebuild(const Config& config) {
  config_ = config;
  robot_ = describeRobot(config_);
  driver_ = std::make_unique<SimDriver>(config_, [this](const SimEvent& event) {
    events_.push_back(event.message + " (at t = " + formatTime(event.time) + " s)");
    if (events_.size() > kMaxEvents) events_.pop_front();
  });
}

std::vector<double> LiveSession::advance(double seconds, double value, long sample_every) {
  if (!(seconds >= 0.0 && seconds <= kMaxAdvance))
    throw std::invalid_argument("seconds must be in [0, " + formatNumber(kMaxAdvance) +
                                "] s, got " + formatNumber(seconds));
  if (!std::isfinite(value))
    throw std::invalid_argument("the command must be finite, got " + formatNumber(value));
  if (sample_every < 1)
    throw std::invalid_argument("sampleEvery must be >= 1, got " + std::to_string(sample_every));
  const double rate = config_.simulation.physics_rate;
  const long steps = seconds > 0 ? std::max(1L, std::lround(seconds * rate)) : 0;
  // A constant command re-sent every frame, as a node commanding at the frame rate; within a
  // long frame the profile's stream re-sends it before command.timeout lapses.
  const TorqueProfile held = TorqueProfile::constant(value);
  ProfileCommands commands(held, config_.command.timeout);
  commands.update(*driver_);
  std::vector<double> rows;
  const std::vector<CsvColumn>& columns = csvColumns();
  runProfile(
      *driver_, commands, steps, sample_every, nullptr, [](const SimDriver&) {},
      [&](const SimDriver& d) {
        const Snapshot snapshot = d.snapshot();
        for (const CsvColumn& c : columns) rows.push_back(c.value(snapshot));
      });
  return rows;
}

void LiveSession::reset() { driver_->reset(); }

std::string LiveSession::setParameter(const std::string& name, double value) {
  const Reconfiguration r = reconfigure(tree_, config_, {{name, value}});
  if (!r.refused.empty() || r.changed.empty()) return r.refused;
  tree_ = r.tree;
  config_ = r.config;
  robot_ = describeRobot(config_);
  driver_->reconfigure(config_);
  return "";
}

std::string LiveSession::setMode(const std::string& mode) {
  YAML::Node tree = YAML::Clone(tree_);
  try {
    setConfigValue(tree, "command", "mode", YAML::Node(mode));
    const LoadedConfig loaded = loadSimulationConfig(tree);
    // The new driver takes the old one's whole memory (sim time, the ledger, the command in
    // force): the motion and its plots go on; only the drive changes. The new mode's servo
    // starts from the old setpoint (the page sends the crank's angle at once).
    const DriverCheckpoint memory = driver_->checkpoint();
    rebuild(loaded.config);
    tree_ = tree;
    try {
      driver_->restore(memory);
    } catch (const std::exception&) {  // cannot happen for a mode change; the state at least
      driver_->setState(memory.simulator.state);
    }
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

std::string LiveSession::setInitialState(const std::string& key, double value) {
  const ParameterSpec* spec = findParameter("initial_state", key);
  if (spec == nullptr || spec->role != ParameterRole::kInitialState)
    return "'" + key + "' is not a key of initial_state (q1, q2, u1, u2)";
  YAML::Node tree = YAML::Clone(tree_);
  try {
    setConfigValue(tree, "initial_state", key, YAML::Node(value));
    const LoadedConfig loaded = loadSimulationConfig(tree);
    rebuild(loaded.config);
    tree_ = tree;
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

std::vector<double> LiveSession::row() const {
  const Snapshot snapshot = driver_->snapshot();
  std::vector<double> values;
  for (const CsvColumn& c : csvColumns()) values.push_back(c.value(snapshot));
  return values;
}

std::string LiveSession::configYaml() const {
  YAML::Emitter out;
  out << tree_;
  return out.c_str();
}

std::vector<LinkOutline> LiveSession::outlinesAt(const JointValues& joints) const {
  return linkOutlines(robot_, joints);
}

std::vector<std::pair<std::string, Eigen::Vector2d>> LiveSession::originsAt(
    const JointValues& joints) const {
  return linkOrigins(robot_, joints);
}

JointValues LiveSession::jointsAt(double q1, double q2) const {
  State x;
  x.q1 = q1;
  x.q2 = q2;
  return jointValues(driver_->simulator().model().kinematics(x), x, 0.0);
}

std::vector<std::string> LiveSession::takeEvents() {
  std::vector<std::string> taken(events_.begin(), events_.end());
  events_.clear();
  return taken;
}

}  // namespace web
}  // namespace kane_sim
