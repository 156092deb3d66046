// Runtime reconfiguration of the node: the dynamic_reconfigure protocol (dynparam, rqt_reconfigure)
// over the one config loader. A change is written into the YAML tree the node was started from
// and that tree goes through the loader again: the same rules, messages and defaults as the
// config file (e.g. a config without rod_inertia keeps I = m (2L)^2 / 12 when rod_mass changes).
//
// The protocol is served here rather than by dynamic_reconfigure::Server, which (a) clamps every
// value to the .cfg's min/max before anyone sees it (torque_limit -50 became 0, gravity inf
// became 100) and (b) mirrors every value as a flat parameter beside the config's own names
// (/kane_sim/spring_stiffness = 400 while /kane_sim/mechanism/spring_stiffness stayed 200). Here
// the parameters, their descriptions and GUI bounds come from the one parameter schema
// (config/parameter_schema.h; there is no .cfg), the bounds only bound a GUI's sliders; a value is
// refused (naming the config key and the value) or accepted, and an accepted one is written back
// under its config name only, so `rosparam get /kane_sim` is the config in force.
#ifndef KANE_SIM_NODES_RUNTIME_PARAMETERS_H
#define KANE_SIM_NODES_RUNTIME_PARAMETERS_H

#include <functional>
#include <string>
#include <vector>

#include <dynamic_reconfigure/Reconfigure.h>
#include <ros/ros.h>
#include <yaml-cpp/yaml.h>

#include "kane_sim/config/config.h"

namespace kane_sim {

class RuntimeParameters {
 public:
  using Apply = std::function<void(const Config&)>;
  // Why the node cannot take `config` now ("" when it can): rules of the running node that a
  // config file cannot know (e.g. real_time_factor 0 under SCHED_FIFO).
  using Veto = std::function<std::string(const Config&)>;

  // `tree`: the YAML the node's config was loaded from; `apply` receives each accepted config
  // that `veto` (when given) does not refuse.
  RuntimeParameters(const ros::NodeHandle& private_nh, const YAML::Node& tree, const Config& config,
                    Apply apply, Veto veto = {});

  // Offers the service and the latched topics (again, after a master restart).
  void advertise();

  // Applies `changes` (dynamic_reconfigure names -> values) as one change. Returns "" when
  // accepted (or nothing changed), else why it was refused (nothing changed then).
  std::string change(const std::vector<std::pair<std::string, double>>& changes);

  // The node's private namespace as the YAML tree the config loader reads (the server keys
  // below left out, each named in a warning); std::invalid_argument when it holds none.
  static YAML::Node readTree(const ros::NodeHandle& private_nh);
  // The simulation's config from that tree (the loader's warnings logged); ConfigError names
  // a bad value.
  static Config load(const YAML::Node& tree, const ros::NodeHandle& private_nh);

  // Names the node's parameter namespace may hold that are not config keys: what older
  // kane_sim versions (and dynamic_reconfigure::Server) mirrored there. A config read from that
  // namespace leaves them out; returned, one line each, for a warning (a user who sets
  // ~spring_stiffness meant ~mechanism/spring_stiffness).
  static std::vector<std::string> removeServerKeys(YAML::Node* tree);

  // The config in force as the YAML tree it was loaded from (for ~checkpoint).
  const YAML::Node& tree() const { return tree_; }

  // The reconfigurable values of `config`, for the log: "torque_limit 50 N m, ...".
  static std::string summary(const Config& config);

 private:
  bool onSetParameters(dynamic_reconfigure::Reconfigure::Request& req,
                       dynamic_reconfigure::Reconfigure::Response& res);

  ros::NodeHandle private_nh_;
  YAML::Node tree_;
  Config start_;   // the description's defaults
  Config config_;  // in force
  Apply apply_;
  Veto veto_;
  ros::ServiceServer set_service_;
  ros::Publisher descriptions_pub_;
  ros::Publisher updates_pub_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_RUNTIME_PARAMETERS_H
