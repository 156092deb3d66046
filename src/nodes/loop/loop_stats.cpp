#include "loop/loop_stats.h"

#include <algorithm>
#include <cmath>

namespace kane_sim {
namespace {

double percentile(std::vector<double>* values, double fraction) {
  if (values->empty()) return 0.0;
  const size_t index =
      std::min(values->size() - 1, static_cast<size_t>(std::ceil(fraction * values->size())) - 1);
  std::nth_element(values->begin(), values->begin() + index, values->end());
  return (*values)[index];
}

}  // namespace

void LoopStats::recordTick(double lateness, bool overrun, double skipped) {
  lateness_.push_back(lateness);
  if (overrun) ++overruns_;
  skipped_ += skipped;
}

LoopStats::Summary LoopStats::takeSummary(double wall_seconds, double sim_seconds) {
  Summary s;
  s.ticks = lateness_.size();
  s.overruns = overruns_;
  s.skipped = skipped_;
  if (!lateness_.empty()) s.lateness_max = *std::max_element(lateness_.begin(), lateness_.end());
  s.lateness_p50 = percentile(&lateness_, 0.50);
  s.lateness_p99 = percentile(&lateness_, 0.99);
  if (wall_seconds > 0) {
    s.physics_rate = static_cast<double>(s.ticks) / wall_seconds;
    s.real_time_factor = sim_seconds / wall_seconds;
  }
  lateness_.clear();
  overruns_ = 0;
  skipped_ = 0.0;
  return s;
}

}  // namespace kane_sim
