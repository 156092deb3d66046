// The config an offline tool works on: --config FILE, or the package's default (said on stderr),
// loaded by the one loader and its warnings printed, each line prefixed with the tool's name.
// One piece for analyze and design, so they find, refuse and warn alike.
#ifndef KANE_SIM_CLI_TOOL_CONFIG_H
#define KANE_SIM_CLI_TOOL_CONFIG_H

#include <optional>
#include <stdexcept>
#include <string>

#include "kane_sim/config/load_config.h"

namespace kane_sim {
namespace cli {

// What stops a tool: the message is whole ("analyze: bad config: ..."); exit code 1.
class ToolConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ToolConfig {
  std::string path;
  LoadedConfig loaded;
};

ToolConfig loadToolConfig(const std::string& tool, const std::optional<std::string>& path);

}  // namespace cli
}  // namespace kane_sim

#endif  // KANE_SIM_CLI_TOOL_CONFIG_H
