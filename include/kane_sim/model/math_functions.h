// The functions the equations of motion call beyond + - * /: sin and cos of one angle (q1) and
// tanh (Coulomb friction's law). One implementation of each, named here, for every path: a
// Simulator, the node, the offline tools, the generic Kane assembly, the geometry the tf frames
// come from, and every SIMD lane width (src/batch/simd_lanes.h calls the same functions' vector
// forms).
//
// They are SLEEF's deterministic functions ("cinz", 3.5-ulp): the same bits for the same
// argument in scalar code and at every vector width (SSE2, AVX, AVX-512), so that W mechanisms
// stepped in one vector equal W single runs bit for bit while taking sin and cos W at a time
// (libm per lane took half of a lane's time). On x86-64 the scalar form is SLEEF's SSE2 one on
// one lane (the same bits as its portable C form, and faster). The WebAssembly build (no SLEEF
// there) takes emscripten's libm, musl's: its runs equal the native ones to ~1e-14 over seconds
// of motion, and bit for bit when musl's functions stand in for these (the browser test does
// that). Measured choice and trade-off: doc/reports/performance.md.
// `static`: a translation unit built for a wider instruction set (src/batch/lanes_avx2.cpp) keeps
// its own copy instead of offering it to the linker as everyone's.
#ifndef KANE_SIM_MODEL_MATH_FUNCTIONS_H
#define KANE_SIM_MODEL_MATH_FUNCTIONS_H

#if defined(__EMSCRIPTEN__)
#include <cmath>
#else
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <sleef.h>
#endif

namespace kane_sim {
namespace math {

// *s = sin x, *c = cos x (radians).
static inline void sinCos(double x, double* s, double* c) {
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

static inline double tanh(double x) {
#if defined(__EMSCRIPTEN__)
  return std::tanh(x);
#elif defined(__SSE2__)
  return _mm_cvtsd_f64(Sleef_cinz_tanhd2_u35sse2(_mm_set_sd(x)));
#else
  return Sleef_cinz_tanhd1_u35purec(x);
#endif
}

}  // namespace math
}  // namespace kane_sim

#endif  // KANE_SIM_MODEL_MATH_FUNCTIONS_H
