// `config_info`: what launch files need to know of a config before any node runs, read
// through the one config loader (so a bad config fails here with the same message as in the
// node).
//
//   config_info urdf FILE [--frame-prefix P]   the robot_description (URDF) of FILE
//   config_info use_sim_time FILE              true when FILE's simulation.publish_clock is
//   config_info parameters                     every config parameter (the table of
//                                              doc/reference/parameters.md)
//   config_info outputs                        every output quantity (the table of
//                                              doc/reference/outputs.md)
//
// launch/sim.launch sets robot_description and /use_sim_time from these before starting
// robot_state_publisher and rviz, which read both once at start-up. Exit codes: 0 ok, 1 bad
// config, 2 bad command line.
#include <iostream>
#include <string>
#include <vector>

#include "kane_sim/config/load_config.h"
#include "kane_sim/config/parameter_schema.h"
#include "kane_sim/description/robot_description.h"
#include "kane_sim/description/urdf.h"
#include "kane_sim/sim/csv_format.h"

namespace {

constexpr const char* kUsage =
    "usage: config_info urdf FILE [--frame-prefix PREFIX]\n"
    "       config_info use_sim_time FILE\n"
    "       config_info parameters [--text | KEY]\n"
    "       config_info outputs\n\n"
    "What kane_sim's launch files and docs read from a config, without a ROS master:\n"
    "  urdf FILE          the robot_description (URDF) of FILE's mechanism (sim.launch's)\n"
    "  use_sim_time FILE  true or false: FILE's simulation.publish_clock (/use_sim_time)\n"
    "  parameters         every config parameter as the Markdown table of\n"
    "                     doc/reference/parameters.md;\n"
    "                     --text: the same for a terminal; KEY (e.g. mechanism.rod_mass): one\n"
    "  outputs            every output quantity (CSV column, Python name, mechanism_state\n"
    "                     field) as the Markdown table of doc/reference/outputs.md\n"
    "Exit 0 on success, 1 for a config the loader refuses, 2 for a usage error, 4 when the\n"
    "output cannot be written.\n";

int usage(const std::string& problem) {
  std::cerr << "error: " << problem << "\n" << kUsage;
  return 2;
}

int run(const std::vector<std::string>& args) {
  for (const std::string& arg : args) {
    if (arg == "-h" || arg == "--help") {
      std::cout << kUsage;
      return 0;
    }
  }
  if (args.empty()) return usage("a command is needed");
  const std::string& command = args[0];
  if (command != "urdf" && command != "use_sim_time" && command != "parameters" &&
      command != "outputs")
    return usage("unknown command '" + command + "' (urdf, use_sim_time, parameters or outputs)");
  if (!args.empty() && args[0] == "outputs") {
    if (args.size() > 1) return usage("outputs takes no argument");
    std::cout << kane_sim::outputTable();
    return 0;
  }
  if (!args.empty() && args[0] == "parameters") {
    if (args.size() > 2) return usage("parameters takes at most one argument: --text or a KEY");
    if (args.size() == 1) {
      std::cout << kane_sim::parameterTable();
    } else if (args[1] == "--text") {
      std::cout << kane_sim::parametersText();
    } else {
      try {
        std::cout << kane_sim::parameterText(args[1]);
      } catch (const std::invalid_argument& e) {
        return usage(e.what());
      }
    }
    return 0;
  }
  if (args.size() < 2) return usage(command + " needs a config FILE");
  const std::string& path = args[1];
  try {
    YAML::Node tree = kane_sim::loadYamlFile(path);
    if (command == "urdf") {
      if (args.size() == 4 && args[2] == "--frame-prefix") {
        if (tree.IsMap()) tree["frames"]["prefix"] = args[3];
      } else if (args.size() != 2) {
        return usage("urdf takes FILE and optionally --frame-prefix PREFIX");
      }
      const kane_sim::LoadedConfig loaded = kane_sim::loadConfig(tree);
      std::cout << kane_sim::toUrdf(kane_sim::describeRobot(loaded.config));
      return 0;
    }
    if (command == "use_sim_time") {
      if (args.size() != 2) return usage("use_sim_time takes only FILE");
      const kane_sim::LoadedConfig loaded = kane_sim::loadConfig(tree);
      std::cout << (loaded.config.simulation.publish_clock ? "true" : "false") << "\n";
      return 0;
    }
    return usage("unknown command '" + command + "'");  // not reached: checked above
  } catch (const kane_sim::ConfigError& e) {
    std::cerr << "error: " << path << ": " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {  // e.g. a frames section that is not a map
    std::cerr << "error: " << path << ": " << e.what() << "\n";
    return 1;
  }
}

}  // namespace

int main(int argc, char** argv) {
  const int code = run(std::vector<std::string>(argv + 1, argv + argc));
  std::cout.flush();
  if (!std::cout) {  // a full disk or a closed pipe: the table or URDF did not arrive
    std::cerr << "error: could not write the output\n";
    return 4;
  }
  return code;
}
