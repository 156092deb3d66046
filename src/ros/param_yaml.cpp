#include "kane_sim/ros/param_yaml.h"

#include <cmath>
#include <cstdio>
#include <string>

namespace kane_sim {

YAML::Node yamlFromXmlRpc(XmlRpc::XmlRpcValue& value) {
  switch (value.getType()) {
    case XmlRpc::XmlRpcValue::TypeStruct: {
      YAML::Node map(YAML::NodeType::Map);
      for (auto& entry : value) map[entry.first] = yamlFromXmlRpc(entry.second);
      return map;
    }
    case XmlRpc::XmlRpcValue::TypeArray: {
      YAML::Node list(YAML::NodeType::Sequence);
      for (int i = 0; i < value.size(); ++i) list.push_back(yamlFromXmlRpc(value[i]));
      return list;
    }
    case XmlRpc::XmlRpcValue::TypeBoolean:
      return YAML::Node(static_cast<bool>(value) ? "true" : "false");
    case XmlRpc::XmlRpcValue::TypeInt:
      return YAML::Node(std::to_string(static_cast<int>(value)));
    case XmlRpc::XmlRpcValue::TypeDouble: {
      // YAML spells the non-finite values .nan/.inf; keep them so the loader names them.
      const double d = value;
      if (std::isnan(d)) return YAML::Node(".nan");
      if (std::isinf(d)) return YAML::Node(d > 0 ? ".inf" : "-.inf");
      char buffer[32];
      std::snprintf(buffer, sizeof(buffer), "%.17g", d);
      return YAML::Node(std::string(buffer));
    }
    case XmlRpc::XmlRpcValue::TypeString:
      return YAML::Node(static_cast<std::string>(value));
    default:
      return YAML::Node(YAML::NodeType::Null);
  }
}

}  // namespace kane_sim
