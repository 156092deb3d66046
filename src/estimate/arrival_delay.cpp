#include "kane_sim/estimate/arrival_delay.h"

#include <algorithm>
#include <cmath>

namespace kane_sim {

namespace {
constexpr std::size_t kIntervalsForAPeriod = 5;  // fewer intervals are not yet a period
}  // namespace

ArrivalDelay::Lateness ArrivalDelay::add(double stamp) {
  if (!has_stamp_) {
    has_stamp_ = true;
    last_stamp_ = stamp;
    return {};
  }
  const double interval = stamp - last_stamp_;
  last_stamp_ = stamp;
  if (period_ > 0.0) {
    delay_ = std::max(0.0, delay_ + interval - period_);
    regular_run_ = std::abs(interval - period_) <= tolerance_ ? regular_run_ + 1 : 0;
    if (regular_run_ >= kForgetAfter) {  // on time again
      delay_ = 0.0;
      recent_delays_.fill(0.0);
    }
  }
  // The period from the intervals that look like one: a burst's long and near-zero intervals
  // stay out. Unusual intervals for longer than kRelearnPeriods periods mean the period is wrong
  // (learnt from a burst at the start, or the rig changed its rate): learn it again.
  const bool usual = period_ == 0.0 || (interval > 0.5 * period_ && interval < 2.0 * period_);
  unusual_time_ = usual ? 0.0 : unusual_time_ + interval;
  if (unusual_time_ > kRelearnPeriods * period_) {
    count_ = 0;
    period_ = 0.0;
    delay_ = 0.0;
    unusual_time_ = 0.0;
  }
  if (usual || period_ == 0.0) {
    intervals_[count_ % kIntervals] = interval;
    ++count_;
  }
  const std::size_t n = std::min(count_, kIntervals);
  if (n >= kIntervalsForAPeriod) {
    // The mean of the intervals near their median: the jitter averages out (a burst's delays
    // are recovered to the period's error times its length), outliers stay out.
    std::array<double, kIntervals> sorted = intervals_;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<long>(n / 2),
                     sorted.begin() + static_cast<long>(n));
    const double median = sorted[n / 2];
    double sum = 0.0;
    std::size_t used = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (intervals_[i] > 0.5 * median && intervals_[i] < 2.0 * median) {
        sum += intervals_[i];
        ++used;
      }
    period_ = used > 0 ? sum / static_cast<double>(used) : median;
  }
  // Inside a burst (an interval shorter than the period allows) the delay is known; otherwise
  // the reading may be on time after a lost one: the delay is its own uncertainty. Outside a
  // burst a delay within the jitter's span is the jitter itself, which the sensors' model has.
  const bool in_burst = period_ > 0.0 && interval < period_ - tolerance_;
  // Its delay after the reading before the burst is known; but that reading may have been late
  // too (a simulator running behind the wall clock catches up in bursts, seldom on time): as
  // late as any reading before the burst recently was.
  if (!in_burst) burst_baseline_ = *std::max_element(recent_delays_.begin(), recent_delays_.end());
  recent_delays_[delays_seen_++ % kIntervals] = delay_;
  if (in_burst) return {delay_, burst_baseline_};
  const double delay = delay_ > tolerance_ ? delay_ : 0.0;
  return {delay, delay};
}

void ArrivalDelay::restart() { *this = ArrivalDelay(tolerance_); }

}  // namespace kane_sim
