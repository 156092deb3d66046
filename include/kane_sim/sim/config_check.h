// Whether a config can be simulated: what the loader cannot judge from the values alone. The
// loader (config/load_config.h) checks each value and the rules between values; this asks the
// model and the integrator: the initial state through Simulator::checkUsable (the same check as
// set_state), and with rk4 the stiffest motion over a sampled turn of the crank
// (analysis/stability.h). The node (start-up and every reconfiguration), `simulate` and each
// sweep case load through loadSimulationConfig; `analyze` and `config_info`, which integrate
// nothing, through loadConfig.
#ifndef KANE_SIM_SIM_CONFIG_CHECK_H
#define KANE_SIM_SIM_CONFIG_CHECK_H

#include <yaml-cpp/yaml.h>

#include "kane_sim/config/load_config.h"

namespace kane_sim {

// Throws ConfigError: key "initial_state" for a state the simulator cannot start from,
// "simulation.physics_rate" when rk4 at that rate cannot follow the mechanism's fastest motion,
// "mechanism" when its equations are not finite.
void checkSimulatable(const Config& config);

// loadConfig, then checkSimulatable.
LoadedConfig loadSimulationConfig(const YAML::Node& root);
LoadedConfig loadSimulationConfigFile(const std::string& path);

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_CONFIG_CHECK_H
