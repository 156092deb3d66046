// A number a user types on a command line (analyze's and design's flags): all of the text, in
// decimal (no hex, no inf or nan, no spaces), or pi / -pi for an angle. One parser for every tool
// that takes one, so that they accept and refuse the same text.
#ifndef KANE_SIM_CLI_NUMBER_ARGUMENT_H
#define KANE_SIM_CLI_NUMBER_ARGUMENT_H

#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace kane_sim {

// Throws std::invalid_argument "<flag> must be a finite number, got '<text>'".
inline double numberArgument(const std::string& text, const std::string& flag, bool angle = false) {
  if (angle && text == "pi") return M_PI;
  if (angle && text == "-pi") return -M_PI;
  const bool decimal =
      !text.empty() && text.find_first_not_of("0123456789+-.eE") == std::string::npos;
  char* end = nullptr;
  const double value = decimal ? std::strtod(text.c_str(), &end) : NAN;
  if (!decimal || end != text.c_str() + text.size() || !std::isfinite(value))
    throw std::invalid_argument(flag + " must be a finite number, got '" + text + "'");
  return value;
}

// An angle [rad] (a number, pi or -pi) within 1e6 rad (beyond, sin and cos of it keep few digits).
inline double angleArgument(const std::string& text, const std::string& flag) {
  const double value = numberArgument(text, flag, true);
  if (std::abs(value) > 1e6)
    throw std::invalid_argument(flag + " must be an angle within 1e6 rad, got '" + text + "'");
  return value;
}

}  // namespace kane_sim

#endif  // KANE_SIM_CLI_NUMBER_ARGUMENT_H
