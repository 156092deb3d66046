// Lanes of plain double, one at a time: the single Simulator's arithmetic, bit for bit.
#include "lane_block.h"

namespace kane_sim {
void runLaneBlockScalar(const LaneBlock& block) {
  runLaneBlockOf<double, generated::Math<double>>(block);
}
}  // namespace kane_sim
