// The functions the equations of motion call beyond + - * /: sin and cos of one angle (q1) and
// tanh (Coulomb friction's law). One implementation of each, named here, for every path: a
// Simulator, the node, the offline tools, the generic Kane assembly, the geometry the tf frames
// come from, and every SIMD lane width (src/batch/simd_lanes.h calls the same functions' vector
// forms).
//
// They are SLEEF's deterministic functions ("cinz", 3.5-ulp): the same bits for the same
// argument in scalar code and at every vector width (SSE2, AVX, AVX-512), so that W mechanisms
// stepped in one vector equal W single runs bit for bit while taking sin and cos W at a time
// (libm per lane took half of a lane's time). The scalar sincos and tanh are SLEEF 3.5's own
// algorithms written out below (sincos for |x| < 1e14: every angle a run reaches, a Simulator
// refuses |q1| beyond 2 pi 1e6; tanh for every argument), operation for operation, so that they
// inline into the integrator's stages: a call into the library spills every live register (the
// sincos call cost a single run's rk4 step ~10 % of its time; tanh's cost is its latency either
// way: doc/reports/performance.md). test_sweep holds them to the library's bits. Beyond 1e14 (and
// for NaN and infinities) the library answers sincos. The WebAssembly build (no SLEEF there)
// runs the same written-out functions, so its runs equal the native ones bit for bit while
// |q1| < 1e14, friction included; beyond that it takes emscripten's libm, musl's (the browser
// test makes the native build use musl's there too).
// `static`: a translation unit built for a wider instruction set (src/batch/lanes_avx2.cpp) keeps
// its own copy instead of offering it to the linker as everyone's.
#ifndef KANE_SIM_MODEL_MATH_FUNCTIONS_H
#define KANE_SIM_MODEL_MATH_FUNCTIONS_H

#include <cmath>
#include <cstdint>
#include <cstring>

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
// A template: sleef_tanh's kernel runs it on one double and on two in an SSE2 register.
template <class V>
static inline V nearestInteger(V v) {
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

namespace sleef_tanh {  // SLEEF 3.5.1, src/libm/sleefsimddp.c: xtanh_u35 and its expm1k

// ln 2 split so that q ln 2 is exact in parts, and 1 / ln 2 (src/common/misc.h).
constexpr double kLn2Upper = .69314718055966295651160180568695068359375;
constexpr double kLn2Lower = .28235290563031577122588448175013436025525412068e-12;
constexpr double kInverseLn2 = 1.442695040888963407359924681001892137426645954152985934135449406931;
constexpr double kSaturation = 18.714973875;  // beyond it the library answers +-1

// The kernel below runs on one double or on two in an SSE2 register (Two): the same IEEE
// operations in the same order, so each lane's bits are the one-value form's. What differs by
// type is the few steps on bits: |v|, 2^n, choosing per lane, and the sign.
static inline double absOf(double v) { return std::abs(v); }
// 2^n for a whole n in [0, 1023] (vpow2i: n + 1023 into the exponent's bits).
static inline double powerOfTwo(double n) {
  const std::uint64_t bits = static_cast<std::uint64_t>(static_cast<int>(n) + 0x3ff) << 52;
  double out;
  std::memcpy(&out, &bits, sizeof(out));
  return out;
}
static inline double whereZero(double v, double then, double otherwise) {
  return v == 0.0 ? then : otherwise;
}
static inline double whereAtMost(double v, double bound, double then, double otherwise) {
  return v <= bound ? then : otherwise;  // NaN: otherwise
}
// Whether every lane is below the bound, beyond it (NaN: neither): the kernel's shortcuts.
static inline bool allBelow(double v, double bound) { return v < bound; }
static inline bool allBeyond(double v, double bound) { return v > bound; }
// y with x's sign flipped in (vmulsign), then every bit set where x is NaN (the library's NaN).
static inline double signedLike(double y, double x) {
  std::uint64_t bits, sign;
  std::memcpy(&bits, &y, sizeof(bits));
  std::memcpy(&sign, &x, sizeof(sign));
  bits ^= sign & 0x8000000000000000ull;
  if (std::isnan(x)) bits = ~0ull;
  std::memcpy(&y, &bits, sizeof(y));
  return y;
}

#if defined(__SSE2__) && !defined(__EMSCRIPTEN__)
struct Two {
  __m128d v;
  explicit Two(__m128d value) : v(value) {}
  explicit Two(double c) : v(_mm_set1_pd(c)) {}
};
static inline Two operator+(Two a, Two b) { return Two(_mm_add_pd(a.v, b.v)); }
static inline Two operator-(Two a, Two b) { return Two(_mm_sub_pd(a.v, b.v)); }
static inline Two operator*(Two a, Two b) { return Two(_mm_mul_pd(a.v, b.v)); }
static inline Two operator/(Two a, Two b) { return Two(_mm_div_pd(a.v, b.v)); }
static inline Two operator+(Two a, double b) { return a + Two(b); }
static inline Two operator+(double a, Two b) { return Two(a) + b; }
static inline Two operator-(Two a, double b) { return a - Two(b); }
static inline Two operator*(Two a, double b) { return a * Two(b); }
static inline Two absOf(Two v) { return Two(_mm_andnot_pd(_mm_set1_pd(-0.0), v.v)); }
static inline Two powerOfTwo(Two n) {
  const __m128i e = _mm_add_epi32(_mm_cvtpd_epi32(n.v), _mm_set1_epi32(0x3ff));
  return Two(_mm_castsi128_pd(_mm_slli_epi64(_mm_unpacklo_epi32(e, _mm_setzero_si128()), 52)));
}
static inline Two choose(__m128d mask, Two then, Two otherwise) {
  return Two(_mm_or_pd(_mm_and_pd(mask, then.v), _mm_andnot_pd(mask, otherwise.v)));
}
static inline Two whereZero(Two v, Two then, Two otherwise) {
  return choose(_mm_cmpeq_pd(v.v, _mm_setzero_pd()), then, otherwise);
}
static inline Two whereAtMost(Two v, double bound, Two then, Two otherwise) {
  return choose(_mm_cmple_pd(v.v, _mm_set1_pd(bound)), then, otherwise);
}
static inline bool allBelow(Two v, double bound) {
  return _mm_movemask_pd(_mm_cmplt_pd(v.v, _mm_set1_pd(bound))) == 3;
}
static inline bool allBeyond(Two v, double bound) {
  return _mm_movemask_pd(_mm_cmpgt_pd(v.v, _mm_set1_pd(bound))) == 3;
}
static inline Two signedLike(Two y, Two x) {
  const __m128d flipped = _mm_xor_pd(y.v, _mm_and_pd(x.v, _mm_set1_pd(-0.0)));
  return Two(_mm_or_pd(_mm_cmpunord_pd(x.v, x.v), flipped));
}
#endif

// e^d - 1 for 0 <= d <= 2 kSaturation (expm1k): d = q ln 2 + s, a polynomial in s by
// Estrin's scheme (the library's POLY10 of MLA(x, y, z) = x y + z: a multiply, then an add),
// then scaled by 2^q in two halves (vldexp2; q >> 1 is q / 2 - 1 / 4 rounded, q >= 0).
// The polynomial part: e^s - 1 for the reduced argument s, |s| <= ln 2 / 2.
template <class V>
static inline V expm1Reduced(V s) {
  const V s2 = s * s, s4 = s2 * s2, s8 = s4 * s4;
  const V high = s * 2.08860621107283687536341e-09 + 2.51112930892876518610661e-08;
  const V upper = s2 * (s * 2.75573911234900471893338e-07 + 2.75572362911928827629423e-06) +
                  (s * 2.4801587159235472998791e-05 + 0.000198412698960509205564975);
  const V lower = s2 * (s * 0.00138888888889774492207962 + 0.00833333333331652721664984) +
                  (s * 0.0416666666666665047591422 + 0.166666666666666851703837);
  const V u = s8 * high + (s4 * upper + lower);
  return (s2 * 0.5 + (s2 * s) * u) + s;
}

template <class V>
static inline V expm1k(V d) {
  const V q = sleef_sincos::nearestInteger(d * kInverseLn2);  // vrint: ties to even
  V s = q * -kLn2Upper + d;
  s = q * -kLn2Lower + s;
  const V u = expm1Reduced(s);
  const V half = sleef_sincos::nearestInteger(q * 0.5 - 0.25);
  return whereZero(q, u, ((u + 1.0) * powerOfTwo(half)) * powerOfTwo(q - half) - 1.0);
}

// tanh x = e / (2 + e), e = e^(2|x|) - 1, with x's sign; +-1 beyond kSaturation; NaN as the
// library returns it. Beyond kSaturation (and for NaN) the quotient is taken of 0, so that
// every step stays in range, and dropped.
// Two shortcuts give the same bits sooner (a friction step waits for its tanh in every rk4
// stage): beyond kSaturation the answer is +-1 outright; below kUnreduced, 2|x| / ln 2 rounds to
// q = 0, where expm1k's reduction leaves s = 2|x| (0 * -ln 2 + s is s, +0 included) and its
// scaling is not taken, so e is the polynomial alone. Both are taken only when every lane can.
constexpr double kUnreduced = 0.17;  // 2 * 0.17 / ln 2 = 0.49 < 0.5

template <class V>
static inline V tanhOf(V x) {
  const V magnitude = absOf(x);
  if (allBeyond(magnitude, kSaturation)) return signedLike(V(1.0), x);
  if (allBelow(magnitude, kUnreduced)) {
    const V e = expm1Reduced(magnitude * 2.0);
    return signedLike(e / (2.0 + e), x);
  }
  const V within = whereAtMost(magnitude, kSaturation, magnitude, V(0.0));
  const V e = expm1k(within * 2.0);
  return signedLike(whereAtMost(magnitude, kSaturation, e / (2.0 + e), V(1.0)), x);
}

}  // namespace sleef_tanh

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

// tanh x (SLEEF's deterministic tanh, written out above: its bits, inlined).
static inline double tanh(double x) { return sleef_tanh::tanhOf(x); }

// *tx = tanh x, *ty = tanh y: two at once in one SSE2 register where there is one (a friction
// step takes 16 tanh), each lane the one-value form's bits.
static inline void tanhPair(double x, double y, double* tx, double* ty) {
  // Both beyond the saturation (a moving mechanism's usual case): +-1 without packing a register.
  if (std::abs(x) > sleef_tanh::kSaturation && std::abs(y) > sleef_tanh::kSaturation) {
    *tx = std::copysign(1.0, x);
    *ty = std::copysign(1.0, y);
    return;
  }
#if defined(__SSE2__) && !defined(__EMSCRIPTEN__)
  const __m128d both = sleef_tanh::tanhOf(sleef_tanh::Two(_mm_set_pd(y, x))).v;
  *tx = _mm_cvtsd_f64(both);
  *ty = _mm_cvtsd_f64(_mm_unpackhi_pd(both, both));
#else
  *tx = tanh(x);
  *ty = tanh(y);
#endif
}

}  // namespace math
}  // namespace kane_sim

#endif  // KANE_SIM_MODEL_MATH_FUNCTIONS_H
