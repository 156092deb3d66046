#include "kane_sim/estimate/innovation_alarm.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>

#include <boost/math/distributions/chi_squared.hpp>

namespace kane_sim {
namespace {

// The spans, in windows, over which each suspect is tested: a change that acts now and then (a
// friction while the crank moves) gathers its evidence over several.
constexpr std::array<std::size_t, 4> kSpans = {1, 2, 4, 8};

}  // namespace

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
  if (!verdict)
    return "no verdict yet: no window of innovations has closed since the filter (re)started";
  if (level == AlarmLevel::kOk) {
    std::snprintf(line, sizeof line,
                  "OK: the last window's innovations are as the model expects (NIS %.4g over "
                  "%g degrees of freedom; least likely test %.2g)",
                  nis, dof, p_value);
    return line;
  }
  std::snprintf(line, sizeof line,
                "%s since t = %.3f s: the rig is not behaving like its model; the last window's "
                "innovations have probability %.2g under it (NIS %.4g over %g degrees of "
                "freedom), ",
                alarmLevelName(level), since, p_value, nis, dof);
  std::string text = line;
  if (suspects.empty()) return text + "most unlike it in " + measuredCoordinateName(coordinate);
  for (std::size_t i = 0; i < suspects.size(); ++i) {
    const Suspect& s = suspects[i];
    std::snprintf(line, sizeof line, "%s%s by %+.3g +- %.2g %s%s",
                  i == 0   ? "most like a change of "
                  : i == 1 ? " (or of "
                           : ", or of ",
                  s.name.c_str(), s.change, s.sigma, s.unit.c_str(),
                  i > 0 && i + 1 == suspects.size() ? ")" : "");
    text += line;
  }
  std::snprintf(line, sizeof line, ", over the last %.3g s", suspects.front().over);
  return text + line;
}

InnovationAlarm::InnovationAlarm(double window, double false_alarms_per_hour,
                                 std::vector<std::string> suspects, std::vector<std::string> units)
    : window_(window), suspects_(std::move(suspects)), units_(std::move(units)) {
  if (!(window > 0.0) || !(false_alarms_per_hour > 0.0))
    throw std::invalid_argument("InnovationAlarm: window and false_alarms_per_hour must be > 0");
  units_.resize(suspects_.size());
  // One window's chance of exceeding the bound on a clean rig, so that a clean hour raises
  // ERROR false_alarms_per_hour times on average (windows do not overlap).
  error_probability_ = std::min(0.5, false_alarms_per_hour * window / 3600.0);
  warn_probability_ = std::min(0.5, 100.0 * error_probability_);
}

void InnovationAlarm::restart() {
  open_ = false;
  past_.clear();
  past_seconds_.clear();
  const std::size_t windows = report_.windows;
  report_ = AlarmReport{};
  report_.windows = windows;
}

bool InnovationAlarm::add(double time, double nis,
                          const std::array<bool, kMeasuredCoordinates>& measured,
                          const std::array<double, kMeasuredCoordinates>& normalised,
                          const std::vector<double>& evidence,
                          const std::vector<double>& information,
                          const std::vector<double>& considered,
                          const std::vector<double>& considered_coordinates) {
  if (!open_) {
    open_ = true;
    window_start_ = time;
    nis_ = dof_ = 0.0;
    sums_.fill(0.0);
    signed_sums_.fill(0.0);
    counts_.fill(0.0);
    window_evidence_.a.assign(suspects_.size(), 0.0);
    window_evidence_.b.assign(suspects_.size(), 0.0);
    window_evidence_.considered.clear();
    window_evidence_.considered_squares.clear();
    coordinate_considered_.clear();
    coordinate_considered_squares_.fill(0.0);
  }
  nis_ += nis;
  const std::size_t n = suspects_.size();
  if (evidence.size() == n && information.size() == n)
    for (std::size_t j = 0; j < n; ++j) {
      window_evidence_.a[j] += evidence[j];
      window_evidence_.b[j] += information[j];
    }
  if (n > 0 && considered.size() == n * n) {
    Evidence& w = window_evidence_;
    if (w.considered.empty()) {
      w.considered.assign(n * n, 0.0);
      w.considered_squares.assign(n, 0.0);
    }
    for (std::size_t j = 0; j < n; ++j)
      for (std::size_t i = 0; i < n; ++i) {
        const double m = considered[j * n + i];
        w.considered[j * n + i] += m;
        w.considered_squares[j] += m * m;
      }
  }
  if (n > 0 && considered_coordinates.size() == kMeasuredCoordinates * n) {
    if (coordinate_considered_.empty())
      coordinate_considered_.assign(kMeasuredCoordinates * n, 0.0);
    for (std::size_t i = 0; i < kMeasuredCoordinates; ++i) {
      if (!measured[i]) continue;
      for (std::size_t k = 0; k < n; ++k) {
        const double r = considered_coordinates[i * n + k];
        coordinate_considered_[i * n + k] += r;
        coordinate_considered_squares_[i] += r * r;
      }
    }
  }
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

double InnovationAlarm::tests() const {
  return 1.0 + 2.0 * kMeasuredCoordinates + static_cast<double>(kSpans.size() * suspects_.size());
}

double InnovationAlarm::suspectErrorStatistic() const {
  return chiSquareUpperQuantile(1.0, error_probability_ / tests());
}

void InnovationAlarm::closeWindow(double time) {
  open_ = false;
  AlarmReport r;
  r.windows = report_.windows + 1;
  r.verdict = true;
  r.window_end = time;
  r.information = window_evidence_.b;
  r.nis = nis_;
  r.dof = dof_;
  const double p_warn = warn_probability_ / tests(), p_error = error_probability_ / tests();
  r.warn_bound = chiSquareUpperQuantile(dof_, p_warn);
  r.error_bound = chiSquareUpperQuantile(dof_, p_error);
  double least_likely = chiSquareUpperTail(dof_, nis_);
  double least_likely_coordinate = 2.0;
  for (std::size_t i = 0; i < kMeasuredCoordinates; ++i) {
    if (counts_[i] == 0.0) continue;
    // The mean's variance: the count, or with parameters considered, their share in it.
    double variance = counts_[i];
    if (!coordinate_considered_.empty()) {
      const std::size_t n = suspects_.size();
      double norm = 0.0;
      for (std::size_t k = 0; k < n; ++k)
        norm += coordinate_considered_[i * n + k] * coordinate_considered_[i * n + k];
      variance += norm - coordinate_considered_squares_[i];
    }
    const double mean_statistic = signed_sums_[i] * signed_sums_[i] / variance;
    const double p =
        std::min(chiSquareUpperTail(1.0, mean_statistic), chiSquareUpperTail(counts_[i], sums_[i]));
    if (p < least_likely_coordinate) {
      least_likely_coordinate = p;
      r.coordinate = i;
    }
  }
  least_likely = std::min(least_likely, least_likely_coordinate);
  past_.push_back(window_evidence_);
  past_seconds_.push_back(time - window_start_);
  if (past_.size() > kSpans.back()) {
    past_.pop_front();
    past_seconds_.pop_front();
  }
  double over = 0.0;
  const std::vector<SuspectTest> ranked = rankSuspects(p_error, p_warn, &over);
  // Ties at the tails' underflow (p = 0) go to the parameters: they say more.
  if (!ranked.empty() && chiSquareUpperTail(1.0, ranked.front().statistic) <= least_likely) {
    least_likely = chiSquareUpperTail(1.0, ranked.front().statistic);
    // Told apart: a likelihood e^2 below the likeliest's, and for a gross change (far beyond the
    // signatures' first order) a tenth of its statistic below: a spring 30 % weaker and a
    // slider 40 % heavier ring alike while the crank is held.
    constexpr double kTellApart = 4.0;  // 2 log(likelihood ratio)
    constexpr double kTellApartShare = 0.1;
    constexpr std::size_t kMostNamed = 3;
    const double told_apart =
        ranked.front().statistic - std::max(kTellApart, kTellApartShare * ranked.front().statistic);
    for (const SuspectTest& x : ranked) {
      if (x.statistic < told_apart || r.suspects.size() == kMostNamed) break;
      r.suspects.push_back({suspects_[x.suspect], units_[x.suspect], x.change, x.sigma, over});
    }
  }
  r.p_value = least_likely;
  r.level = least_likely <= p_error  ? AlarmLevel::kError
            : least_likely <= p_warn ? AlarmLevel::kWarn
                                     : AlarmLevel::kOk;
  if (r.level == AlarmLevel::kOk) r.suspects.clear();  // nothing to explain
  if (r.level != AlarmLevel::kOk)
    // Since: the start of the first window of this streak of non-OK windows.
    r.since = report_.level != AlarmLevel::kOk ? report_.since : window_start_;
  report_ = r;
}

std::vector<InnovationAlarm::SuspectTest> InnovationAlarm::rankSuspects(double p_error,
                                                                        double p_warn,
                                                                        double* over) const {
  // Each suspect's statistic a^2 / b (chi-square, 1 degree of freedom) over each span of the last
  // windows, a and b summed over them; a parameter whose signature barely acts there (b ~ 0) is
  // no test. A span longer than one window counts only when its newest window adds to the
  // evidence (the statistic without it is smaller): a change long over is not reported again.
  const std::size_t n = suspects_.size();
  std::vector<double> a(n, 0.0), b(n, 0.0), considered, squares;
  const Evidence& newest = past_.back();
  // a_j's variance over the windows summed so far, without the newest's share when `before`.
  const auto variance = [&](std::size_t j, bool before) {
    const double b_j = b[j] - (before ? newest.b[j] : 0.0);
    if (considered.empty()) return b_j;
    double norm = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const double m = considered[j * n + i] -
                       (before && !newest.considered.empty() ? newest.considered[j * n + i] : 0.0);
      norm += m * m;
    }
    const double square =
        squares[j] - (before && !newest.considered.empty() ? newest.considered_squares[j] : 0.0);
    return b_j - square + norm;
  };
  std::vector<std::vector<SuspectTest>> spans;  // each span's tests, strongest first
  std::vector<double> span_seconds;
  double seconds = 0.0, strongest = 0.0;
  for (std::size_t windows = 1; windows <= past_.size(); ++windows) {
    const Evidence& w = past_[past_.size() - windows];
    seconds += past_seconds_[past_.size() - windows];
    for (std::size_t j = 0; j < n; ++j) {
      a[j] += w.a[j];
      b[j] += w.b[j];
    }
    if (!w.considered.empty()) {
      if (considered.empty()) {
        considered.assign(n * n, 0.0);
        squares.assign(n, 0.0);
      }
      for (std::size_t k = 0; k < n * n; ++k) considered[k] += w.considered[k];
      for (std::size_t j = 0; j < n; ++j) squares[j] += w.considered_squares[j];
    }
    if (std::find(kSpans.begin(), kSpans.end(), windows) == kSpans.end()) continue;
    std::vector<SuspectTest> tests;
    for (std::size_t j = 0; j < n; ++j) {
      const double var = variance(j, false);
      if (!(b[j] > 0.0) || !std::isfinite(b[j]) || !(var > 0.0) || !std::isfinite(var)) continue;
      const double statistic = a[j] * a[j] / var;
      const double a_before = a[j] - newest.a[j], var_before = variance(j, true);
      if (windows > 1 && var_before > 0.0 && !(statistic > a_before * a_before / var_before))
        continue;
      tests.push_back({statistic, j, a[j] / b[j],
                       considered.empty() ? 1.0 / std::sqrt(b[j]) : std::sqrt(var) / b[j]});
    }
    std::sort(tests.begin(), tests.end(),
              [](const SuspectTest& x, const SuspectTest& y) { return x.statistic > y.statistic; });
    if (!tests.empty()) strongest = std::max(strongest, tests.front().statistic);
    spans.push_back(std::move(tests));
    span_seconds.push_back(seconds);
  }
  // The level the strongest test reaches; the shortest span that reaches it names the change (a
  // gross change is best told by the window after it alone, its signature fresh).
  const double p = chiSquareUpperTail(1.0, strongest);
  const double bound = p <= p_error ? p_error : p <= p_warn ? p_warn : p;
  for (std::size_t s = 0; s < spans.size(); ++s)
    if (!spans[s].empty() && chiSquareUpperTail(1.0, spans[s].front().statistic) <= bound) {
      *over = span_seconds[s];
      return spans[s];
    }
  *over = 0.0;
  return {};
}

}  // namespace kane_sim
