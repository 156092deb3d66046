#include "runtime_parameters.h"

#include <sstream>
#include <utility>

#include <dynamic_reconfigure/Config.h>
#include <dynamic_reconfigure/ConfigDescription.h>

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

const Binding* bindingOf(const std::string& name) {
  for (const Binding& b : kBindings)
    if (name == b.name) return &b;
  return nullptr;
}

}  // namespace

RuntimeParameters::RuntimeParameters(const ros::NodeHandle& private_nh, const YAML::Node& tree,
                                     const Config& config, Apply apply)
    : private_nh_(private_nh), tree_(YAML::Clone(tree)), config_(config), apply_(std::move(apply)) {
  advertise();
}

void RuntimeParameters::advertise() {
  set_service_ =
      private_nh_.advertiseService("set_parameters", &RuntimeParameters::onSetParameters, this);
  descriptions_pub_ = private_nh_.advertise<dynamic_reconfigure::ConfigDescription>(
      "parameter_descriptions", 1, true);
  descriptions_pub_.publish(KaneSimConfig::__getDescriptionMessage__());
  updates_pub_ = private_nh_.advertise<dynamic_reconfigure::Config>("parameter_updates", 1, true);
  publishValues();
}

void RuntimeParameters::removeServerKeys(YAML::Node* tree) {
  if (!tree->IsMap()) return;
  for (const Binding& b : kBindings) tree->remove(b.name);
}

KaneSimConfig RuntimeParameters::valuesOf(const Config& c) {
  KaneSimConfig v = KaneSimConfig::__getDefault__();
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

void RuntimeParameters::publishValues() {
  dynamic_reconfigure::Config msg;
  valuesOf(config_).__toMessage__(msg);
  updates_pub_.publish(msg);
}

std::string RuntimeParameters::change(const std::vector<std::pair<std::string, double>>& changes) {
  const KaneSimConfig current = valuesOf(config_);
  YAML::Node tree = YAML::Clone(tree_);
  std::vector<const Binding*> changed;
  for (const auto& [name, value] : changes) {
    const Binding* b = bindingOf(name);
    if (!b) return "'" + name + "' is not a reconfigurable parameter of kane_sim_node";
    if (value == current.*(b->value)) continue;  // untouched keys stay as written
    tree[b->section][b->key] = value;
    changed.push_back(b);
  }
  if (changed.empty()) return "";
  try {
    LoadedConfig loaded = loadConfig(tree);
    tree_ = tree;
    config_ = loaded.config;
  } catch (const ConfigError& e) {
    return e.what();
  }
  // The parameter server holds the config in force under the config's own names.
  for (const Binding* b : changed)
    private_nh_.setParam(std::string(b->section) + "/" + b->key,
                         tree_[b->section][b->key].as<double>());
  apply_(config_);
  return "";
}

bool RuntimeParameters::onSetParameters(dynamic_reconfigure::Reconfigure::Request& req,
                                        dynamic_reconfigure::Reconfigure::Response& res) {
  std::vector<std::pair<std::string, double>> changes;
  std::string refused;
  for (const auto& d : req.config.doubles) changes.emplace_back(d.name, d.value);
  const auto wrongType = [&refused](const std::string& name, const char* type) {
    if (refused.empty())
      refused = "'" + name + "' was sent as " + type + "; kane_sim_node's parameters are doubles";
  };
  for (const auto& p : req.config.bools) wrongType(p.name, "a bool");
  for (const auto& p : req.config.ints) wrongType(p.name, "an int");
  for (const auto& p : req.config.strs) wrongType(p.name, "a string");
  if (refused.empty()) refused = change(changes);
  if (!refused.empty())
    ROS_ERROR("kane_sim: reconfiguration refused, %s; keeping the previous values",
              refused.c_str());
  valuesOf(config_).__toMessage__(res.config);  // what is in force, as the server answers
  publishValues();
  return true;
}

}  // namespace kane_sim
