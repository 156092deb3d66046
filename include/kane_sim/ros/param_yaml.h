// rosparam's view of a namespace (XmlRpc) -> the YAML tree the one config loader reads, so the
// node validates its parameters with exactly the rules `simulate` applies to a file.
#ifndef KANE_SIM_ROS_PARAM_YAML_H
#define KANE_SIM_ROS_PARAM_YAML_H

#include <xmlrpcpp/XmlRpcValue.h>
#include <yaml-cpp/yaml.h>

namespace kane_sim {

YAML::Node yamlFromXmlRpc(XmlRpc::XmlRpcValue& value);

}  // namespace kane_sim

#endif  // KANE_SIM_ROS_PARAM_YAML_H
