// One classical Runge-Kutta step, the one every rk4 path takes (a Simulator, the SIMD lanes, a
// batch): odeint's runge_kutta4 arithmetic, operation for operation, on a local copy of the
// state and its four slopes. Written out here instead of calling odeint's stepper because the
// stepper keeps its slopes and coefficients in its own object: GCC then re-reads the
// equations' constants after each store into them (they could alias), and the step cost twice
// the hand-written floor of bench/bench_core.cpp. test_rk4_step holds this to odeint's
// runge_kutta4 bit for bit; dopri5 stays odeint's.
#ifndef KANE_SIM_MODEL_RK4_STEP_H
#define KANE_SIM_MODEL_RK4_STEP_H

#include <array>
#include <cstddef>

namespace kane_sim {

// x <- x + h (k1/6 + k2/3 + k3/3 + k4/6), k_i the slopes of x' = f(x) at odeint's stages.
// f(x, dxdt) writes the derivative; Real is double or a SIMD batch of doubles. odeint forms
// each coefficient as a_i * h and each stage as 1.0 * x + sum (a_i h) k_i (its zero a_i's
// terms add a signed zero to x, which is x itself except for x = -0).
template <class Real, std::size_t N, class F>
inline void rk4Step(const F& f, std::array<Real, N>& x, double h) {
  constexpr double kHalf = 1.0 / 2.0, kSixth = 1.0 / 6.0, kThird = 1.0 / 3.0;
  const double half_h = kHalf * h, sixth_h = kSixth * h, third_h = kThird * h;
  std::array<Real, N> k1, k2, k3, k4, y;
  f(x, k1);
  for (std::size_t i = 0; i < N; ++i) y[i] = x[i] + half_h * k1[i];
  f(y, k2);
  for (std::size_t i = 0; i < N; ++i) y[i] = x[i] + half_h * k2[i];
  f(y, k3);
  for (std::size_t i = 0; i < N; ++i) y[i] = x[i] + h * k3[i];
  f(y, k4);
  for (std::size_t i = 0; i < N; ++i)
    x[i] = x[i] + sixth_h * k1[i] + third_h * k2[i] + third_h * k3[i] + sixth_h * k4[i];
}

}  // namespace kane_sim

#endif  // KANE_SIM_MODEL_RK4_STEP_H
