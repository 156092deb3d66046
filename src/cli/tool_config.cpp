#include "kane_sim/cli/tool_config.h"

#include <iostream>

namespace kane_sim {
namespace cli {

ToolConfig loadToolConfig(const std::string& tool, const std::optional<std::string>& path) {
  ToolConfig out;
  if (path) {
    out.path = *path;
  } else {
    try {
      out.path = defaultConfigFile();
    } catch (const ConfigError& e) {
      throw ToolConfigError(tool + ": no --config given and " + e.what());
    }
    std::cerr << tool << ": no --config given: using the package's default " << out.path << "\n";
  }
  try {
    out.loaded = loadConfigFile(out.path);
  } catch (const ConfigError& e) {
    throw ToolConfigError(tool + ": bad config: " + e.what());
  }
  for (const std::string& warning : out.loaded.warnings)
    std::cerr << tool << ": " << warning << "\n";
  return out;
}

}  // namespace cli
}  // namespace kane_sim
