// Numeric private parameters of the small nodes (pd_controller, teleop_key, crank_marker): a
// value that is absent keeps its default, one that is present must be a number, and where a
// bound is asked for, finite and within it. Errors name the fully resolved parameter and the
// value, so the node can exit with a message that says what to fix. Header-only: it needs
// roscpp and nothing of this package's libraries.
#ifndef KANE_SIM_ROS_NODE_PARAMS_H
#define KANE_SIM_ROS_NODE_PARAMS_H

#include <cmath>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <vector>

#include <ros/node_handle.h>

#include "kane_sim/format_number.h"

namespace kane_sim {

enum class ParamBound { kAnyFinite, kNonNegative, kPositive };

// The parameter `name` of `pnh`, or `fallback` when absent. Throws std::invalid_argument when it
// is present but not a number.
inline double numberParam(const ros::NodeHandle& pnh, const std::string& name, double fallback) {
  double value = fallback;
  if (pnh.hasParam(name) && !pnh.getParam(name, value))
    throw std::invalid_argument("parameter " + pnh.resolveName(name) + " must be a number");
  return value;
}

// As numberParam, and finite and within `bound` (the default too).
inline double boundedParam(const ros::NodeHandle& pnh, const std::string& name, double fallback,
                           ParamBound bound) {
  const double value = numberParam(pnh, name, fallback);
  const bool ok = std::isfinite(value) && (bound != ParamBound::kNonNegative || value >= 0) &&
                  (bound != ParamBound::kPositive || value > 0);
  if (!ok)
    throw std::invalid_argument("parameter " + pnh.resolveName(name) + " must be finite" +
                                (bound == ParamBound::kNonNegative ? " and >= 0"
                                 : bound == ParamBound::kPositive  ? " and > 0"
                                                                   : "") +
                                ", got " + formatNumber(value));
  return value;
}

// The boolean parameter `name` of `pnh`, or `fallback` when absent. Throws std::invalid_argument
// when it is present but not true or false (a typo such as "yes" is not silently false).
inline bool flagParam(const ros::NodeHandle& pnh, const std::string& name, bool fallback) {
  bool value = fallback;
  if (pnh.hasParam(name) && !pnh.getParam(name, value))
    throw std::invalid_argument("parameter " + pnh.resolveName(name) + " must be true or false");
  return value;
}

// The file path parameter `name` of `pnh`, or "" when absent. Throws std::invalid_argument when
// it is present but not a string (`_setpoint_table:=5` is read as the number 5, not a file).
inline std::string pathParam(const ros::NodeHandle& pnh, const std::string& name) {
  XmlRpc::XmlRpcValue value;
  if (!pnh.getParam(name, value)) return "";
  if (value.getType() == XmlRpc::XmlRpcValue::TypeString) return static_cast<std::string>(value);
  std::string shown = value.toXml();
  if (value.getType() == XmlRpc::XmlRpcValue::TypeInt)
    shown = std::to_string(static_cast<int>(value));
  else if (value.getType() == XmlRpc::XmlRpcValue::TypeDouble)
    shown = formatNumber(static_cast<double>(value));
  else if (value.getType() == XmlRpc::XmlRpcValue::TypeBoolean)
    shown = static_cast<bool>(value) ? "true" : "false";
  throw std::invalid_argument("parameter " + pnh.resolveName(name) + " must be a file path, got " +
                              shown);
}

// The private parameters of `pnh` not among `known` (a typo such as ~setpoint_tabel, which
// would otherwise be left unread without a word), by their resolved names.
inline std::vector<std::string> unknownParams(const ros::NodeHandle& pnh,
                                              std::initializer_list<const char*> known) {
  std::vector<std::string> all, unknown;
  if (!pnh.getParamNames(all)) return unknown;
  const std::string prefix = pnh.getNamespace() + "/";
  for (const std::string& name : all) {
    if (name.rfind(prefix, 0) != 0) continue;
    const std::string key =
        name.substr(prefix.size(), name.find('/', prefix.size()) - prefix.size());
    bool found = false;
    for (const char* k : known) found = found || key == k;
    if (!found && (unknown.empty() || unknown.back() != prefix + key))
      unknown.push_back(prefix + key);
  }
  return unknown;
}

}  // namespace kane_sim

#endif  // KANE_SIM_ROS_NODE_PARAMS_H
