// The one config loader: YAML (a file, or a node converted from rosparam) -> validated Config.
#ifndef KANE_SIM_CONFIG_LOAD_CONFIG_H
#define KANE_SIM_CONFIG_LOAD_CONFIG_H

#include <stdexcept>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "kane_sim/config/config.h"
#include "kane_sim/config/parameter_schema.h"

namespace kane_sim {

// A bad configuration: `key()` is the dotted path of the offending entry (e.g.
// "mechanism.rod_mass"), what() a full sentence naming the key and the value.
class ConfigError : public std::runtime_error {
 public:
  ConfigError(const std::string& key, const std::string& problem);
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

struct LoadedConfig {
  Config config;
  std::vector<std::string> unknown_keys;  // dotted paths the loader does not read
  std::vector<std::string> warnings;      // unknown keys, one sentence each
};

// Throws ConfigError on a missing required key, a wrong type or an out-of-range value.
LoadedConfig loadConfig(const YAML::Node& root);

// One number into `config` by its schema row's rule (finite, positive, its range, whole): the
// loader's own check and message, under `key`. How loadConfig stores a number, and how a batch
// sets 10^6 mechanisms' numbers without a YAML round trip each (numbers_into_configs.h).
void storeNumber(const std::string& key, const ParameterSpec& spec, double value, Config* config);
// One YAML document from a file; ConfigError (key "file") when it cannot be read or parsed.
YAML::Node loadYamlFile(const std::string& path);
// The same from text in memory (the browser's pasted or uploaded config): the same limits and
// messages, with `name` where a file's would name its path.
YAML::Node loadYamlText(const std::string& text, const std::string& name);
// loadConfig(loadYamlFile(path)).
LoadedConfig loadConfigFile(const std::string& path);

// The package's config/mechanism.yaml (installed share folder, else the source tree it was built
// from): what the offline tools run when no --config is given. ConfigError (key "file") when
// neither exists.
std::string defaultConfigFile();

// Sets `section`.`key` in a config tree (the section created when absent or empty), as a user
// would edit the file: how a reconfiguration, a sweep case and simulate's --integrator change a
// config before it goes through loadConfig again. ConfigError when the section is not a map.
void setConfigValue(YAML::Node& root, const std::string& section, const std::string& key,
                    const YAML::Node& value);

// "rk4" -> kRk4, ...; throws ConfigError(key, ...) listing the valid names otherwise.
IntegratorType parseIntegratorName(const std::string& name, const std::string& key);
// "generated" -> kGenerated, "generic" -> kGeneric; throws ConfigError(key, ...) otherwise.
EquationsSource parseEquationsName(const std::string& name, const std::string& key);

}  // namespace kane_sim

#endif  // KANE_SIM_CONFIG_LOAD_CONFIG_H
