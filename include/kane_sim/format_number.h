// Numbers in messages: the shortest form that reads back as the same double (0.1, 1e+200, -50),
// "nan" for every NaN (never "-nan"), "inf"/"-inf". Header-only: used by every layer's
// messages and by the small nodes, which link none of the libraries.
#ifndef KANE_SIM_FORMAT_NUMBER_H
#define KANE_SIM_FORMAT_NUMBER_H

#include <charconv>
#include <cmath>
#include <string>

namespace kane_sim {

inline std::string formatNumber(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[32];
  const std::to_chars_result r = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, r.ptr);
}

}  // namespace kane_sim

#endif  // KANE_SIM_FORMAT_NUMBER_H
