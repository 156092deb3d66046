// Sweep cases on SIMD lanes (batch/lanes.h): which cases a lane runs as their single run would,
// and running a set of them. Private to the sweep runner.
#ifndef KANE_SIM_SRC_SIM_LANE_SWEEP_H
#define KANE_SIM_SRC_SIM_LANE_SWEEP_H

#include <string>
#include <vector>

#include "kane_sim/batch/lanes.h"
#include "kane_sim/sim/sweep.h"

namespace kane_sim {

// rk4 on the generated equations, free motion (contact off), no motor line, a torque command
// in force when sent (effort mode: a servo's torque depends on each lane's state at each step;
// no sensors.command_latency), and a run short enough for the command stream held in memory
// (kMaxLaneSteps). Everything else runs one case at a time, as before.
bool laneEligible(const Config& config, const SweepSettings& settings);
// What of `config` keeps it off lanes (the conditions above but the run's length), or "".
std::string whyNotOnLanes(const Config& config);

// Each lane's command array costs 8 bytes a step per group of lanes: at most 32 MB.
constexpr long kMaxLaneSteps = 1L << 22;

// Runs `configs` (each laneEligible) on lanes of `arch`, grouped by physics rate and equations
// variant. Fills results[i] for each; a case whose step the Simulator would refuse is run there
// (runSweepCase) for its message and its exact end.
void runSweepLanes(const std::vector<const Config*>& configs, const SweepSettings& settings,
                   LaneArch arch, std::vector<SweepResult*>& results);

}  // namespace kane_sim

#endif  // KANE_SIM_SRC_SIM_LANE_SWEEP_H
