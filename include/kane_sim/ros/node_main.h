// What every kane_sim node does before it touches ROS, the same for all of them:
//   - `--help` / `-h` prints the usage and exits 0 without contacting a master (ros::init would
//     register the node and, under a taken name, kill the running one);
//   - ros::init's refusal of a name (an invalid ns:=, __name:= or remapping, e.g. "robot-a")
//     exits 1 with a message naming it instead of aborting on an uncaught exception.
#ifndef KANE_SIM_ROS_NODE_MAIN_H
#define KANE_SIM_ROS_NODE_MAIN_H

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include <ros/ros.h>

namespace kane_sim {

// Call first in main: prints `usage` and exits 0 when --help or -h is among the arguments.
inline void exitOnHelp(int argc, char** argv, const char* usage) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
      std::fputs(usage, stdout);
      std::exit(0);
    }
  }
}

// ros::init with its name errors turned into exit 1 and a message.
inline void initNode(int& argc, char** argv, const char* name, uint32_t options) {
  try {
    ros::init(argc, argv, name, options);
  } catch (const ros::InvalidNameException& e) {
    std::fprintf(stderr,
                 "%s: %s\n  (a namespace, node name or remapping must start with a letter and "
                 "hold only letters, digits, '_' and '/': check ns:=, node_name:= or __ns:=)\n",
                 name, e.what());
    std::exit(1);
  }
}

}  // namespace kane_sim

#endif  // KANE_SIM_ROS_NODE_MAIN_H
