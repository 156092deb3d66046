// Lanes of plain double, one at a time: the single Simulator's arithmetic, bit for bit.
#include "lane_block.h"

namespace kane_sim {
void runLaneBlockScalar(const LaneBlock& block) {
  runLaneBlockOf<double, generated::Math<double>>(block);
}
void laneMathScalar(const double* x, std::size_t count, double* s, double* c, double* t) {
  runLaneMathOf<double, generated::Math<double>>(x, count, s, c, t);
}
}  // namespace kane_sim
