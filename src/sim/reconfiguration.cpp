#include "kane_sim/sim/reconfiguration.h"

#include "kane_sim/config/load_config.h"
#include "kane_sim/sim/config_check.h"

namespace kane_sim {

Reconfiguration reconfigure(const YAML::Node& tree, const Config& current,
                            const std::vector<std::pair<std::string, double>>& changes,
                            const std::function<std::string(const Config&)>& veto) {
  Reconfiguration r;
  YAML::Node changed_tree = YAML::Clone(tree);
  for (const auto& [name, value] : changes) {
    const ParameterSpec* p = findReconfigurable(name);
    if (!p) {
      r.refused = "'" + name + "' is not a reconfigurable parameter of kane_sim_node";
      return r;
    }
    if (value == numericValue(*p, current)) continue;  // untouched keys stay as written
    try {
      setConfigValue(changed_tree, p->section, p->key, YAML::Node(value));
    } catch (const ConfigError& e) {
      r.refused = e.what();
      return r;
    }
    r.changed.push_back(p);
  }
  if (r.changed.empty()) return r;
  try {
    LoadedConfig loaded = loadSimulationConfig(changed_tree);
    const std::string vetoed = veto ? veto(loaded.config) : "";
    if (!vetoed.empty()) {
      r.refused = vetoed;
      r.changed.clear();
      return r;
    }
    r.tree = changed_tree;
    r.config = loaded.config;
  } catch (const ConfigError& e) {
    r.refused = e.what();
    r.changed.clear();
  }
  return r;
}

}  // namespace kane_sim
