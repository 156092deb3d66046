// A change of parameters at run time, as dynamic_reconfigure asks the node for it and as the
// browser's parameter panel asks its session: the names are the schema's reconfigurable ones,
// the values go into the config's YAML tree where a user would edit them, and the whole tree goes
// through the loader and the start-up check again, so a change is refused with the loader's own
// words. ROS-free: the node's dynamic_reconfigure server only translates.
#ifndef KANE_SIM_SIM_RECONFIGURATION_H
#define KANE_SIM_SIM_RECONFIGURATION_H

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "kane_sim/config/config.h"
#include "kane_sim/config/parameter_schema.h"

namespace kane_sim {

struct Reconfiguration {
  std::string refused;                        // "" when accepted, else why (nothing changed)
  YAML::Node tree;                            // accepted: the tree with the new values
  Config config;                              // accepted: the config loaded from it
  std::vector<const ParameterSpec*> changed;  // the rows whose value changed (empty: no change)
};

// `changes` (reconfigurable names -> values) as one change of the config `current`, loaded from
// `tree`. A value equal to the one in force is not written (untouched keys stay as written);
// `veto` may refuse a config the loader accepts (the node: a never-sleeping loop at real-time
// priority).
Reconfiguration reconfigure(const YAML::Node& tree, const Config& current,
                            const std::vector<std::pair<std::string, double>>& changes,
                            const std::function<std::string(const Config&)>& veto = {});

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_RECONFIGURATION_H
