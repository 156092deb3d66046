// Numbers in messages: the shortest form that reads back as the same double (0.1, 1e+200, -50),
// "nan" for every NaN (never "-nan"), "inf"/"-inf". Header-only: used by every layer's
// messages and by the small nodes, which link none of the libraries.
#ifndef KANE_SIM_FORMAT_NUMBER_H
#define KANE_SIM_FORMAT_NUMBER_H

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace kane_sim {

// std::to_chars(buffer, buffer + 32, value)'s text, built from printf's digits: the shortest
// digits that read back as `value` (printf rounds correctly, so the first precision that reads
// back gives the digits closest to the value, as to_chars does), in fixed or scientific notation,
// whichever is shorter, fixed on a tie. For a standard library without floating-point to_chars
// (emscripten 3.1.6's libc++, the browser's build); a test holds it to to_chars natively.
inline char* shortestCharsByPrintf(char* buffer, double value) {
  char* out = buffer;
  if (std::signbit(value)) *out++ = '-';
  const double magnitude = std::fabs(value);
  if (std::isnan(value) || std::isinf(value) || magnitude == 0.0) {
    const char* text = std::isnan(value) ? "nan" : std::isinf(value) ? "inf" : "0";
    std::strcpy(out, text);
    return out + std::strlen(text);
  }
  char scientific[40];
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(scientific, sizeof scientific, "%.*e", precision - 1, magnitude);
    if (std::strtod(scientific, nullptr) == magnitude) break;
  }
  // scientific = d[.ddd]e±XX: the digits and the exponent
  char digits[20];
  int count = 0;
  const char* p = scientific;
  for (; *p != 'e'; ++p)
    if (*p != '.') digits[count++] = *p;
  const int exponent = std::atoi(p + 1);
  while (count > 1 && digits[count - 1] == '0') --count;
  char fixed[400];
  int n = 0;
  if (exponent >= 0 && count <= exponent + 1) {
    // A whole number: to_chars prints its exact digits, as printf's %.0f does (same length).
    n = std::snprintf(fixed, sizeof fixed, "%.0f", magnitude);
  } else if (exponent >= 0) {
    for (int i = 0; i < count || i <= exponent; ++i) {
      if (i == exponent + 1) fixed[n++] = '.';
      fixed[n++] = i < count ? digits[i] : '0';
    }
  } else {
    fixed[n++] = '0';
    fixed[n++] = '.';
    for (int i = 0; i < -exponent - 1; ++i) fixed[n++] = '0';
    for (int i = 0; i < count; ++i) fixed[n++] = digits[i];
  }
  char shortest_scientific[40];
  int s = 0;
  shortest_scientific[s++] = digits[0];
  if (count > 1) {
    shortest_scientific[s++] = '.';
    for (int i = 1; i < count; ++i) shortest_scientific[s++] = digits[i];
  }
  s += std::snprintf(shortest_scientific + s, sizeof shortest_scientific - s, "e%c%02d",
                     exponent < 0 ? '-' : '+', std::abs(exponent));
  const char* chosen = n <= s ? fixed : shortest_scientific;
  const int length = n <= s ? n : s;
  std::memcpy(out, chosen, length);
  return out + length;
}

// The shortest text of `value` into `buffer` (32 chars at least): std::to_chars's; returns the end.
inline char* shortestChars(char* buffer, double value) {
#if defined(__cpp_lib_to_chars) || (defined(__GLIBCXX__) && __GNUC__ >= 11)
  return std::to_chars(buffer, buffer + 32, value).ptr;
#else
  return shortestCharsByPrintf(buffer, value);
#endif
}

inline std::string formatNumber(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buffer[32];
  return std::string(buffer, shortestChars(buffer, value));
}

// A time [s] for a message: to the nanosecond (far below any physics step), then as formatNumber
// does, so that a sim time summed step by step reads 19.99, not 19.990000000000002.
inline std::string formatTime(double seconds) {
  if (!std::isfinite(seconds) || std::fabs(seconds) > 1e9) return formatNumber(seconds);
  return formatNumber(std::round(seconds * 1e9) / 1e9);
}

}  // namespace kane_sim

#endif  // KANE_SIM_FORMAT_NUMBER_H
