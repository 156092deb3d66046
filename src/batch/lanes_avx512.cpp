// Lanes on avx512: 8 doubles per instruction. Built with this instruction set's flags
// (CMakeLists.txt); called only when the CPU has it (lanes.cpp).
#include "simd_lanes.h"

namespace kane_sim {
void runLaneBlockAvx512(const LaneBlock& block) { runSimdLaneBlock<xsimd::avx512f>(block); }
}  // namespace kane_sim
