// Lanes<B> and Trig<B> for xsimd's batches of doubles: what lane_block.h needs of a SIMD type.
// Included only by the lanes_<arch>.cpp files, each built with its instruction set's flags.
#ifndef KANE_SIM_SRC_BATCH_SIMD_LANES_H
#define KANE_SIM_SRC_BATCH_SIMD_LANES_H

#include <sleef.h>
#include <xsimd/xsimd.hpp>

#include "kane_sim/model/math_functions.h"
#include "lane_block.h"

namespace kane_sim {

template <class A>
struct Lanes<xsimd::batch<double, A>> {
  using B = xsimd::batch<double, A>;
  using Mask = xsimd::batch_bool<double, A>;
  static constexpr std::size_t width = B::size;
  static B load(const double* p) { return B::load_aligned(p); }
  static B loadUnaligned(const double* p) { return B::load_unaligned(p); }
  // p[0], p[stride], p[2 stride], ...: built in a register (the compiler's loads and inserts),
  // never stored as a whole and read back (lane_block.h: store forwarding). Each branch compiles
  // only in the lanes_<arch>.cpp of its width.
  static B strided(const double* p, std::size_t stride) {
    if constexpr (width == 2) {
      return B(_mm_set_pd(p[stride], p[0]));
    } else if constexpr (width == 4) {
      return B(_mm256_set_pd(p[3 * stride], p[2 * stride], p[stride], p[0]));
    } else {
      static_assert(width == 8, "SSE2, AVX2 or AVX-512 lanes");
      return B(_mm512_set_pd(p[7 * stride], p[6 * stride], p[5 * stride], p[4 * stride],
                             p[3 * stride], p[2 * stride], p[stride], p[0]));
    }
  }
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
};

// SLEEF's tanh on W lanes, +-1 outright when every lane is beyond its saturation (the library's
// own answer there, as the scalar form's shortcut: model/math_functions.h): a block of moving
// mechanisms' friction skips the call.
template <class B, class Vector>
B saturatingTanh(const B& x) {
  if (xsimd::all(xsimd::abs(x) > B(math::sleef_tanh::kSaturation)))  // false for NaN
    return xsimd::copysign(B(1.0), x);
  return B(Vector::tanh(x));
}

// The equations' functions (model/math_functions.h) on W lanes: the vector forms of the same
// SLEEF functions, which return the scalar form's bits in every lane. `Vector` names them for
// one instruction set (lanes_<arch>.cpp): sincos(register) -> {sines, cosines}, tanh(register).
template <class B, class Vector>
struct DeterministicMath {
  static B tanh(const B& x) { return saturatingTanh<B, Vector>(x); }
  static void tanhPair(const B& x, const B& y, B* tx, B* ty) {  // every lane already used
    *tx = tanh(x);
    *ty = tanh(y);
  }
  static void sinCos(const B& x, B* s, B* c) {
    const auto both = Vector::sincos(x);
    *s = B(both.x);
    *c = B(both.y);
  }
};

// xsimd's vector sincos (Cody-Waite reduction, polynomials, with FMA where the CPU has it):
// within an ulp or two of the deterministic functions but not their bits; sensitive motion grows
// the difference (measured: batches.md). tanh stays the deterministic one.
template <class B, class Vector>
struct VectorMath {
  static B tanh(const B& x) { return saturatingTanh<B, Vector>(x); }
  static void tanhPair(const B& x, const B& y, B* tx, B* ty) {
    *tx = tanh(x);
    *ty = tanh(y);
  }
  static void sinCos(const B& x, B* s, B* c) {
    const auto both = xsimd::sincos(x);
    *s = both.first;
    *c = both.second;
  }
};

// One instruction set's block: the deterministic functions unless asked for xsimd's sincos.
template <class A, class Vector>
void runSimdLaneBlock(const LaneBlock& block) {
  using B = xsimd::batch<double, A>;
  if (block.vector_trig)
    runLaneBlockOf<B, VectorMath<B, Vector>>(block);
  else
    runLaneBlockOf<B, DeterministicMath<B, Vector>>(block);
}

}  // namespace kane_sim

#endif  // KANE_SIM_SRC_BATCH_SIMD_LANES_H
