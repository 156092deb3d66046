#include "kane_sim/estimate/mechanism_estimator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>

#include "kane_sim/config/parameter_schema.h"
#include "kane_sim/format_number.h"
#include "kane_sim/model/joint_names.h"
#include "kane_sim/model/rk4_step.h"
#include "kane_sim/sensors/joint_sensors.h"

namespace kane_sim {
namespace {

// Exact readings (sensors off) still need a measurement variance for the gain's inverse: a
// micro-radian (micrometre), and a micro-radian per second, far below any encoder.
constexpr double kPositionFloor = 1e-6;
constexpr double kVelocityFloor = 1e-6;
// [m] slider 4 further than this from the origin is no reading of this mechanism (a metre scale).
constexpr double kMaxSliderPosition = 1e3;
// A reading whose innovation is this many of its standard deviations from the estimate is
// refused; so many in a row restart the filter.
constexpr double kOutlierSigma = 1e3;
constexpr int kOutliersBeforeRestart = 3;
// The speeds' spread before the first reading that carries none [rad/s, m/s].
constexpr double kUnknownCrankSpeed = 10.0;
constexpr double kUnknownSliderSpeed = 1.0;

using Matrix4 = Eigen::Matrix4d;

double encoderStepVariance(const JointSensorSettings& s, bool revolute) {
  if (!(s.encoder_counts > 0.0)) return 0.0;
  const double step = (revolute ? 2.0 * M_PI : 1.0) / s.encoder_counts;
  return step * step / 12.0;
}

}  // namespace

MeasurementNoise measurementNoise(const Config& config) {
  MeasurementNoise n;
  const SensorSettings& sensors = config.sensors;
  const int joints[2] = {kCrankJoint, kSlider4Joint};
  for (int i = 0; i < 2; ++i) {
    const JointSensorSettings s =
        sensors.enabled ? sensors.joints[joints[i]] : JointSensorSettings{};
    n.position_variance[i] = s.position_noise * s.position_noise + encoderStepVariance(s, i == 0) +
                             kPositionFloor * kPositionFloor;
    n.velocity_variance[i] = s.velocity_noise * s.velocity_noise + kVelocityFloor * kVelocityFloor;
    n.bias_walk_rate[i] = s.bias_walk * s.bias_walk;
  }
  if (sensors.enabled) {
    // The sensors' own rounding to physics steps (sensors/joint_sensors.h): a latency of L
    // ticks plus a jitter uniform over the whole ticks 0..J.
    const double rate = config.simulation.physics_rate;
    const double latency = static_cast<double>(physicsTicks(sensors.latency, rate));
    const double jitter = static_cast<double>(physicsTicks(sensors.latency_jitter, rate));
    n.latency = (latency + jitter / 2.0) / rate;
    n.timing_variance = ((jitter + 1.0) * (jitter + 1.0) - 1.0) / 12.0 / (rate * rate);
    n.command_latency = static_cast<double>(physicsTicks(sensors.command_latency, rate)) / rate;
    n.answer_delay = n.latency + n.command_latency;
  }
  const double step = 1.0 / config.simulation.physics_rate;
  n.answer_timing_variance =
      n.timing_variance + step * step +
      config.estimator.answer_timing_noise * config.estimator.answer_timing_noise;
  return n;
}

std::array<double, 4> FilterEstimate::sigma() const {
  return {std::sqrt(covariance(0, 0)), std::sqrt(covariance(1, 1)), std::sqrt(covariance(2, 2)),
          std::sqrt(covariance(3, 3))};
}

MechanismEstimator::MechanismEstimator(const Config& config)
    : mechanism_(mechanismModel(config)),
      noise_(measurementNoise(config)),
      suspects_(suspectsOf(config, &suspect_names_, &suspect_units_)),
      acceleration_density_{
          config.estimator.crank_acceleration_noise * config.estimator.crank_acceleration_noise,
          config.estimator.slider4_acceleration_noise *
              config.estimator.slider4_acceleration_noise},
      step_(1.0 / config.simulation.physics_rate),
      restart_gap_(config.estimator.restart_gap),
      max_speed_(1.0 / step_),
      torque_limit_(config.command.torque_limit),
      alarm_(config.estimator.alarm_window, config.estimator.false_alarms_per_hour, suspect_names_,
             suspect_units_),
      // The intervals stray by the jitter's span and a physics step without being late.
      arrival_(std::sqrt(12.0 * noise_.timing_variance) + step_) {
  // uncertainty.<suspect>: identify's standard error of each parameter the alarm suspects.
  parameter_sigma_.resize(static_cast<Eigen::Index>(suspects_.size()));
  for (std::size_t j = 0; j < suspects_.size(); ++j) {
    const ParameterSpec* row = findParameter("uncertainty", suspect_names_[j]);
    const double sigma = row != nullptr ? numericValue(*row, config) : 0.0;
    parameter_sigma_(static_cast<Eigen::Index>(j)) = sigma;
    considers_parameters_ |= sigma > 0.0;
  }
}

std::vector<MechanismEstimator::Suspect> MechanismEstimator::suspectsOf(
    const Config& config, std::vector<std::string>* names, std::vector<std::string>* units) {
  std::vector<Suspect> suspects;
  for (const ParameterSpec& spec : parameterSchema()) {
    if (!identifiable(spec)) continue;
    Config changed = config;
    double& value = spec.field.number(changed);
    // A step u' is linear in to rounding (friction and dampers are linear in theirs; masses
    // and k smooth): a millionth of the value, or of 1 for a resistance that is off.
    const double delta = 1e-6 * std::max(std::abs(value), 1.0);
    value += delta;
    suspects.push_back({GeneratedMechanism(mechanismModel(changed)), delta});
    names->push_back(spec.path());
    units->push_back(spec.unit);
  }
  if (suspects.size() > static_cast<std::size_t>(kMaxSuspects))
    throw std::logic_error("MechanismEstimator: more identifiable parameters than kMaxSuspects");
  return suspects;
}

void MechanismEstimator::restart() {
  if (started_) ++restarts_;
  started_ = false;
  alarm_.restart();
}

std::string MechanismEstimator::unusable(const RigReading& r) const {
  const auto field = [](const char* name, double value) {
    return std::string(name) + " = " + formatNumber(value) + " is not finite";
  };
  if (!std::isfinite(r.stamp)) return field("the stamp", r.stamp);
  if (!std::isfinite(r.q1)) return field("crank_joint's position", r.q1);
  if (!std::isfinite(r.q2)) return field("slider4_joint's position", r.q2);
  if (!std::isfinite(r.torque)) return field("crank_joint's effort", r.torque);
  if (r.has_velocity && !std::isfinite(r.u1)) return field("crank_joint's velocity", r.u1);
  if (r.has_velocity && !std::isfinite(r.u2)) return field("slider4_joint's velocity", r.u2);
  // Finite but beyond any motion of this mechanism: a corrupt message, not a reading (taken, it
  // would drag the encoders' biases with it).
  if (std::abs(r.q2) > kMaxSliderPosition)
    return "slider4_joint's position = " + formatNumber(r.q2) + " m is beyond " +
           formatNumber(kMaxSliderPosition) + " m (not this mechanism's)";
  if (r.has_velocity && (std::abs(r.u1) > max_speed_ || std::abs(r.u2) > max_speed_))
    return "a velocity (crank_joint " + formatNumber(r.u1) + " rad/s, slider4_joint " +
           formatNumber(r.u2) + " m/s) is beyond the model's range, " + formatNumber(max_speed_) +
           " per second";
  // The drive cannot deliver more than its limit: such an effort is not this rig's.
  if (std::abs(r.torque) > torque_limit_ * (1.0 + 1e-9))
    return "crank_joint's effort = " + formatNumber(r.torque) +
           " N m is beyond command.torque_limit " + formatNumber(torque_limit_) +
           " N m (is the config the rig's?)";
  // Further back than restart_gap is a clock set back (or the last stamp was wrong): update()
  // starts again from it rather than refusing every reading after.
  if (started_ && r.stamp < last_stamp_ && last_stamp_ - r.stamp <= restart_gap_)
    return "the stamp " + formatNumber(r.stamp) + " s goes back " +
           formatNumber(last_stamp_ - r.stamp) + " s before the last reading's";
  return "";
}

EstimatorStep MechanismEstimator::update(const RigReading& reading) {
  const std::string refusal = unusable(reading);
  if (!refusal.empty()) return {EstimatorEvent::kRefused, refusal};
  if (!started_) {
    start(reading, reading.stamp - noise_.latency);
    return {EstimatorEvent::kStarted, ""};
  }
  if (reading.stamp < last_stamp_) {  // back by more than restart_gap (unusable() took the rest)
    const std::string reason = "the stamp went back " + formatNumber(last_stamp_ - reading.stamp) +
                               " s (> estimator.restart_gap " + formatNumber(restart_gap_) +
                               " s): the rig's clock was set back, or the last stamp was wrong";
    restart();
    start(reading, reading.stamp - noise_.latency);
    return {EstimatorEvent::kRestarted, reason};
  }
  // Sampled latency before its stamp, and earlier when the stamp came late (a burst).
  const ArrivalDelay::Lateness late = arrival_.add(reading.stamp);
  arrival_variance_ = late.uncertainty * late.uncertainty;
  // Readings never overtake each other: none was sampled before the last one.
  const double sample_time = std::max(reading.stamp - noise_.latency - late.delay, sample_.time);
  const double gap = reading.stamp - last_stamp_;
  std::string restart_reason;
  if (gap > restart_gap_) {
    restart_reason = "a gap of " + formatNumber(gap) +
                     " s between readings (> estimator.restart_gap " + formatNumber(restart_gap_) +
                     " s)";
  } else {
    before_outlier_ = sample_;
    signature_before_outlier_ = signature_;
    FilterEstimate predicted = sample_;
    SignatureMatrix signature = signature_;
    if (predict(&predicted, sample_time - sample_.time, reading.torque, &signature, last_delay_,
                last_delay_variance_)) {
      sample_ = predicted;
      signature_ = signature;
    } else
      restart_reason = "the prediction to the reading at " + formatNumber(reading.stamp) +
                       " s (q1 = " + formatNumber(reading.q1) +
                       ", q2 = " + formatNumber(reading.q2) + ", effort " +
                       formatNumber(reading.torque) + " N m) left the model's range (|u1| > " +
                       formatNumber(max_speed_) + " rad/s, |u2| > " + formatNumber(max_speed_) +
                       " m/s or not finite)";
  }
  if (!restart_reason.empty()) {
    restart();
    start(reading, sample_time);
    return {EstimatorEvent::kRestarted, restart_reason};
  }
  const double last_stamp = last_stamp_;
  last_stamp_ = reading.stamp;
  // Its answer lands between sample + answer_delay (a simulator catching up runs its physics
  // ahead of the wall clock: the answer lands within the catch-up) and that plus the delay (a
  // stalled driver answered when it arrives): uniform between them.
  const double delay = reading.stamp - noise_.latency - sample_time;
  last_delay_ = delay / 2.0;
  last_delay_variance_ = delay * delay / 12.0 + arrival_variance_;
  if (correct(reading)) {
    outliers_ = 0;
    return {EstimatorEvent::kUpdated, ""};
  }
  const std::string far =
      "the reading at " + formatNumber(reading.stamp) + " s (q1 = " + formatNumber(reading.q1) +
      ", q2 = " + formatNumber(reading.q2) + ") is " + formatNumber(kOutlierSigma) +
      " standard deviations or more from the estimate";
  // One such reading is a corrupt message: refused, the estimate as it was. Several in a row:
  // the rig was moved, or the estimate lost it: start again from this one.
  if (++outliers_ < kOutliersBeforeRestart) {
    sample_ = before_outlier_;
    signature_ = signature_before_outlier_;
    last_stamp_ = last_stamp;
    return {EstimatorEvent::kRefused, far + " (estimate kept)"};
  }
  outliers_ = 0;
  restart();
  start(reading, sample_time);
  return {EstimatorEvent::kRestarted, far + ", " + std::to_string(kOutliersBeforeRestart) +
                                          " in a row: the rig was moved, or the estimate lost it"};
}

void MechanismEstimator::start(const RigReading& r, double sample_time) {
  // The encoders' biases belong to the sensors, not to the motion: a restart keeps them and
  // their uncertainty, grown by their walk over the silence (the first start has them at 0,
  // as the sensors' start).
  const bool keep_biases = ever_started_;
  const std::array<double, 2> biases = sample_.bias;
  const Eigen::Matrix2d bias_covariance = sample_.covariance.bottomRightCorner<2, 2>();
  const double silence = std::max(0.0, sample_time - sample_.time);
  started_ = ever_started_ = true;
  last_stamp_ = r.stamp;
  last_delay_ = last_delay_variance_ = 0.0;
  arrival_.restart();
  arrival_.add(r.stamp);
  sample_ = FilterEstimate{};
  sample_.time = sample_time;
  sample_.torque = r.torque;
  sample_.state = {r.q1, r.q2, r.has_velocity ? r.u1 : 0.0, r.has_velocity ? r.u2 : 0.0};
  EstimateCovariance& P = sample_.covariance;
  P(0, 0) = noise_.position_variance[0];
  P(1, 1) = noise_.position_variance[1];
  P(2, 2) = r.has_velocity ? noise_.velocity_variance[0] : kUnknownCrankSpeed * kUnknownCrankSpeed;
  P(3, 3) =
      r.has_velocity ? noise_.velocity_variance[1] : kUnknownSliderSpeed * kUnknownSliderSpeed;
  if (keep_biases) {
    sample_.bias = biases;
    P.bottomRightCorner<2, 2>() = bias_covariance;
    for (int i = 0; i < 2; ++i) P(4 + i, 4 + i) += noise_.bias_walk_rate[i] * silence;
  }
  innovation_.fill(0.0);
  s_ii_.fill(0.0);
  measured_.fill(false);
  nis_ = 0.0;
  signature_ = SignatureMatrix::Zero(6, static_cast<Eigen::Index>(suspects_.size()));
  // The parameters' errors have not yet acted on a state read off the rig.
  if (considers_parameters_) sample_.parameter_cross = signature_;
}

bool MechanismEstimator::predict(FilterEstimate* e, double span, double end_torque,
                                 SignatureMatrix* signature, double answer_lateness,
                                 double answer_lateness_variance) const {
  if (!(span > 0.0)) return true;
  const auto steps = static_cast<long>(std::ceil(span / step_ - 1e-9));
  const double h = span / static_cast<double>(steps);
  const generated::Constants& constants = mechanism_.constants();
  const generated::RatesVariant variant = mechanism_.variant();
  const double start_torque = e->torque;
  double torque = start_torque;
  const double switch_at = switchOffset(span, answer_lateness);
  SignatureRates signature_rates;
  double signature_torque = std::nan("");
  const auto rates = [&](const std::array<double, 4>& x, std::array<double, 4>& dxdt) {
    const generated::Rates r =
        generated::ratesFor(variant, constants, x[0], x[1], x[2], x[3], torque);
    dxdt = {x[2], x[3], r.u1_dot, r.u2_dot};
  };
  // Process noise of one step h: white accelerations (q, u pairs) and the biases' walks.
  EstimateCovariance Q = EstimateCovariance::Zero();
  for (int i = 0; i < 2; ++i) {
    const double s = acceleration_density_[i];
    Q(i, i) = s * h * h * h / 3.0;
    Q(i, 2 + i) = Q(2 + i, i) = s * h * h / 2.0;
    Q(2 + i, 2 + i) = s * h;
    Q(4 + i, 4 + i) = noise_.bias_walk_rate[i] * h;
  }
  std::array<double, 4> x = {e->state.q1, e->state.q2, e->state.u1, e->state.u2};
  EstimateCovariance& P = e->covariance;
  for (long k = 0; k < steps; ++k) {
    // The torque between two readings' efforts: a controller answering every reading changes
    // it once per reading period, answer_delay after a sample (a period's whole multiples
    // later: the answer to an earlier reading); the first reading's effort until then, the
    // next one's after.
    torque = (static_cast<double>(k) + 0.5) * h < switch_at ? start_torque : end_torque;
    const generated::RateJacobian d =
        generated::rateJacobian(constants, x[0], x[1], x[2], x[3], torque);
    Matrix4 A = Matrix4::Zero();
    A(0, 2) = A(1, 3) = 1.0;
    for (int row = 0; row < 2; ++row)
      for (int col = 0; col < 4; ++col) A(2 + row, col) = d.d[row][col];
    const Matrix4 Ah = A * h;
    const Matrix4 Phi = Matrix4::Identity() +
                        Ah * (Matrix4::Identity() + Ah / 2.0 * (Matrix4::Identity() + Ah / 3.0));
    // P <- Phi P Phi' + Q on the (q, u) block; the biases' rows carry through Phi's identity.
    P.topLeftCorner<4, 4>() = Phi * P.topLeftCorner<4, 4>() * Phi.transpose();
    P.topRightCorner<4, 2>() = Phi * P.topRightCorner<4, 2>();
    P.bottomLeftCorner<2, 4>() = P.topRightCorner<4, 2>().transpose();
    P += Q;
    if (signature != nullptr || considers_parameters_) {
      // The signature is first order: its rates are taken once per torque held (the interval's
      // start and its switch), not at every step.
      if (!(torque == signature_torque)) {
        signature_rates = signatureRates(x, torque);
        signature_torque = torque;
      }
      if (signature != nullptr) carrySignature(signature, Phi, signature_rates, h);
      if (considers_parameters_) considerParameters(e, Phi, signature_rates, h);
    }
    rk4Step(rates, x, h);
  }
  // The switch's instant is known to the readings' jitter, a physics step and the transport's
  // delays (answer_timing_variance): its torque step's impulse is uncertain by
  // (B dM)^2 var(instant) on the speeds (B = du'/dM_m).
  if (start_torque != end_torque) {
    const generated::RateJacobian d =
        generated::rateJacobian(constants, x[0], x[1], x[2], x[3], torque);
    const Eigen::Vector2d impulse(d.d[0][4] * (end_torque - start_torque),
                                  d.d[1][4] * (end_torque - start_torque));
    P.block<2, 2>(2, 2) +=
        impulse * impulse.transpose() * (noise_.answer_timing_variance + answer_lateness_variance);
  }
  e->state = {x[0], x[1], x[2], x[3]};
  e->time += span;
  e->torque = end_torque;
  return e->state.isFinite() && std::abs(x[2]) <= max_speed_ && std::abs(x[3]) <= max_speed_ &&
         P.allFinite();
}

MechanismEstimator::SignatureRates MechanismEstimator::signatureRates(
    const std::array<double, 4>& x, double torque) const {
  // d(u')/dp for each suspect, by a step of its value (u' is smooth or linear in each).
  SignatureRates g(2, static_cast<Eigen::Index>(suspects_.size()));
  const generated::Rates base = generated::ratesFor(mechanism_.variant(), mechanism_.constants(),
                                                    x[0], x[1], x[2], x[3], torque);
  for (std::size_t j = 0; j < suspects_.size(); ++j) {
    const GeneratedMechanism& changed = suspects_[j].changed;
    const generated::Rates r =
        generated::ratesFor(changed.variant(), changed.constants(), x[0], x[1], x[2], x[3], torque);
    const auto col = static_cast<Eigen::Index>(j);
    g(0, col) = (r.u1_dot - base.u1_dot) / suspects_[j].delta;
    g(1, col) = (r.u2_dot - base.u2_dot) / suspects_[j].delta;
  }
  return g;
}

void MechanismEstimator::carrySignature(SignatureMatrix* signature, const Matrix4& Phi,
                                        const SignatureRates& g, double h) {
  // E <- Phi E + the step's own response to each suspect: d(u')/dp h on u, h^2 / 2 on q.
  SignatureMatrix& E = *signature;
  E.topRows<4>() = Phi * E.topRows<4>();
  E.topRows<2>() += (0.5 * h * h) * g;
  E.middleRows<2>(2) += h * g;
}

void MechanismEstimator::considerParameters(FilterEstimate* e, const Matrix4& Phi,
                                            const SignatureRates& g, double h) const {
  // x' = Phi x + G p, G a step's response to each parameter's standard error (as the
  // signature's: g h^2 / 2 on q, g h on u, nothing on the biases), p of unit variance and
  // C = cov(x, p): P' = Phi P Phi' + Phi C G' + G C' Phi' + G G' (Phi P Phi' already taken),
  // C' = Phi C + G.
  using Response = Eigen::Matrix<double, 4, Eigen::Dynamic, 0, 4, kMaxSuspects>;
  const SignatureRates scaled = g.array().rowwise() * parameter_sigma_.array();
  Response G(4, scaled.cols());
  G.topRows<2>() = (0.5 * h * h) * scaled;
  G.bottomRows<2>() = h * scaled;
  SignatureMatrix& C = e->parameter_cross;
  C.topRows<4>() = (Phi * C.topRows<4>()).eval();  // Phi C (the biases' rows carry through)
  const Eigen::Matrix<double, 6, 4> cross = C * G.transpose();
  EstimateCovariance& P = e->covariance;
  P.leftCols<4>() += cross;
  P.topRows<4>() += cross.transpose();
  P.topLeftCorner<4, 4>() += G * G.transpose();
  C.topRows<4>() += G;
}

double MechanismEstimator::switchOffset(double span, double lateness) const {
  // In physics steps: a sample at tick s sees the torque of the step after it, so an answer in
  // force a whole number of periods after a sample (command latency > 0) is the next reading's
  // effort from its start; with no command latency the drive takes it the step the reading
  // arrived, after that tick's sample: from the interval's start.
  const double period = span / step_;
  const double offset = std::fmod(noise_.answer_delay / step_, period);
  double at = offset * step_;
  if (offset < 1e-6 || period - offset < 1e-6) at = noise_.command_latency > 0.0 ? span : 0.0;
  // A late reading's answer came as late: a stalled driver's burst is answered when it arrives.
  return std::min(at + lateness, span);
}

FilterEstimate MechanismEstimator::atStamp() const {
  FilterEstimate now = sample_;
  if (started_ && !predict(&now, last_stamp_ - sample_.time, sample_.torque)) return sample_;
  return now;
}

bool MechanismEstimator::correct(const RigReading& r) {
  // The measured coordinates this reading holds, in MeasuredCoordinate order.
  measured_ = {true, true, r.has_velocity, r.has_velocity};
  const State& x = sample_.state;
  // Rates at the estimate for the jitter's share of the velocity readings' variance.
  const generated::Rates rates = generated::ratesFor(mechanism_.variant(), mechanism_.constants(),
                                                     x.q1, x.q2, x.u1, x.u2, sample_.torque);
  const double z[4] = {r.q1, r.q2, r.u1, r.u2};
  const double predicted[4] = {x.q1 + sample_.bias[0], x.q2 + sample_.bias[1], x.u1, x.u2};
  // The sample instant is uncertain by the jitter and, for a late stamp, by how late it is.
  const double timing = noise_.timing_variance + arrival_variance_;
  const double variance[4] = {noise_.position_variance[0] + x.u1 * x.u1 * timing,
                              noise_.position_variance[1] + x.u2 * x.u2 * timing,
                              noise_.velocity_variance[0] + rates.u1_dot * rates.u1_dot * timing,
                              noise_.velocity_variance[1] + rates.u2_dot * rates.u2_dot * timing};
  const int m = r.has_velocity ? 4 : 2;
  // At most 4 measured coordinates: sizes fixed at their largest, nothing allocated.
  using Rows = Eigen::Matrix<double, Eigen::Dynamic, 6, 0, 4, 6>;
  using Square = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 4, 4>;
  using Gain = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, 4>;
  using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 4, 1>;
  Rows H = Rows::Zero(m, 6);
  Vector nu(m);
  Square R = Square::Zero(m, m);
  for (int i = 0; i < m; ++i) {
    H(i, i) = 1.0;                 // q1, q2, u1, u2
    if (i < 2) H(i, 4 + i) = 1.0;  // + the encoder's bias
    nu(i) = z[i] - predicted[i];
    R(i, i) = variance[i];
  }
  nu(0) = std::remainder(nu(0), 2.0 * M_PI);  // a crank reading wrapped to a turn is the same angle
  EstimateCovariance& P = sample_.covariance;
  const Gain PHt = P * H.transpose();
  const Square S = H * PHt + R;
  // A reading this far from the estimate is no correction of it: taken, its innovation would
  // drag every coordinate and the biases with it.
  for (int i = 0; i < m; ++i)
    if (!(std::abs(nu(i)) <= kOutlierSigma * std::sqrt(S(i, i)))) return false;
  const Eigen::LLT<Square> llt(S);
  const Gain K = llt.solve(PHt.transpose()).transpose();
  const EstimateVector dx = K * nu;
  sample_.state.q1 += dx(0);
  sample_.state.q2 += dx(1);
  sample_.state.u1 += dx(2);
  sample_.state.u2 += dx(3);
  sample_.bias[0] += dx(4);
  sample_.bias[1] += dx(5);
  // Joseph's form keeps P symmetric and positive whatever the gain's rounding.
  const EstimateCovariance IKH = EstimateCovariance::Identity() - K * H;
  P = IKH * P * IKH.transpose() + K * R * K.transpose();
  P = 0.5 * (P + P.transpose()).eval();
  nis_ = nu.dot(llt.solve(nu));
  innovation_.fill(0.0);
  s_ii_.fill(0.0);
  std::array<double, kMeasuredCoordinates> normalised{};
  for (int i = 0; i < m; ++i) {
    innovation_[i] = nu(i);
    s_ii_[i] = S(i, i);
    normalised[i] = nu(i) / std::sqrt(S(i, i));
  }
  // Each suspect's evidence: its signature in the innovations, Sigma = H E, weighed by S^-1;
  // then the filter's correction takes its share of that error too, E <- (I - K H) E.
  using SuspectRows = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 4, kMaxSuspects>;
  const SuspectRows Sigma = H * signature_;
  const SuspectRows S_inv_Sigma = llt.solve(Sigma);
  const Vector S_inv_nu = llt.solve(nu);
  const auto n = static_cast<std::size_t>(signature_.cols());
  evidence_.resize(n);
  information_.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    const auto c = static_cast<Eigen::Index>(j);
    evidence_[j] = Sigma.col(c).dot(S_inv_nu);
    information_[j] = Sigma.col(c).dot(S_inv_Sigma.col(c));
  }
  if (considers_parameters_) {
    // Each suspect's share of the considered parameters' errors: m_j = sigma_j' S^-1 H C.
    const SuspectRows HC = H * sample_.parameter_cross;
    const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxSuspects, kMaxSuspects> M =
        S_inv_Sigma.transpose() * HC;
    considered_.resize(n * n);
    for (std::size_t j = 0; j < n; ++j)
      for (std::size_t i = 0; i < n; ++i)
        considered_[j * n + i] = M(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(i));
    // And each measured coordinate's: (H C)_i / sqrt(S_ii).
    considered_coordinates_.assign(kMeasuredCoordinates * n, 0.0);
    for (int i = 0; i < m; ++i)
      for (std::size_t k = 0; k < n; ++k)
        considered_coordinates_[static_cast<std::size_t>(i) * n + k] =
            HC(i, static_cast<Eigen::Index>(k)) / std::sqrt(S(i, i));
  }
  signature_ = (IKH * signature_).eval();
  // The parameters are not corrected: only the state's share of their errors is.
  if (considers_parameters_) sample_.parameter_cross = (IKH * sample_.parameter_cross).eval();
  const bool closed = alarm_.add(sample_.time, nis_, measured_, normalised, evidence_, information_,
                                 considers_parameters_ ? considered_ : no_considered_,
                                 considers_parameters_ ? considered_coordinates_ : no_considered_);
  // A new window looks for a change from its start.
  if (closed) signature_.setZero();
  return true;
}

}  // namespace kane_sim
