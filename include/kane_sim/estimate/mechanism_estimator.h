// The twin beside the rig: an extended Kalman filter on the textbook example's Kane equations
// (the generated equations and their exact Jacobian, model/generated_jacobian.h) that turns a
// rig's joint readings (crank angle and slider 4's position, their speeds when given, the
// delivered torque) into the whole state with its covariance.
//
//   x = (q1, q2, u1, u2, b1, b2)      b: the encoders' position biases (sensors' bias_walk)
//   predict:  x' = f(x, M_m) by rk4 on the physics step; M_m one reading's effort until an answer
//             to it can be in force (MeasurementNoise::answer_delay), then the next reading's;
//             P' = Phi P Phi' + Q, Phi = exp(A h) to third order, A the exact Jacobian, Q white
//             acceleration noise (estimator.*_acceleration_noise) and the biases' walk; with
//             the config's uncertainty.* (identify's standard errors) the parameters' errors
//             are considered: x' = Phi x + G p (G: each parameter's effect on a step), P gains
//             Phi C G' + G C' Phi' + G G' and C' = Phi C + G, p scaled to unit variance, and a
//             correction keeps p as it is: C <- (I - K H) C (Schmidt's consider filter)
//   update:   z = (q1 + b1, q2 + b2 [, u1, u2]) at the reading's sample instant, stamp minus the
//             sensors' latency (and half their jitter); R from the sensors' noise model: white
//             noise, the encoder's step^2 / 12, and the jitter's timing error (speed^2 var)
//             plus a late stamp's (ArrivalDelay: a stalled driver's readings come in a burst)
//
// The measurement model is config's `sensors:` section (a fitted config from identify, say);
// `estimator:` says how far the model is trusted. Readings that cannot be used are refused,
// named, and the estimate kept; a gap beyond estimator.restart_gap restarts the filter. ROS-free.
#ifndef KANE_SIM_ESTIMATE_MECHANISM_ESTIMATOR_H
#define KANE_SIM_ESTIMATE_MECHANISM_ESTIMATOR_H

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "kane_sim/config/config.h"
#include "kane_sim/estimate/arrival_delay.h"
#include "kane_sim/estimate/innovation_alarm.h"
#include "kane_sim/model/generated_mechanism.h"
#include "kane_sim/model/state.h"

namespace kane_sim {

// One reading of the rig as joint_states carries it.
struct RigReading {
  double stamp = 0.0;  // [s] the message's stamp: when it arrived (sampled `latency` earlier)
  double q1 = 0.0;     // [rad] crank_joint's position
  double q2 = 0.0;     // [m] slider4_joint's position
  bool has_velocity = false;
  double u1 = 0.0;      // [rad/s] crank_joint's velocity (when has_velocity)
  double u2 = 0.0;      // [m/s] slider4_joint's velocity
  double torque = 0.0;  // [N m] crank_joint's effort: M_m in force when it was sampled
};

// The measurement model the config's sensors give (exact readings get a floor of 1e-6).
struct MeasurementNoise {
  std::array<double, 2> position_variance{};  // [rad^2, m^2] white noise + encoder step^2 / 12
  std::array<double, 2> velocity_variance{};  // [(rad/s)^2, (m/s)^2]
  std::array<double, 2> bias_walk_rate{};     // [rad^2/s, m^2/s] the biases' variance per second
  double latency = 0.0;          // [s] mean age of a reading at its stamp (latency + jitter / 2)
  double timing_variance = 0.0;  // [s^2] the jitter's variance around that age
  // [s] after a sample, when a controller answering it is in force (latency + command_latency):
  // the torque between readings is the first's effort until then, the next's after.
  double answer_delay = 0.0;
  double command_latency = 0.0;  // [s] sensors.command_latency in physics steps
  // [s^2] how uncertain that instant is beyond the jitter: a physics step (where in it the drive
  // takes the answer) and estimator.answer_timing_noise^2 (a transport's delays)
  double answer_timing_variance = 0.0;
};
MeasurementNoise measurementNoise(const Config& config);

using EstimateVector = Eigen::Matrix<double, 6, 1>;
using EstimateCovariance = Eigen::Matrix<double, 6, 6>;
// At most this many suspect parameters (the schema's identifiable rows: 15), so that the
// signatures live on the stack: no allocation per reading at 1 kHz.
constexpr int kMaxSuspects = kMaxIdentifiable;
// Each suspect parameter's signature: how the estimate's error would have grown since the alarm
// window opened, per unit change of that parameter (a column each).
using SignatureMatrix = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, kMaxSuspects>;

// The filter's estimate at one instant.
struct FilterEstimate {
  double time = 0.0;  // [s] on the readings' clock
  State state;
  std::array<double, 2> bias{};  // [rad, m] b1, b2
  EstimateCovariance covariance = EstimateCovariance::Zero();
  // cov(x's error, each uncertain parameter's error / its uncertainty.*), a column each: the
  // model's parameters considered, never estimated (Schmidt's consider filter). Empty when the
  // config gives no parameter an uncertainty.
  SignatureMatrix parameter_cross;
  double torque = 0.0;                  // [N m] M_m held
  std::array<double, 4> sigma() const;  // standard deviations of q1, q2, u1, u2
};

enum class EstimatorEvent {
  kUpdated,    // the reading corrected the estimate
  kStarted,    // the first reading (or the first after restart()) started the filter
  kRestarted,  // a gap or a diverged prediction: the filter started again from this reading
  kRefused,    // the reading is unusable (`reason` names the field and value); nothing changed
};
struct EstimatorStep {
  EstimatorEvent event = EstimatorEvent::kRefused;
  std::string reason;
};

class MechanismEstimator {
 public:
  explicit MechanismEstimator(const Config& config);

  EstimatorStep update(const RigReading& reading);
  void restart();  // forget the estimate (the rig was reset): the next reading starts it again

  bool started() const { return started_; }
  double lastStamp() const { return last_stamp_; }  // [s] the last used reading's stamp
  // At the last reading's sample instant (stamp - latency): what the filter corrected.
  const FilterEstimate& atSample() const { return sample_; }
  // The same carried forward to the last reading's stamp with the torque held: the state now,
  // what a controller reading the estimate wants (latency compensated).
  FilterEstimate atStamp() const;
  // The last update's innovation: each coordinate's nu, S_ii, and whether it was measured.
  const std::array<double, kMeasuredCoordinates>& innovation() const { return innovation_; }
  const std::array<double, kMeasuredCoordinates>& innovationVariance() const { return s_ii_; }
  const std::array<bool, kMeasuredCoordinates>& measured() const { return measured_; }
  double nis() const { return nis_; }  // nu' S^-1 nu of the last update
  const InnovationAlarm& alarm() const { return alarm_; }
  const MeasurementNoise& noise() const { return noise_; }
  std::size_t restarts() const { return restarts_; }  // gaps, diverged predictions, restart()
  double restartGap() const { return restart_gap_; }  // [s] estimator.restart_gap
  // The parameters the alarm tests for a change: the config's identifiable ones (masses, the rod's
  // inertia, springs, dampers, friction), as "mechanism.rod_mass".
  const std::vector<std::string>& suspects() const { return suspect_names_; }

 private:
  void start(const RigReading& reading, double sample_time);
  // Carries `e` forward by `span` seconds (steps of at most the physics step), the torque going
  // from e.torque to end_torque; false when the state left the finite or the model's scale.
  // `signature` (when given) is carried along: E <- Phi E + the step's response to each suspect.
  // `answer_lateness`: how much later than its sample + answer_delay the last reading's answer
  // can be in force (that reading's stamp came late by it: a burst), and its variance.
  bool predict(FilterEstimate* e, double span, double end_torque,
               SignatureMatrix* signature = nullptr, double answer_lateness = 0.0,
               double answer_lateness_variance = 0.0) const;
  // d(u1', u2')/dp, a column each
  using SignatureRates = Eigen::Matrix<double, 2, Eigen::Dynamic, 0, 2, kMaxSuspects>;
  SignatureRates signatureRates(const std::array<double, 4>& x, double torque) const;
  static void carrySignature(SignatureMatrix* signature, const Eigen::Matrix4d& Phi,
                             const SignatureRates& g, double h);
  // One step of the parameters' errors (uncertainty.*) into e's covariance and cross-covariance.
  void considerParameters(FilterEstimate* e, const Eigen::Matrix4d& Phi, const SignatureRates& g,
                          double h) const;
  // [s] where in a reading interval of `span` the torque takes the next reading's effort, the
  // last reading's answer `lateness` later than in a regular stream (at most the interval).
  double switchOffset(double span, double lateness) const;
  // False (nothing changed) for a reading too far from the estimate to correct it.
  bool correct(const RigReading& reading);
  std::string unusable(const RigReading& reading) const;

  // A suspect parameter: the model with it changed by `delta`, for u' 's derivative along it.
  struct Suspect {
    GeneratedMechanism changed;
    double delta;
  };
  static std::vector<Suspect> suspectsOf(const Config& config, std::vector<std::string>* names,
                                         std::vector<std::string>* units);

  GeneratedMechanism mechanism_;
  MeasurementNoise noise_;
  std::vector<std::string> suspect_names_, suspect_units_;
  std::vector<Suspect> suspects_;
  // Each suspect's uncertainty.* (its standard error), and whether any is above 0.
  Eigen::Matrix<double, 1, Eigen::Dynamic, Eigen::RowMajor, 1, kMaxSuspects> parameter_sigma_;
  bool considers_parameters_ = false;
  std::array<double, 2> acceleration_density_;  // [rad^2/s^3, m^2/s^3] of the process noise
  double step_;                                 // [s] the physics step
  double restart_gap_;
  double max_speed_;     // [rad/s, m/s] beyond this |u1|, |u2| the prediction diverged (1 per step)
  double torque_limit_;  // [N m] command.torque_limit: a larger effort is refused
  InnovationAlarm alarm_;
  ArrivalDelay arrival_;  // how late each stamp is beyond the jitter (a stalled driver's burst)
  double arrival_variance_ = 0.0;  // [s^2] this reading's sample instant: its delay's uncertainty^2
  // The last used reading's delay (ArrivalDelay) and its uncertainty^2: its answer, computed when
  // it arrived, lands that much later after its sample.
  double last_delay_ = 0.0, last_delay_variance_ = 0.0;
  bool started_ = false;
  bool ever_started_ = false;  // a restart keeps the biases once there are some
  double last_stamp_ = 0.0;
  FilterEstimate sample_;
  SignatureMatrix signature_;  // since the alarm's window opened
  std::array<double, kMeasuredCoordinates> innovation_{}, s_ii_{};
  std::array<bool, kMeasuredCoordinates> measured_{};
  double nis_ = 0.0;
  std::size_t restarts_ = 0;
  int outliers_ = 0;               // readings in a row too far from the estimate to correct it
  FilterEstimate before_outlier_;  // the estimate before the last prediction, kept for a refusal
  SignatureMatrix signature_before_outlier_;
  std::vector<double> evidence_,
      information_;  // this reading's, for the alarm (kept: no allocation)
  // With parameters considered: this reading's sigma_j' S^-1 H C (InnovationAlarm::add).
  std::vector<double> considered_, considered_coordinates_;
  const std::vector<double> no_considered_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_ESTIMATE_MECHANISM_ESTIMATOR_H
