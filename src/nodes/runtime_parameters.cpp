#include "runtime_parameters.h"

#include <utility>

#include "kane_sim/config/load_config.h"

namespace kane_sim {
namespace {

// The config key each reconfigurable value is (section, key).
struct Binding {
  const char* name;  // in cfg/KaneSim.cfg
  const char* section;
  const char* key;
  double KaneSimConfig::*value;
};

const Binding kBindings[] = {
    {"torque_limit", "command", "torque_limit", &KaneSimConfig::torque_limit},
    {"command_timeout", "command", "timeout", &KaneSimConfig::command_timeout},
    {"real_time_factor", "simulation", "real_time_factor", &KaneSimConfig::real_time_factor},
    {"rod_mass", "mechanism", "rod_mass", &KaneSimConfig::rod_mass},
    {"slider3_mass", "mechanism", "slider3_mass", &KaneSimConfig::slider3_mass},
    {"slider4_mass", "mechanism", "slider4_mass", &KaneSimConfig::slider4_mass},
    {"spring_stiffness", "mechanism", "spring_stiffness", &KaneSimConfig::spring_stiffness},
    {"gravity", "mechanism", "gravity", &KaneSimConfig::gravity},
    {"motor_no_load_speed", "command", "motor_no_load_speed", &KaneSimConfig::motor_no_load_speed},
    {"crank_damping", "damping", "crank_joint", &KaneSimConfig::crank_damping},
    {"coupler_damping", "damping", "coupler_joint", &KaneSimConfig::coupler_damping},
    {"slider3_damping", "damping", "slider3_joint", &KaneSimConfig::slider3_damping},
    {"slider4_damping", "damping", "slider4_joint", &KaneSimConfig::slider4_damping},
};

}  // namespace

RuntimeParameters::RuntimeParameters(const ros::NodeHandle& private_nh, const YAML::Node& tree,
                                     const Config& config, Apply apply)
    : tree_(YAML::Clone(tree)), config_(config), apply_(std::move(apply)) {
  server_ = std::make_unique<dynamic_reconfigure::Server<KaneSimConfig>>(mutex_, private_nh);
  // The config file, not leftovers on the parameter server or the .cfg defaults, is what the
  // node starts with.
  KaneSimConfig start = valuesOf(config_);
  server_->updateConfig(start);
  server_->setCallback([this](KaneSimConfig& values, uint32_t level) { onChange(values, level); });
}

void RuntimeParameters::removeServerKeys(YAML::Node* tree) {
  if (!tree->IsMap()) return;
  for (const Binding& b : kBindings) tree->remove(b.name);
}

KaneSimConfig RuntimeParameters::valuesOf(const Config& c) {
  KaneSimConfig v;
  v.torque_limit = c.command.torque_limit;
  v.command_timeout = c.command.timeout;
  v.real_time_factor = c.simulation.real_time_factor;
  v.rod_mass = c.mechanism.rod_mass;
  v.slider3_mass = c.mechanism.slider3_mass;
  v.slider4_mass = c.mechanism.slider4_mass;
  v.spring_stiffness = c.mechanism.spring_stiffness;
  v.gravity = c.mechanism.gravity;
  v.motor_no_load_speed = c.mechanism.motor.no_load_speed;
  v.crank_damping = c.mechanism.damping.crank;
  v.coupler_damping = c.mechanism.damping.coupler;
  v.slider3_damping = c.mechanism.damping.slider3;
  v.slider4_damping = c.mechanism.damping.slider4;
  return v;
}

void RuntimeParameters::onChange(KaneSimConfig& values, uint32_t /*level*/) {
  const KaneSimConfig current = valuesOf(config_);
  YAML::Node tree = YAML::Clone(tree_);
  bool changed = false;
  for (const Binding& b : kBindings) {
    if (values.*(b.value) == current.*(b.value)) continue;  // untouched keys stay as written
    tree[b.section][b.key] = values.*(b.value);
    changed = true;
  }
  if (!changed) return;
  try {
    LoadedConfig loaded = loadConfig(tree);
    tree_ = tree;
    config_ = loaded.config;
    apply_(config_);
  } catch (const ConfigError& e) {
    ROS_ERROR("kane_sim: reconfiguration refused, %s; keeping the previous values", e.what());
    values = current;  // the server publishes and answers with what is in force
  }
}

}  // namespace kane_sim
