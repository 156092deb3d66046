// Lanes<B> and Trig<B> for xsimd's batches of doubles: what lane_block.h needs of a SIMD type.
// Included only by the lanes_<arch>.cpp files, each built with its instruction set's flags.
#ifndef KANE_SIM_SRC_BATCH_SIMD_LANES_H
#define KANE_SIM_SRC_BATCH_SIMD_LANES_H

#include <xsimd/xsimd.hpp>

#include "lane_block.h"

namespace kane_sim {

template <class A>
struct Lanes<xsimd::batch<double, A>> {
  using B = xsimd::batch<double, A>;
  using Mask = xsimd::batch_bool<double, A>;
  static constexpr std::size_t width = B::size;
  static B load(const double* p) { return B::load_aligned(p); }
  static void store(const B& v, double* p) { v.store_aligned(p); }
  static B select(const Mask& m, const B& a, const B& b) { return xsimd::select(m, a, b); }
  static Mask both(const Mask& a, const Mask& b) { return a && b; }
  static Mask either(const Mask& a, const Mask& b) { return a || b; }
  static Mask negate(const Mask& a) { return !a; }
  static bool any(const Mask& m) { return xsimd::any(m); }
  static B abs(const B& v) { return xsimd::abs(v); }
  // std::max(a, b) is (a < b) ? b : a: the same choice, lane by lane.
  static B max(const B& a, const B& b) { return xsimd::select(a < b, b, a); }
  static void toBools(const Mask& m, bool* out) { m.store_unaligned(out); }
  static Mask fromBools(const bool* in) { return Mask::load_unaligned(in); }
};

// tanh of W lanes, bit for bit libm's, one call per lane: friction's law (LoadLaw::kCoulomb) on
// every path, so that lanes with friction keep the single run's bits (vector sin/cos or not).
template <class B>
B libmTanh(const B& x) {
  alignas(64) double values[B::size];
  x.store_aligned(values);
  for (std::size_t j = 0; j < B::size; ++j) values[j] = std::tanh(values[j]);
  return B::load_aligned(values);
}

// sin and cos of W lanes, bit for bit libm's: one call per lane (what makes SIMD lanes equal the
// single run's bits; about half of a lane's time, doc/guide/batches.md).
template <class B>
struct LibmMath {
  static B tanh(const B& x) { return libmTanh(x); }
  static void sinCos(const B& x, B* s, B* c) {
    alignas(64) double in[B::size], sines[B::size], cosines[B::size];
    x.store_aligned(in);
    for (std::size_t j = 0; j < B::size; ++j) __builtin_sincos(in[j], &sines[j], &cosines[j]);
    *s = B::load_aligned(sines);
    *c = B::load_aligned(cosines);
  }
};

// xsimd's vector sincos (Cody-Waite reduction, polynomials): faster, within an ulp or two of
// libm's but not its bits; sensitive motion grows the difference (measured: batches.md).
template <class B>
struct VectorMath {
  static B tanh(const B& x) { return libmTanh(x); }
  static void sinCos(const B& x, B* s, B* c) {
    const auto both = xsimd::sincos(x);
    *s = both.first;
    *c = both.second;
  }
};

// One instruction set's block: libm's sin and cos per lane unless asked for the vector ones.
template <class A>
void runSimdLaneBlock(const LaneBlock& block) {
  using B = xsimd::batch<double, A>;
  if (block.vector_trig)
    runLaneBlockOf<B, VectorMath<B>>(block);
  else
    runLaneBlockOf<B, LibmMath<B>>(block);
}

}  // namespace kane_sim

#endif  // KANE_SIM_SRC_BATCH_SIMD_LANES_H
