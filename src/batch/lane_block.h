// The lanes' stepping loop, a template over the number type B: double (one lane) or an xsimd
// batch of doubles (W lanes). Private to src/batch: each lanes_<arch>.cpp includes it once,
// built with that instruction set's flags, and exports one plain function. Nothing here may be
// an inline function of a type other TUs use too (the linker could keep this TU's copy, built
// for an instruction set the CPU may lack): raw pointers in, no std::vector, no std::min.
#ifndef KANE_SIM_SRC_BATCH_LANE_BLOCK_H
#define KANE_SIM_SRC_BATCH_LANE_BLOCK_H

#include <array>
#include <cmath>
#include <cstring>

#include "kane_sim/batch/lanes.h"
#include "kane_sim/model/rk4_step.h"
#include "kane_sim/model/slider_geometry.h"

namespace kane_sim {

// One call's lanes, as raw pointers (see above).
struct LaneBlock {
  const generated::Constants* constants;
  // When not null: this block's constants, torque limits and reaches as W-wide columns, in that
  // order (LaneRun::packed), read in place of constants' and torque_limit's.
  const double* packed;
  const double* torque_limit;
  const LaneState* start;
  generated::RatesVariant variant;
  double step;
  const double* command;       // one for all lanes per step, or
  const double* lane_command;  // one per lane for every step (when not null)
  long steps;
  bool stop_at_crossing;
  long steps_per_sample;
  const std::atomic<bool>* stop;
  void (*on_sample)(void*, std::size_t, const LaneState&);
  void* sample_context;
  bool vector_trig;          // SIMD lanes: xsimd's sincos instead of the equations' own
  std::size_t first, count;  // lanes first .. first + count - 1, count <= the width
  LaneOutcome* out;          // count of them
};

// One per instruction set (lanes_<arch>.cpp): block.count lanes, at most that set's width.
void runLaneBlockScalar(const LaneBlock& block);
void runLaneBlockSse2(const LaneBlock& block);
void runLaneBlockAvx2(const LaneBlock& block);
void runLaneBlockAvx512(const LaneBlock& block);
// And the equations' functions on `count` values, that set's width at a time (padded with 0).
using LaneMathRun = void (*)(const double* x, std::size_t count, double* sines, double* cosines,
                             double* tanhs);
void laneMathScalar(const double* x, std::size_t count, double* s, double* c, double* t);
void laneMathSse2(const double* x, std::size_t count, double* s, double* c, double* t);
void laneMathAvx2(const double* x, std::size_t count, double* s, double* c, double* t);
void laneMathAvx512(const double* x, std::size_t count, double* s, double* c, double* t);

// What the loop needs of its number type, for double (bool masks) and batches (batch_bool).
template <class B>
struct Lanes;

template <>
struct Lanes<double> {
  static constexpr std::size_t width = 1;
  using Mask = bool;
  static double load(const double* p) { return *p; }
  static double loadUnaligned(const double* p) { return *p; }
  static double strided(const double* p, std::size_t) { return *p; }
  static void store(double v, double* p) { *p = v; }
  static double select(bool m, double a, double b) { return m ? a : b; }
  static bool both(bool a, bool b) { return a && b; }
  static bool either(bool a, bool b) { return a || b; }
  static bool negate(bool a) { return !a; }
  static bool any(bool m) { return m; }
  static double abs(double v) { return std::abs(v); }
  static double max(double a, double b) { return a < b ? b : a; }  // std::max's order
  static void toBools(bool m, bool* out) { out[0] = m; }
};

// The equations' functions through MathOf (generated::Math's shape) on number type B.
template <class B, class MathOf>
void runLaneMathOf(const double* x, std::size_t count, double* sines, double* cosines,
                   double* tanhs) {
  constexpr std::size_t W = Lanes<B>::width;
  alignas(64) double in[W], s[W], c[W], t[W];
  for (std::size_t first = 0; first < count; first += W) {
    for (std::size_t j = 0; j < W; ++j) in[j] = first + j < count ? x[first + j] : 0.0;
    B sine, cosine;
    MathOf::sinCos(Lanes<B>::load(in), &sine, &cosine);
    Lanes<B>::store(sine, s);
    Lanes<B>::store(cosine, c);
    Lanes<B>::store(MathOf::tanh(Lanes<B>::load(in)), t);
    for (std::size_t j = 0; j < W && first + j < count; ++j) {
      sines[first + j] = s[j];
      cosines[first + j] = c[j];
      tanhs[first + j] = t[j];
    }
  }
}

namespace {

// x' = f(x) at the held torque: q' = u, u' (generated), W' = M_m u1, D' (the resistances'
// power), as GeneratedMechanism::stateDerivative without the motor line.
template <class B, class MathOf>
struct LaneEquations {
  const generated::ConstantsOf<B>* constants;
  B torque;
  generated::RatesVariant variant;
  void operator()(const std::array<B, 6>& x, std::array<B, 6>& dxdt) const {
    const generated::RatesOf<B> r =
        generated::ratesFor<B, MathOf>(variant, *constants, x[0], x[1], x[2], x[3], torque);
    dxdt = {x[2], x[3], r.u1_dot, r.u2_dot, torque * x[2], r.dissipated_power};
  }
};

// B: the number type; MathOf: the functions the equations call on B (generated::Math's shape).
template <class B, class MathOf>
void runLaneBlockOf(const LaneBlock& block) {
  using L = Lanes<B>;
  using Mask = typename L::Mask;
  constexpr std::size_t W = L::width;
  constexpr int kConstants = sizeof(generated::Constants) / sizeof(double);
  static_assert(sizeof(generated::ConstantsOf<B>) == kConstants * sizeof(B),
                "ConstantsOf is kConstants numbers, nothing else");
  // Lane j of the block; the lanes past `count` repeat the last real one (their results dropped).
  const auto index = [&block](std::size_t j) {
    return block.first + (j < block.count ? j : block.count - 1);
  };
  // One number of each lane into a register, not through memory: W scalar stores read back as
  // one vector stall store forwarding (~12 cycles each; a call of one step gathers ~30 of them).
  const auto gather = [&](auto value_of) {
    double lane[W];
    for (std::size_t j = 0; j < W; ++j) lane[j] = value_of(index(j));
    return L::strided(lane, 1);
  };
  // A condition per lane, the same way: 1 or 0 gathered, compared.
  const auto gatherMask = [&](auto holds) {
    return gather([&](std::size_t i) { return holds(i) ? 1.0 : 0.0; }) != B(0.0);
  };
  generated::ConstantsOf<B> constants;
  B* constant = reinterpret_cast<B*>(&constants);
  B limit, reach;  // reach: |x_B| <= 4L
  if (block.packed) {
    for (int f = 0; f < kConstants; ++f) constant[f] = L::loadUnaligned(block.packed + f * W);
    limit = L::loadUnaligned(block.packed + kConstants * W);
    reach = L::loadUnaligned(block.packed + (kConstants + 1) * W);
  } else {
    for (int f = 0; f < kConstants; ++f)
      constant[f] = gather(
          [&](std::size_t i) { return reinterpret_cast<const double*>(&block.constants[i])[f]; });
    limit = gather([&](std::size_t i) { return block.torque_limit[i]; });
    reach = gather(
        [&](std::size_t i) { return slider3Position(block.constants[i].rod_half_length, 1.0); });
  }
  const B lower = -limit;
  // x_C - x_B >= 0 in each lane (sliderSeparationAtLeast's test): bounds first, the cosine only
  // for lanes they leave open.
  const auto apartAt = [&](const B& q1, const B& q2) {
    const Mask apart = q2 - reach >= B(0.0);
    const Mask open = L::negate(L::either(apart, q2 + reach < B(0.0)));
    if (!L::any(open)) return apart;
    alignas(64) double crank[W], slider[W];
    L::store(q1, crank);
    L::store(q2, slider);
    return gatherMask([&](std::size_t i) {
      const std::size_t j = i - block.first;
      return sliderSeparationAtLeast(block.constants[i].rod_half_length, crank[j], slider[j], 0.0);
    });
  };
  std::array<B, 6> x;
  B held(0.0);
  if (block.count == W) {  // a full block: each number straight from its place
    for (int k = 0; k < 6; ++k) x[k] = L::strided(&block.start[block.first][k], 6);
    if (block.lane_command) held = L::loadUnaligned(block.lane_command + block.first);
  } else {
    for (int k = 0; k < 6; ++k) x[k] = gather([&](std::size_t i) { return block.start[i][k]; });
    if (block.lane_command) held = gather([&](std::size_t i) { return block.lane_command[i]; });
  }
  Mask below = apartAt(x[0], x[1]);
  Mask running = B(0.0) == B(0.0);  // every lane
  bool flags[W];
  B crossings(0.0), max_q1(0.0), max_q2(0.0), ran(0.0);  // ran: each lane's steps taken
  const B h(block.step);
  long until_sample = block.steps_per_sample;
  bool stopped = false;
  for (long i = 0; i < block.steps; ++i) {
    if ((i & 255) == 0 && block.stop && block.stop->load(std::memory_order_relaxed)) {
      stopped = true;
      break;
    }
    const B command = block.lane_command ? held : B(block.command[i]);
    // std::clamp(command, -limit, limit), the same comparisons.
    const B torque = L::select(command < lower, lower, L::select(limit < command, limit, command));
    const LaneEquations<B, MathOf> equations{&constants, torque, block.variant};
    std::array<B, 6> trial = x;
    rk4Step(equations, trial, block.step);
    // The Simulator's checks: finite and within 1e100, the crank under 1 rad in the step.
    Mask ok = L::abs(trial[2]) * h <= B(1.0);
    for (int k = 0; k < 6; ++k) ok = L::both(ok, L::abs(trial[k]) <= B(1e100));
    ok = L::both(ok, running);
    running = ok;
    for (int k = 0; k < 6; ++k) x[k] = L::select(ok, trial[k], x[k]);
    // The crossing counter.
    const Mask now_below = apartAt(x[0], x[1]);
    const Mask flipped = L::both(
        ok, L::either(L::both(now_below, L::negate(below)), L::both(below, L::negate(now_below))));
    ran = L::select(ok, ran + B(1.0), ran);
    crossings = L::select(flipped, crossings + B(1.0), crossings);
    if (block.stop_at_crossing) running = L::both(running, L::negate(flipped));
    below = L::either(L::both(ok, now_below), L::both(L::negate(ok), below));
    max_q1 = L::select(ok, L::max(max_q1, L::abs(x[0])), max_q1);
    max_q2 = L::select(ok, L::max(max_q2, L::abs(x[1])), max_q2);
    if (!L::any(running)) break;
    if (--until_sample == 0 || i == block.steps - 1) {
      until_sample = block.steps_per_sample;
      if (block.on_sample) {
        alignas(64) double values[6][W];
        for (int k = 0; k < 6; ++k) L::store(x[k], values[k]);
        L::toBools(running, flags);
        for (std::size_t j = 0; j < block.count; ++j) {
          if (!flags[j]) continue;
          LaneState state;
          for (int k = 0; k < 6; ++k) state[k] = values[k][j];
          block.on_sample(block.sample_context, block.first + j, state);
        }
      }
    }
  }
  alignas(64) double values[6][W], counts[W], m1[W], m2[W], taken[W];
  for (int k = 0; k < 6; ++k) L::store(x[k], values[k]);
  L::store(crossings, counts);
  L::store(ran, taken);
  L::store(max_q1, m1);
  L::store(max_q2, m2);
  L::toBools(running, flags);
  for (std::size_t j = 0; j < block.count; ++j) {
    LaneOutcome& o = block.out[j];
    for (int k = 0; k < 6; ++k) o.state[k] = values[k][j];
    o.steps = static_cast<long>(taken[j]);
    o.max_abs_q1 = m1[j];
    o.max_abs_q2 = m2[j];
    o.slider_crossings = static_cast<std::uint64_t>(counts[j]);
    // Stopped at a crossing (stop_at_crossing) is not refused: the crossing step ran.
    o.refused = !flags[j] && !(block.stop_at_crossing && counts[j] > 0.0);
    o.stopped = stopped;
  }
}

}  // namespace
}  // namespace kane_sim

#endif  // KANE_SIM_SRC_BATCH_LANE_BLOCK_H
