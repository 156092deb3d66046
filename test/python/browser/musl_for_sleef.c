/* The native build's calls into SLEEF (include/kane_sim/model/math_functions.h: its
 * deterministic sincos beyond |x| = 1e14; tanh for the library's SSE2 form, which the single run
 * no longer calls) answered with musl's sin, cos and tanh, for the browser test's LD_PRELOAD
 * library: `simulate` then computes with the WebAssembly build's functions everywhere (below
 * 1e14 both builds run the same written-out sincos and tanh), and the two must agree bit for
 * bit (the same C++ on the same numbers). */
#include <emmintrin.h>
#include <sleef.h>

double sin(double);
double cos(double);
double tanh(double);

Sleef___m128d_2 Sleef_cinz_sincosd2_u35sse2(__m128d x) {
  double in[2];
  _mm_storeu_pd(in, x);
  Sleef___m128d_2 out;
  out.x = _mm_set_pd(sin(in[1]), sin(in[0]));
  out.y = _mm_set_pd(cos(in[1]), cos(in[0]));
  return out;
}

__m128d Sleef_cinz_tanhd2_u35sse2(__m128d x) {
  double in[2];
  _mm_storeu_pd(in, x);
  return _mm_set_pd(tanh(in[1]), tanh(in[0]));
}
