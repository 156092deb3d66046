// The linear analysis as one JSON object: what `analyze --json` prints and what the Python
// module's kane_sim.analyze returns (parsed), from one writer.
#ifndef KANE_SIM_ANALYSIS_ANALYSIS_JSON_H
#define KANE_SIM_ANALYSIS_ANALYSIS_JSON_H

#include <string>

#include "kane_sim/analysis/linear_analysis.h"

namespace kane_sim {

// {"torque", "equilibrium": {q1, q2}, "state", "A", "B", "eigenvalues" ([re, im] pairs),
// "natural_frequencies_hz", "damping_ratios", "neutral", "mode_shapes", "notes"}. JSON has no NaN
// or infinity: a non-finite value is null and "notes" says which and why.
std::string analysisJson(const LinearModel& linear, const ModalAnalysis& modal);

}  // namespace kane_sim

#endif  // KANE_SIM_ANALYSIS_ANALYSIS_JSON_H
