// Lanes on avx512: 8 doubles per instruction. Built with this instruction set's flags
// (CMakeLists.txt); called only when the CPU has it (lanes.cpp).
#include "simd_lanes.h"

namespace kane_sim {
namespace {
// SLEEF's deterministic functions on this width (without FMA, as the others).
struct VectorAvx512 {
  static Sleef___m512d_2 sincos(__m512d x) { return Sleef_cinz_sincosd8_u35avx512fnofma(x); }
  static __m512d tanh(__m512d x) { return Sleef_cinz_tanhd8_u35avx512fnofma(x); }
};
}  // namespace

void runLaneBlockAvx512(const LaneBlock& block) {
  runSimdLaneBlock<xsimd::avx512f, VectorAvx512>(block);
}
void laneMathAvx512(const double* x, std::size_t count, double* s, double* c, double* t) {
  using B = xsimd::batch<double, xsimd::avx512f>;
  runLaneMathOf<B, DeterministicMath<B, VectorAvx512>>(x, count, s, c, t);
}
}  // namespace kane_sim
