// Many mechanisms stepped together: the generated equations (model/generated_equations.h, a
// template over its number type) instantiated over a SIMD batch of doubles (xsimd), rk4 over
// W mechanisms per instruction, the widest this CPU runs chosen at run time. Each lane does
// what a single Simulator does with rk4, free motion (no contact), no motor line, and a held
// torque each step: the same stages in the same order, the same step checks, the same slider
// crossing test, and the same sin, cos and tanh (model/math_functions.h, whose vector forms
// return the scalar form's bits): every lane is that Simulator's arithmetic bit for bit
// (LaneRun::vector_trig takes xsimd's sin/cos instead: doc/guide/batches.md measures both).
// A lane whose step the Simulator would refuse is flagged, not explained: rerun that case there.
#ifndef KANE_SIM_BATCH_LANES_H
#define KANE_SIM_BATCH_LANES_H

#include <array>
#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

#include "kane_sim/model/generated_equations.h"

namespace kane_sim {

// q1, q2, u1, u2, W, D: the single Simulator's LaneState (model/state.h), named here without that
// header's Eigen: the lanes' code is built for other instruction sets, and an inline function
// of a shared library compiled there could be the copy the linker keeps for everyone.
using LaneState = std::array<double, 6>;

// The instruction sets lanes run on, narrowest first: kScalar is one lane of plain double.
enum class LaneArch { kScalar, kSse2, kAvx2, kAvx512 };

const char* laneArchName(LaneArch arch);  // "scalar", "sse2", "avx2", "avx512"
unsigned laneWidth(LaneArch arch);        // doubles per instruction: 1, 2, 4, 8
bool laneArchAvailable(LaneArch arch);    // this CPU (and this build) runs it
LaneArch bestLaneArch();                  // the widest available
// "auto" (bestLaneArch) or a name above; throws std::invalid_argument naming the value, or the
// instruction set this CPU lacks.
LaneArch parseLaneArch(const std::string& name);
// Throws std::invalid_argument naming KANE_SIM_SIMD_MAX when it is set to no instruction set's
// name (every door calls it, lanes or not, so that a typo in it is never silently ignored).
void checkLaneEnvironment();

// The mechanisms of one run: per lane its constants, torque limit and start; for all lanes one
// step size, one equations variant and one command stream.
struct LaneRun {
  std::vector<generated::Constants> constants;  // per lane
  std::vector<double> torque_limit;             // per lane: command.torque_limit [N m]
  std::vector<LaneState> start;                 // per lane: q1, q2, u1, u2, W, D
  // The generated equations' variant (generated::variantFor: the single Simulator picks it per
  // config, by the resistances that are on); lanes of different variants run apart.
  generated::RatesVariant variant = generated::kEveryTerm;
  double step = 1e-3;  // h [s]
  // The command in force during step i (i = 0 .. size-1), before each lane's clamp to its limit:
  // a profile's value at t = i h, as ProfileCommands sends it to a single run.
  std::vector<double> command;
  // Instead of `command` (when not empty): per lane one torque, held for `held_steps` steps (a
  // batched simulator's step(torques): each lane's set_torque, then step(held_steps)).
  std::vector<double> lane_command;
  long held_steps = 0;
  // A lane stops after the step in which its sliders cross (the crossing counted, that state
  // kept), as a refused step stops it: a batched simulator's termination.
  bool stop_at_crossing = false;
  // SIMD lanes: xsimd's vector sin and cos instead of the equations' own. No longer the single
  // run's bits (rounding differences, grown by sensitive motion: doc/guide/batches.md).
  bool vector_trig = false;
  long steps_per_sample = 100;
  // Optional (packLanes): constants, torque limits and reaches laid out once for one width, W
  // lanes' values of each side by side, so a call reads each block's as W-wide columns instead
  // of gathering them lane by lane (18 numbers a lane: ~6 ns a mechanism a call, measured). For
  // a caller that steps the same lanes call after call; used when packed_width is the arch's.
  std::vector<double> packed;
  unsigned packed_width = 0;
  const std::atomic<bool>* stop = nullptr;  // checked every 256 steps
  // After every steps_per_sample-th step and the last: (context, lane, state after the step),
  // for each lane still running. A plain function pointer: called from code built for the
  // lane's instruction set, it must not be a template instantiated there (doc: batches.md).
  void (*on_sample)(void* context, std::size_t lane, const LaneState& state) = nullptr;
  void* sample_context = nullptr;
};

struct LaneOutcome {
  LaneState state{};                          // after the last step run (before a refused one)
  long steps = 0;                             // steps this lane ran (not the refused one)
  double max_abs_q1 = 0.0, max_abs_q2 = 0.0;  // over the states after each step
  std::uint64_t slider_crossings = 0;
  bool refused = false;  // the Simulator would refuse a step (non-finite, runaway, > 1 rad)
  bool stopped = false;  // `stop` was set before the last step
};

// Runs every lane of `run` for run.command.size() steps (run.held_steps with lane_command) on
// `arch` (laneArchAvailable).
std::vector<LaneOutcome> runLanes(const LaneRun& run, LaneArch arch);
// The same into out[0 .. run.start.size() - 1]: a caller that steps often keeps its outcomes.
void runLanes(const LaneRun& run, LaneArch arch, LaneOutcome* out);
// run.packed for `arch` from run.constants and run.torque_limit (again after changing them).
void packLanes(LaneRun& run, LaneArch arch);

// The equations' functions (model/math_functions.h) as the lanes of `arch` compute them: sin,
// cos and tanh of values[0 .. count-1], `arch`'s width at a time (test_sweep holds every width
// to the scalar form, bit for bit).
struct LaneMathValues {
  std::vector<double> sines, cosines, tanhs;
};
LaneMathValues laneMathFunctions(LaneArch arch, const std::vector<double>& values);

}  // namespace kane_sim

#endif  // KANE_SIM_BATCH_LANES_H
