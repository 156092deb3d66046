// Shared by the unit tests: the shipped config files, loaded through the real loader.
#ifndef KANE_SIM_TEST_HELPERS_H
#define KANE_SIM_TEST_HELPERS_H

#include <sstream>
#include <string>
#include <vector>

#include "kane_sim/load_config.h"

namespace kane_sim {
namespace test {

inline std::string configPath(const std::string& file) {
  return std::string(KANE_SIM_CONFIG_DIR) + "/" + file;
}
inline Config defaultConfig() { return loadConfigFile(configPath("mechanism.yaml")).config; }
inline Config textbookConfig() { return loadConfigFile(configPath("textbook.yaml")).config; }

// The rows of a CSV written by `simulate` (header returned separately).
inline std::vector<std::vector<double>> parseCsv(const std::string& text, std::string* header) {
  std::istringstream in(text);
  std::getline(in, *header);
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::istringstream fields(line);
    std::string field;
    while (std::getline(fields, field, ',')) row.push_back(std::stod(field));
    rows.push_back(row);
  }
  return rows;
}

}  // namespace test
}  // namespace kane_sim

#endif  // KANE_SIM_TEST_HELPERS_H
