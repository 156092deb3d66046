// The mechanism's state in the textbook example's generalized coordinates and speeds.
#ifndef KANE_SIM_MODEL_STATE_H
#define KANE_SIM_MODEL_STATE_H

#include <array>
#include <cmath>

#include <Eigen/Core>

namespace kane_sim {

constexpr int kNumSpeeds = 2;  // mobility M = 3n - 2c5 - c4 = 3(4) - 2(5) - 0 = 2
using SpeedVector = Eigen::Matrix<double, kNumSpeeds, 1>;

struct State {
  double q1 = 0.0;  // [rad]   q1: angle from the down-pointing i axis to rod 1
  double q2 = 0.0;  // [m]     q2: x of slider 4's mass center C
  double u1 = 0.0;  // [rad/s] u1 = q1'
  double u2 = 0.0;  // [m/s]   u2 = q2'

  SpeedVector speeds() const { return SpeedVector(u1, u2); }
  bool isFinite() const {
    return std::isfinite(q1) && std::isfinite(q2) && std::isfinite(u1) && std::isfinite(u2);
  }
};

// The first-order form x = [q1, q2, u1, u2, W, D] that Boost.Odeint integrates: the state and
// the energy ledger's motor work W [J] and dissipated energy D [J], integrated with it.
using OdeState = std::array<double, 6>;

inline OdeState toOdeState(const State& s, double motor_work = 0.0, double dissipated = 0.0) {
  return {s.q1, s.q2, s.u1, s.u2, motor_work, dissipated};
}
inline State fromOdeState(const OdeState& x) { return {x[0], x[1], x[2], x[3]}; }

}  // namespace kane_sim

#endif  // KANE_SIM_MODEL_STATE_H
