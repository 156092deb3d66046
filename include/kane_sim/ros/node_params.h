// Numeric private parameters of the small nodes (pd_controller, teleop_key, crank_marker): a
// value that is absent keeps its default, one that is present must be a number, and where a
// bound is asked for, finite and within it. Errors name the fully resolved parameter and the
// value, so the node can exit with a message that says what to fix. Header-only: it needs
// roscpp and nothing of this package's libraries.
#ifndef KANE_SIM_ROS_NODE_PARAMS_H
#define KANE_SIM_ROS_NODE_PARAMS_H

#include <cmath>
#include <stdexcept>
#include <string>

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

}  // namespace kane_sim

#endif  // KANE_SIM_ROS_NODE_PARAMS_H
