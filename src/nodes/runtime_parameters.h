// Runtime reconfiguration of the node (dynamic_reconfigure, cfg/KaneSim.cfg). A change is
// written into the YAML tree the node was started from and that tree goes through the one
// config loader again: the same rules, messages and defaults as the config file (e.g. a
// config without rod_inertia keeps I = m (2L)^2 / 12 when rod_mass changes). A refused change
// is reverted in the server and logged naming the key and the value.
#ifndef KANE_SIM_NODES_RUNTIME_PARAMETERS_H
#define KANE_SIM_NODES_RUNTIME_PARAMETERS_H

#include <functional>
#include <memory>

#include <dynamic_reconfigure/server.h>
#include <yaml-cpp/yaml.h>
#include <boost/thread/recursive_mutex.hpp>

#include "kane_sim/KaneSimConfig.h"
#include "kane_sim/config/config.h"

namespace kane_sim {

class RuntimeParameters {
 public:
  using Apply = std::function<void(const Config&)>;

  // `tree`: the YAML the node's config was loaded from; `apply` receives each accepted config.
  RuntimeParameters(const ros::NodeHandle& private_nh, const YAML::Node& tree, const Config& config,
                    Apply apply);

  // The flat parameters the server keeps in the node's namespace (torque_limit, ...): a config
  // read from that namespace leaves them out (they mirror the config, they are not config).
  static void removeServerKeys(YAML::Node* tree);

 private:
  void onChange(KaneSimConfig& values, uint32_t level);
  static KaneSimConfig valuesOf(const Config& config);

  YAML::Node tree_;
  Config config_;
  Apply apply_;
  boost::recursive_mutex mutex_;  // the server's; all its calls come from the node's one thread
  std::unique_ptr<dynamic_reconfigure::Server<KaneSimConfig>> server_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_RUNTIME_PARAMETERS_H
