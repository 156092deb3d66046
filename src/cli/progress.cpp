#include "kane_sim/cli/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <utility>

namespace kane_sim {
namespace cli {
namespace {

constexpr auto kRedrawEvery = std::chrono::milliseconds(250);

std::string duration(double seconds) {
  char text[32];
  if (seconds < 90)
    std::snprintf(text, sizeof text, "%.0f s", seconds);
  else if (seconds < 5400)
    std::snprintf(text, sizeof text, "%.0f min", seconds / 60);
  else
    std::snprintf(text, sizeof text, "%.1f h", seconds / 3600);
  return text;
}

}  // namespace

Progress::Progress(std::ostream& out, std::string what, double total, std::string unit, bool shown)
    : out_(out),
      what_(std::move(what)),
      unit_(std::move(unit)),
      total_(total),
      shown_(shown && std::isfinite(total) && total > 0),
      start_(std::chrono::steady_clock::now()),
      last_(start_) {}

Progress::Progress(std::string what, double total, std::string unit)
    : Progress(std::cerr, std::move(what), total, std::move(unit), isatty(STDERR_FILENO) == 1) {}

void Progress::update(double done) {
  if (!shown_) return;
  if (drawn_ && ++calls_ % 64 != 0) return;
  const auto now = std::chrono::steady_clock::now();
  if (drawn_ && now - last_ < kRedrawEvery) return;
  draw(done, now);
}

void Progress::draw(double done, std::chrono::steady_clock::time_point now) {
  last_ = now;
  drawn_ = true;
  const double fraction = std::min(std::max(done / total_, 0.0), 1.0);
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  char line[160];
  std::snprintf(line, sizeof line, "%s: %.1f %% (%.6g of %.6g %s)", what_.c_str(), 100 * fraction,
                done, total_, unit_.c_str());
  std::string text = line;
  if (fraction > 0 && elapsed > 0.5)
    text += ", " + duration(elapsed * (1 - fraction) / fraction) + " left";
  out_ << "\r\033[K" << text << std::flush;  // back to the line's start, erase it, draw
}

void Progress::clear() {
  if (!drawn_) return;
  out_ << "\r\033[K" << std::flush;
  drawn_ = false;
}

}  // namespace cli
}  // namespace kane_sim
