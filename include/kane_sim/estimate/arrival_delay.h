// How late a reading's stamp is beyond the sensors' own latency, from the stamps alone. A rig's
// driver (or kane_sim_node on the wall clock) stamps a reading when it publishes it; a stalled
// driver or scheduler publishes the readings it owes in a burst: a long interval, then readings
// stamped almost together, each later than its sample by what the stall left.
//
// With samples a period T apart (T: the mean of the recent intervals near their median), the
// stamps' intervals
// are T + d_k - d_(k-1) for delays d_k >= 0, so d_k = max(0, d_(k-1) + interval - T) (Lindley's
// recursion) recovers each reading's delay through a burst. Only a shorter interval than the
// period confirms one: a long interval followed by regular ones may as well be a lost reading
// (or a driver that re-anchored its clock), so there the delay is as uncertain as it is large,
// and it is forgotten after a few regular intervals. A period contradicted for 20 periods (one
// learnt from a burst at the start) is learnt again. The delays are counted from the latest
// reading before the burst, as if it were on time; a driver (or a simulator behind the wall
// clock) late in burst after burst may not have been, so a burst's readings are uncertain by
// the largest delay seen before it. ROS-free.
#ifndef KANE_SIM_ESTIMATE_ARRIVAL_DELAY_H
#define KANE_SIM_ESTIMATE_ARRIVAL_DELAY_H

#include <array>
#include <cstddef>

namespace kane_sim {

class ArrivalDelay {
 public:
  // `tolerance` [s]: how far an interval may stray from the period by the sensors' own jitter.
  explicit ArrivalDelay(double tolerance) : tolerance_(tolerance) {}

  struct Lateness {
    double delay = 0.0;        // [s] how much later than its sample + latency it was stamped
    double uncertainty = 0.0;  // [s] how far that delay may be wrong (as large when unconfirmed)
  };
  // The next reading's stamp [s] (not before the last): its delay beyond the jitter, 0 while the
  // stamps keep their period.
  Lateness add(double stamp);
  void restart();                            // a new run of readings (the filter restarted)
  double period() const { return period_; }  // [s] the readings' period, 0 until known

 private:
  static constexpr std::size_t kIntervals = 64;  // the period's window
  static constexpr int kForgetAfter = 3;         // regular intervals that end a delay
  static constexpr double kRelearnPeriods = 20;  // unusual intervals this long: a wrong period
  double tolerance_;
  std::array<double, kIntervals> intervals_{};
  std::size_t count_ = 0;  // intervals seen (the window holds the last kIntervals)
  double last_stamp_ = 0.0;
  bool has_stamp_ = false;
  double period_ = 0.0;
  double delay_ = 0.0;
  int regular_run_ = 0;
  double unusual_time_ = 0.0;  // [s] intervals in a row outside [period / 2, 2 period]
  std::array<double, kIntervals> recent_delays_{};  // the last readings' delays
  std::size_t delays_seen_ = 0;
  double burst_baseline_ = 0.0;  // [s] the latest delay before the current burst
};

}  // namespace kane_sim

#endif  // KANE_SIM_ESTIMATE_ARRIVAL_DELAY_H
