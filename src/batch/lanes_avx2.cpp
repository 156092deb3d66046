// Lanes on avx2: 4 doubles per instruction. Built with this instruction set's flags
// (CMakeLists.txt); called only when the CPU has it (lanes.cpp).
#include "simd_lanes.h"

namespace kane_sim {
namespace {
// SLEEF's deterministic functions on this width: its AVX form without FMA, the bits of the
// SSE2 and scalar forms.
struct VectorAvx2 {
  static Sleef___m256d_2 sincos(__m256d x) { return Sleef_cinz_sincosd4_u35avx(x); }
  static __m256d tanh(__m256d x) { return Sleef_cinz_tanhd4_u35avx(x); }
};
}  // namespace

void runLaneBlockAvx2(const LaneBlock& block) { runSimdLaneBlock<xsimd::avx2, VectorAvx2>(block); }
void laneMathAvx2(const double* x, std::size_t count, double* s, double* c, double* t) {
  using B = xsimd::batch<double, xsimd::avx2>;
  runLaneMathOf<B, DeterministicMath<B, VectorAvx2>>(x, count, s, c, t);
}
}  // namespace kane_sim
