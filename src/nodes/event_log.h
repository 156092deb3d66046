// The driver's events as kane_sim_node reports them: rosconsole, one throttled call site per
// kind (a flood of one kind never hides another), refused steps also in /diagnostics.
#ifndef KANE_SIM_NODES_EVENT_LOG_H
#define KANE_SIM_NODES_EVENT_LOG_H

#include "kane_sim/sim/sim_driver.h"
#include "loop/loop_diagnostics.h"

namespace kane_sim {

void logSimEvent(const SimEvent& event, LoopDiagnostics* diagnostics);

}  // namespace kane_sim

#endif  // KANE_SIM_NODES_EVENT_LOG_H
