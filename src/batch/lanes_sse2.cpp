// Lanes on sse2: 2 doubles per instruction. Built with this instruction set's flags
// (CMakeLists.txt); called only when the CPU has it (lanes.cpp).
#include "simd_lanes.h"

namespace kane_sim {
void runLaneBlockSse2(const LaneBlock& block) { runSimdLaneBlock<xsimd::sse2>(block); }
}  // namespace kane_sim
