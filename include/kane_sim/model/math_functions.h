// The functions the equations of motion call beyond + - * /: sin and cos of one angle (q1) and
// tanh (Coulomb friction's law). One implementation of each, named here, for every path: a
// Simulator, the node, the offline tools, the generic Kane assembly, the geometry the tf frames
// come from, and every SIMD lane width (src/batch/simd_lanes.h calls the same functions' vector
// forms).
//
// They are SLEEF's deterministic functions ("cinz", 3.5-ulp): the same bits for the same
// argument in scalar code and at every vector width (SSE2, AVX, AVX-512), so that W mechanisms
// stepped in one vector equal W single runs bit for bit while taking sin and cos W at a time
// (libm per lane took half of a lane's time). The scalar sincos is SLEEF 3.5's own algorithm
// written out below for |x| < 1e14 (every angle a run reaches: a Simulator refuses |q1| beyond
// 2 pi 1e6), operation for operation, so that it inlines into the integrator's stages: a call
// into the library spills every live register and costs a single run's rk4 step ~10 % of its
// time (doc/reports/performance.md). test_sweep holds it to the library's bits. Beyond 1e14 (and
// for NaN and infinities) the library answers. tanh is the library's (SSE2 form on one lane).
// The WebAssembly build (no SLEEF there) runs the same written-out sincos, so its runs equal the
// native ones bit for bit while |q1| < 1e14 and no friction's tanh enters; beyond that it takes
// emscripten's libm, musl's (the browser test makes the native build use musl's there too).
// `static`: a translation unit built for a wider instruction set (src/batch/lanes_avx2.cpp) keeps
// its own copy instead of offering it to the linker as everyone's.
#ifndef KANE_SIM_MODEL_MATH_FUNCTIONS_H
#define KANE_SIM_MODEL_MATH_FUNCTIONS_H

#include <cmath>
#include <cstdint>

#if !defined(__EMSCRIPTEN__)
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <sleef.h>
#endif

namespace kane_sim {
namespace math {

namespace sleef_sincos {  // SLEEF 3.5.1, src/libm/sleefsimddp.c: xsincos, DETERMINISTIC

// Its reduction constants (src/common/misc.h): pi split so that q pi/2 is exact in parts.
constexpr double kPiA2 = 3.141592653589793116, kPiB2 = 1.2246467991473532072e-16;
constexpr double kPiA = 3.1415926218032836914, kPiB = 3.1786509424591713469e-08;
constexpr double kPiC = 1.2246467864107188502e-16, kPiD = 1.2736634327021899816e-24;
constexpr double kNearRange = 15.0;  // TRIGRANGEMAX2: the two-part reduction suffices below it
constexpr double kFarRange = 1e14;   // TRIGRANGEMAX: the four-part one below it

// Round to the nearest integer, ties to even (the library's vrint), for |v| < 2^51: adding
// 1.5 2^52 leaves no fraction bits. Plain arithmetic, so the same in every build.
static inline double nearestInteger(double v) {
  constexpr double kShift = 6755399441055744.0;  // 1.5 * 2^52
  return (v + kShift) - kShift;
}

// sin and cos of d for |d| < kFarRange, as the library computes them (vmla: a multiply, then an
// add; no fused multiply-add, which the build keeps off with -ffp-contract=off).
static inline void sinCos(double d, double* sine, double* cosine) {
  double s, dql;
  if (std::abs(d) < kNearRange) {
    dql = nearestInteger(d * (2 * M_1_PI));
    s = dql * (-kPiA2 * 0.5) + d;
    s = dql * (-kPiB2 * 0.5) + s;
  } else {
    const double dqh =
        static_cast<double>(static_cast<std::int64_t>(d * (2 * M_1_PI / (1 << 24)))) * (1 << 24);
    dql = nearestInteger((d * (2 * M_1_PI)) - dqh);
    s = dqh * (-kPiA * 0.5) + d;
    s = dql * (-kPiA * 0.5) + s;
    s = dqh * (-kPiB * 0.5) + s;
    s = dql * (-kPiB * 0.5) + s;
    s = dqh * (-kPiC * 0.5) + s;
    s = dql * (-kPiC * 0.5) + s;
    s = (dqh + dql) * (-kPiD * 0.5) + s;
  }
  const int ql = static_cast<int>(dql);  // the quadrant, modulo 4
  const double t = s;
  s = s * s;
  double u = 1.58938307283228937328511e-10;
  u = u * s + -2.50506943502539773349318e-08;
  u = u * s + 2.75573131776846360512547e-06;
  u = u * s + -0.000198412698278911770864914;
  u = u * s + 0.0083333333333191845961746;
  u = u * s + -0.166666666666666130709393;
  double rx = (u * s) * t + t;  // sin of the reduced angle
  if (d == 0.0 && std::signbit(d)) rx = -0.0;
  u = -1.13615350239097429531523e-11;
  u = u * s + 2.08757471207040055479366e-09;
  u = u * s + -2.75573144028847567498567e-07;
  u = u * s + 2.48015872890001867311915e-05;
  u = u * s + -0.00138888888888714019282329;
  u = u * s + 0.0416666666666665519592062;
  u = u * s + -0.5;
  const double ry = s * u + 1;  // its cos
  const bool even = (ql & 1) == 0;
  *sine = (ql & 2) == 2 ? -(even ? rx : ry) : (even ? rx : ry);
  *cosine = ((ql + 1) & 2) == 2 ? -(even ? ry : rx) : (even ? ry : rx);
}

}  // namespace sleef_sincos

// *s = sin x, *c = cos x (radians).
static inline void sinCos(double x, double* s, double* c) {
  if (std::abs(x) < sleef_sincos::kFarRange) {  // false for NaN
    sleef_sincos::sinCos(x, s, c);
    return;
  }
#if defined(__EMSCRIPTEN__)  // musl's sin and cos share sincos's kernels
  *s = std::sin(x);
  *c = std::cos(x);
#elif defined(__SSE2__)
  const Sleef___m128d_2 both = Sleef_cinz_sincosd2_u35sse2(_mm_set_sd(x));
  *s = _mm_cvtsd_f64(both.x);
  *c = _mm_cvtsd_f64(both.y);
#else
  const Sleef_double_2 both = Sleef_cinz_sincosd1_u35purec(x);
  *s = both.x;
  *c = both.y;
#endif
}

static inline double cos(double x) {
  double s, c;
  sinCos(x, &s, &c);
  return c;
}

static inline double sin(double x) {
  double s, c;
  sinCos(x, &s, &c);
  return s;
}

static inline double tanh(double x) {
#if defined(__EMSCRIPTEN__)
  return std::tanh(x);
#elif defined(__SSE2__)
  return _mm_cvtsd_f64(Sleef_cinz_tanhd2_u35sse2(_mm_set_sd(x)));
#else
  return Sleef_cinz_tanhd1_u35purec(x);
#endif
}

// *tx = tanh x, *ty = tanh y: the library's two-lane call costs what one value does (a
// friction step takes 16 tanh), and each lane's bits are the one-value call's.
static inline void tanhPair(double x, double y, double* tx, double* ty) {
#if defined(__EMSCRIPTEN__) || !defined(__SSE2__)
  *tx = tanh(x);
  *ty = tanh(y);
#else
  const __m128d both = Sleef_cinz_tanhd2_u35sse2(_mm_set_pd(y, x));
  *tx = _mm_cvtsd_f64(both);
  *ty = _mm_cvtsd_f64(_mm_unpackhi_pd(both, both));
#endif
}

}  // namespace math
}  // namespace kane_sim

#endif  // KANE_SIM_MODEL_MATH_FUNCTIONS_H
