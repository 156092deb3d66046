#include "runtime_parameters.h"

#include <cstdint>
#include <utility>

#include <dynamic_reconfigure/Config.h>
#include <dynamic_reconfigure/ConfigDescription.h>
#include <dynamic_reconfigure/DoubleParameter.h>
#include <dynamic_reconfigure/GroupState.h>

#include "kane_sim/config/load_config.h"
#include "kane_sim/config/parameter_schema.h"
#include "kane_sim/ros/param_yaml.h"
#include "kane_sim/sim/config_check.h"
#include "kane_sim/sim/reconfiguration.h"

namespace kane_sim {
namespace {

std::vector<const ParameterSpec*> reconfigurableParameters() {
  std::vector<const ParameterSpec*> specs;
  for (const ParameterSpec& p : parameterSchema())
    if (p.reconfigurable()) specs.push_back(&p);
  return specs;
}

// dynamic_reconfigure's Config message: one group ("Default", as its generator names the top
// group) and a double per reconfigurable parameter.
dynamic_reconfigure::Config configMessage(double (*value)(const ParameterSpec&, const Config&),
                                          const Config& config) {
  dynamic_reconfigure::Config msg;
  for (const ParameterSpec* p : reconfigurableParameters()) {
    dynamic_reconfigure::DoubleParameter d;
    d.name = p->reconfigure.name;
    d.value = value(*p, config);
    msg.doubles.push_back(d);
  }
  dynamic_reconfigure::GroupState group;
  group.name = "Default";
  group.state = true;
  msg.groups.push_back(group);
  return msg;
}

double guiMin(const ParameterSpec& p, const Config&) { return p.reconfigure.gui_min; }
double guiMax(const ParameterSpec& p, const Config&) { return p.reconfigure.gui_max; }

// What dynparam and rqt_reconfigure read first: the parameters, their types, GUI bounds and the
// values of the config the node started with.
dynamic_reconfigure::ConfigDescription descriptionMessage(const Config& start) {
  dynamic_reconfigure::ConfigDescription msg;
  dynamic_reconfigure::Group group;
  group.name = "Default";
  for (const ParameterSpec* p : reconfigurableParameters()) {
    dynamic_reconfigure::ParamDescription d;
    d.name = p->reconfigure.name;
    d.type = "double";
    d.level = static_cast<std::uint32_t>(p->reconfigure.level);
    d.description = p->path() + (*p->symbol ? " " + std::string(p->symbol) : "") +
                    (*p->unit ? " [" + std::string(p->unit) + "]" : "") + ": " + p->doc;
    group.parameters.push_back(d);
  }
  msg.groups.push_back(group);
  msg.min = configMessage(guiMin, start);
  msg.max = configMessage(guiMax, start);
  msg.dflt = configMessage(numericValue, start);
  return msg;
}

}  // namespace

RuntimeParameters::RuntimeParameters(const ros::NodeHandle& private_nh, const YAML::Node& tree,
                                     const Config& config, Apply apply, Veto veto)
    : private_nh_(private_nh),
      tree_(YAML::Clone(tree)),
      start_(config),
      config_(config),
      apply_(std::move(apply)),
      veto_(std::move(veto)) {
  advertise();
}

void RuntimeParameters::advertise() {
  set_service_ =
      private_nh_.advertiseService("set_parameters", &RuntimeParameters::onSetParameters, this);
  descriptions_pub_ = private_nh_.advertise<dynamic_reconfigure::ConfigDescription>(
      "parameter_descriptions", 1, true);
  descriptions_pub_.publish(descriptionMessage(start_));
  updates_pub_ = private_nh_.advertise<dynamic_reconfigure::Config>("parameter_updates", 1, true);
  updates_pub_.publish(configMessage(numericValue, config_));
}

YAML::Node RuntimeParameters::readTree(const ros::NodeHandle& private_nh) {
  XmlRpc::XmlRpcValue params;
  if (!ros::param::get(private_nh.getNamespace(), params) ||
      params.getType() != XmlRpc::XmlRpcValue::TypeStruct)
    throw std::invalid_argument("no parameters in " + private_nh.getNamespace() +
                                ": load config/mechanism.yaml into the node's private namespace "
                                "(launch/sim.launch does)");
  YAML::Node tree = yamlFromXmlRpc(params);
  for (const std::string& ignored : removeServerKeys(&tree))
    ROS_WARN("kane_sim: %s", ignored.c_str());
  return tree;
}

Config RuntimeParameters::load(const YAML::Node& tree, const ros::NodeHandle& private_nh) {
  LoadedConfig loaded = loadSimulationConfig(tree);
  for (const std::string& warning : loaded.warnings)
    ROS_WARN("%s (in %s)", warning.c_str(), private_nh.getNamespace().c_str());
  return loaded.config;
}

std::vector<std::string> RuntimeParameters::removeServerKeys(YAML::Node* tree) {
  std::vector<std::string> removed;
  if (!tree->IsMap()) return removed;
  for (const ParameterSpec* p : reconfigurableParameters()) {
    const YAML::Node& view = *tree;  // const: looking a key up adds nothing
    const YAML::Node value = view[p->reconfigure.name];
    if (!value) continue;
    removed.push_back("private parameter ~" + std::string(p->reconfigure.name) + " = " +
                      (value.IsScalar() ? value.Scalar() : std::string("(not a number)")) +
                      " is not read: the config key is ~" + p->section + "/" + p->key +
                      " (to change it at run time: rosrun dynamic_reconfigure dynparam set)");
    tree->remove(p->reconfigure.name);
  }
  return removed;
}

std::string RuntimeParameters::change(const std::vector<std::pair<std::string, double>>& changes) {
  const Reconfiguration r = reconfigure(tree_, config_, changes, veto_);
  if (!r.refused.empty() || r.changed.empty()) return r.refused;
  tree_ = r.tree;
  config_ = r.config;
  // The parameter server holds the config in force under the config's own names.
  for (const ParameterSpec* p : r.changed)
    private_nh_.setParam(std::string(p->section) + "/" + p->key,
                         tree_[p->section][p->key].as<double>());
  apply_(config_);
  return "";
}

std::string RuntimeParameters::summary(const Config& config) {
  std::string text;
  for (const ParameterSpec* p : reconfigurableParameters())
    text += (text.empty() ? "" : ", ") + std::string(p->reconfigure.name) + " " +
            valueText(*p, config) + (*p->unit ? " " + std::string(p->unit) : "");
  return text;
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
  res.config = configMessage(numericValue, config_);  // what is in force, as the server answers
  updates_pub_.publish(res.config);
  return true;
}

}  // namespace kane_sim
