#include "kane_sim/estimate/innovation_alarm.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include <boost/math/distributions/chi_squared.hpp>

namespace kane_sim {

const char* measuredCoordinateName(std::size_t coordinate) {
  static const char* const kNames[kMeasuredCoordinates] = {
      "crank_joint position", "slider4_joint position", "crank_joint velocity",
      "slider4_joint velocity"};
  return coordinate < kMeasuredCoordinates ? kNames[coordinate] : "?";
}

const char* alarmLevelName(AlarmLevel level) {
  switch (level) {
    case AlarmLevel::kWarn:
      return "WARN";
    case AlarmLevel::kError:
      return "ERROR";
    default:
      return "OK";
  }
}

double chiSquareUpperQuantile(double dof, double p) {
  return boost::math::quantile(boost::math::complement(boost::math::chi_squared(dof), p));
}

double chiSquareUpperTail(double dof, double x) {
  if (!(x > 0.0)) return 1.0;
  return boost::math::cdf(boost::math::complement(boost::math::chi_squared(dof), x));
}

std::string AlarmReport::text() const {
  char line[320];
  if (windows == 0) {
    std::snprintf(line, sizeof line,
                  "no verdict yet: no window of innovations has closed since the filter "
                  "(re)started");
  } else if (level == AlarmLevel::kOk) {
    std::snprintf(line, sizeof line,
                  "OK: the last window's innovations are as the model expects (NIS %.4g over "
                  "%g degrees of freedom; least likely test %.2g)",
                  nis, dof, p_value);
  } else {
    std::snprintf(line, sizeof line,
                  "%s since t = %.3f s: the rig is not behaving like its model; the last "
                  "window's innovations have probability %.2g under it (NIS %.4g over %g "
                  "degrees of freedom), most unlike it in %s",
                  alarmLevelName(level), since, p_value, nis, dof,
                  measuredCoordinateName(coordinate));
  }
  return line;
}

InnovationAlarm::InnovationAlarm(double window, double false_alarms_per_hour) : window_(window) {
  if (!(window > 0.0) || !(false_alarms_per_hour > 0.0))
    throw std::invalid_argument("InnovationAlarm: window and false_alarms_per_hour must be > 0");
  // One window's chance of exceeding the bound on a clean rig, so that a clean hour raises
  // ERROR false_alarms_per_hour times on average (windows do not overlap).
  error_probability_ = std::min(0.5, false_alarms_per_hour * window / 3600.0);
  warn_probability_ = std::min(0.5, 100.0 * error_probability_);
}

void InnovationAlarm::restart() {
  open_ = false;
  const std::size_t windows = report_.windows;
  report_ = AlarmReport{};
  report_.windows = windows;
}

bool InnovationAlarm::add(double time, double nis,
                          const std::array<bool, kMeasuredCoordinates>& measured,
                          const std::array<double, kMeasuredCoordinates>& normalised) {
  if (!open_) {
    open_ = true;
    window_start_ = time;
    nis_ = dof_ = 0.0;
    sums_.fill(0.0);
    signed_sums_.fill(0.0);
    counts_.fill(0.0);
  }
  nis_ += nis;
  for (std::size_t i = 0; i < kMeasuredCoordinates; ++i) {
    if (!measured[i]) continue;
    dof_ += 1.0;
    sums_[i] += normalised[i] * normalised[i];
    signed_sums_[i] += normalised[i];
    counts_[i] += 1.0;
  }
  if (time - window_start_ < window_) return false;
  closeWindow(time);
  return true;
}

void InnovationAlarm::closeWindow(double time) {
  open_ = false;
  AlarmReport r;
  r.windows = report_.windows + 1;
  r.window_end = time;
  r.nis = nis_;
  r.dof = dof_;
  // The tests share the window's false-alarm probability (Bonferroni): the NIS, and each
  // coordinate's squares and mean.
  const double tests = 1.0 + 2.0 * kMeasuredCoordinates;
  const double p_warn = warn_probability_ / tests, p_error = error_probability_ / tests;
  r.warn_bound = chiSquareUpperQuantile(dof_, p_warn);
  r.error_bound = chiSquareUpperQuantile(dof_, p_error);
  double least_likely = chiSquareUpperTail(dof_, nis_);
  double least_likely_coordinate = 2.0;
  for (std::size_t i = 0; i < kMeasuredCoordinates; ++i) {
    if (counts_[i] == 0.0) continue;
    const double mean_statistic = signed_sums_[i] * signed_sums_[i] / counts_[i];
    const double p =
        std::min(chiSquareUpperTail(1.0, mean_statistic), chiSquareUpperTail(counts_[i], sums_[i]));
    if (p < least_likely_coordinate) {
      least_likely_coordinate = p;
      r.coordinate = i;
    }
  }
  least_likely = std::min(least_likely, least_likely_coordinate);
  r.p_value = least_likely;
  r.level = least_likely <= p_error  ? AlarmLevel::kError
            : least_likely <= p_warn ? AlarmLevel::kWarn
                                     : AlarmLevel::kOk;
  if (r.level != AlarmLevel::kOk)
    // Since: the start of the first window of this streak of non-OK windows.
    r.since = report_.level != AlarmLevel::kOk ? report_.since : window_start_;
  report_ = r;
}

}  // namespace kane_sim
