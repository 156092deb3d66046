// The model-mismatch alarm: the Kalman filter's normalised innovations squared (NIS), summed over
// a window of readings, tested against their chi-square bound. On a rig that behaves like its
// model the sum over n readings of m coordinates each is chi-square with n m degrees of freedom;
// and each coordinate's normalised innovations nu_i / sqrt(S_ii) average to zero: their sum over
// the window, squared and divided by n, is chi-square with one degree of freedom (a model error
// that pushes one way - a mass, a spring, a latency - shows there long before in the squares).
// ERROR's bound is the quantile a window exceeds with probability p = false_alarms_per_hour x
// window / 3600 (so a clean rig raises it that often; split evenly between the tests), WARN's the
// one exceeded 100 times as often. The coordinate named is the least likely one.
//
// A parameter that changed (a mass, the spring, a friction) pushes the innovations along its own
// signature sigma_k (the filter's response to that change, MechanismEstimator propagates it).
// For each suspect parameter j the window's evidence a_j = sum sigma_kj' S_k^-1 nu_k has variance
// b_j = sum sigma_kj' S_k^-1 sigma_kj on a rig that is its model, so a_j^2 / b_j is chi-square
// with one degree of freedom (a generalised likelihood ratio test, as Willsky and Jones's for
// jumps in a Kalman filter); a_j / b_j estimates the change. These tests join the Bonferroni
// split; when one is the least likely, the report names the parameter and the change, and the
// others that explain the window nearly as well (a rod's mass and a crank spring both change the
// torque a held crank needs: one window may not tell them apart). A change that shows only now
// and then (a friction, while the crank moves) is also tested over the last 2, 4 and 8 windows
// together: their a_j and b_j add (the innovations are white), so one test sees the evidence
// of every window in which the parameter acted.
// When the model's parameters are uncertain (uncertainty.*, the filter considers them), their
// errors are constant in time: the innovations are not white along them, and a_j's variance is
// b_j - sum_k |m_jk|^2 + |sum_k m_jk|^2, m_jk = sigma_kj' S_k^-1 H C_k (C the state's
// cross-covariance with those errors, each of unit variance): a parameter off by its error bar
// is no change. Each coordinate's mean is tested so too.
// ROS-free; the observer publishes the report on /diagnostics.
#ifndef KANE_SIM_ESTIMATE_INNOVATION_ALARM_H
#define KANE_SIM_ESTIMATE_INNOVATION_ALARM_H

#include <array>
#include <cstddef>
#include <deque>
#include <string>
#include <utility>
#include <vector>

namespace kane_sim {

// What the filter measures: the crank's and slider 4's positions, and their speeds when the
// readings carry them.
enum MeasuredCoordinate { kCrankPosition, kSlider4Position, kCrankVelocity, kSlider4Velocity };
constexpr std::size_t kMeasuredCoordinates = 4;
// "crank_joint position", ...: joint_states' joint and field.
const char* measuredCoordinateName(std::size_t coordinate);

enum class AlarmLevel { kOk = 0, kWarn = 1, kError = 2 };  // diagnostic_msgs' levels
const char* alarmLevelName(AlarmLevel level);              // "OK", "WARN", "ERROR"

// The last closed window's verdict.
struct AlarmReport {
  AlarmLevel level = AlarmLevel::kOk;
  double since = 0.0;          // [s] the estimate time this level (not OK) began; 0 when OK
  std::size_t coordinate = 0;  // the least likely coordinate (meaningful when not OK)
  double nis = 0.0;            // the window's sum of NIS
  double dof = 0.0;            // its degrees of freedom (readings x coordinates)
  double warn_bound = 0.0;     // the NIS test's chi-square quantiles for dof
  double error_bound = 0.0;
  double p_value = 1.0;  // the least likely of the window's tests, under the model
  // When that test is a suspect parameter's: it, and any other whose evidence is nearly as
  // strong (a likelihood within e^2 of it, or within a tenth of its statistic for a gross
  // change: parameters this window cannot tell apart), most likely first, at most three, each
  // with the change that would explain the window; empty otherwise.
  struct Suspect {
    std::string name, unit;  // "mechanism.rod_mass", "kg"
    double change = 0.0, sigma = 0.0;
    double over = 0.0;  // [s] the span of windows that tells it (the last window's, or more)
  };
  std::vector<Suspect> suspects;
  double window_end = 0.0;  // [s] when the window closed
  std::size_t windows = 0;  // windows closed since the start
  bool verdict = false;     // a window closed since the filter (re)started
  // Each suspect's information in the window, b_j (in the suspects' order): how well the motion
  // told that parameter; a change of c shows as a statistic of about c^2 b_j.
  std::vector<double> information;
  std::string text() const;  // one line: "ERROR since t = 12.5 s: slider4_joint position ..."
};

class InnovationAlarm {
 public:
  // window [s] > 0, false_alarms_per_hour > 0 (the config's rules); the suspect parameters'
  // names and units (add()'s evidence comes in this order).
  InnovationAlarm(double window, double false_alarms_per_hour,
                  std::vector<std::string> suspects = {}, std::vector<std::string> units = {});

  // One reading's innovation: its NIS over `measured` coordinates, and each measured
  // coordinate's own normalised square (nu_i^2 / S_ii). Returns true when a window closed.
  // `normalised` holds each coordinate's nu_i / sqrt(S_ii).
  // `evidence` / `information` (one per suspect, or empty): this reading's sigma_j' S^-1 nu and
  // sigma_j' S^-1 sigma_j. `considered` (n x n, suspect j's row j n .. j n + n - 1, or empty):
  // this reading's m_j = sigma_j' S^-1 H C, C the cross-covariance with the considered
  // parameters' errors (unit variance; a column each, in the suspects' order).
  // `considered_coordinates` (kMeasuredCoordinates x n, coordinate i's row i n .., or empty): each
  // measured coordinate's (H C)_i / sqrt(S_ii), for its mean's test.
  bool add(double time, double nis, const std::array<bool, kMeasuredCoordinates>& measured,
           const std::array<double, kMeasuredCoordinates>& normalised,
           const std::vector<double>& evidence = {}, const std::vector<double>& information = {},
           const std::vector<double>& considered = {},
           const std::vector<double>& considered_coordinates = {});
  void restart();  // a new start of the filter: the open window is dropped, the verdict OK

  const AlarmReport& report() const { return report_; }
  // P(a window of `dof` NIS >= bound) under the model: the bounds' probabilities.
  double errorProbability() const { return error_probability_; }
  double warnProbability() const { return warn_probability_; }
  // The statistic a suspect's test a^2 / b must reach to raise ERROR on its own.
  double suspectErrorStatistic() const;

 private:
  void closeWindow(double time);
  // How many tests share a window's false-alarm probability (Bonferroni): the NIS, each
  // coordinate's squares and mean, and each suspect over each span.
  double tests() const;
  // One suspect's test over a span of windows: a^2 / b, the change a / b and its 1 / sqrt(b).
  struct SuspectTest {
    double statistic;
    std::size_t suspect;
    double change, sigma;
  };
  // The suspects' tests over the span that tells a change (see its comment), strongest first;
  // `over` [s]: that span. The bounds: ERROR's and WARN's probabilities per test.
  std::vector<SuspectTest> rankSuspects(double p_error, double p_warn, double* over) const;

  double window_;
  double error_probability_, warn_probability_;
  bool open_ = false;
  double window_start_ = 0.0;
  double nis_ = 0.0, dof_ = 0.0;
  std::array<double, kMeasuredCoordinates> sums_{}, signed_sums_{}, counts_{};
  // With parameters considered: each coordinate's sum_k (H C)_i / sqrt(S_ii) (n each) and the
  // sum of their squared norms; its mean's variance is count - squares + |sum|^2.
  std::vector<double> coordinate_considered_;
  std::array<double, kMeasuredCoordinates> coordinate_considered_squares_{};
  std::vector<std::string> suspects_, units_;
  // A window's a_j, b_j and, with parameters considered, sum_k m_jk (n x n) and sum_k |m_jk|^2.
  struct Evidence {
    std::vector<double> a, b, considered, considered_squares;
  };
  Evidence window_evidence_;
  // The last closed windows' evidence (newest last; at most the longest span's count) and spans.
  std::deque<Evidence> past_;
  std::deque<double> past_seconds_;
  AlarmReport report_;
};

// The chi-square quantile with `dof` degrees of freedom exceeded with probability p.
double chiSquareUpperQuantile(double dof, double p);
// P(X >= x) for X chi-square with `dof` degrees of freedom.
double chiSquareUpperTail(double dof, double x);

}  // namespace kane_sim

#endif  // KANE_SIM_ESTIMATE_INNOVATION_ALARM_H
