// Lanes on sse2: 2 doubles per instruction. Built with this instruction set's flags
// (CMakeLists.txt); called only when the CPU has it (lanes.cpp).
#include "simd_lanes.h"

namespace kane_sim {
namespace {
// SLEEF's deterministic functions on this width.
struct VectorSse2 {
  static Sleef___m128d_2 sincos(__m128d x) { return Sleef_cinz_sincosd2_u35sse2(x); }
  static __m128d tanh(__m128d x) { return Sleef_cinz_tanhd2_u35sse2(x); }
};
}  // namespace

void runLaneBlockSse2(const LaneBlock& block) { runSimdLaneBlock<xsimd::sse2, VectorSse2>(block); }
void laneMathSse2(const double* x, std::size_t count, double* s, double* c, double* t) {
  using B = xsimd::batch<double, xsimd::sse2>;
  runLaneMathOf<B, DeterministicMath<B, VectorSse2>>(x, count, s, c, t);
}
}  // namespace kane_sim
