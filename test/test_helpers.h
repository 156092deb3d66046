// Shared by the unit tests: the shipped config files, loaded through the real loader.
#ifndef KANE_SIM_TEST_HELPERS_H
#define KANE_SIM_TEST_HELPERS_H

#include <string>

#include "kane_sim/load_config.h"

namespace kane_sim {
namespace test {

inline std::string configPath(const std::string& file) {
  return std::string(KANE_SIM_CONFIG_DIR) + "/" + file;
}
inline Config defaultConfig() { return loadConfigFile(configPath("mechanism.yaml")).config; }
inline Config textbookConfig() { return loadConfigFile(configPath("textbook.yaml")).config; }

}  // namespace test
}  // namespace kane_sim

#endif  // KANE_SIM_TEST_HELPERS_H
