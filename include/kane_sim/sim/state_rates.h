// The rates of many states at once: x' = (q1', q2', u1', u2') of each row of an n x 4 array,
// from the equations a Simulator steps (its config and equations variant), across the cores for
// large n. What Python's Simulator.rates and learning code's batched model calls run.
#ifndef KANE_SIM_SIM_STATE_RATES_H
#define KANE_SIM_SIM_STATE_RATES_H

#include "kane_sim/sim/simulator.h"

namespace kane_sim {

// Fills out (n x 4, row-major) with the rates of states (n x 4) at torque[i] (per_state) or
// torque[0] for all. The inputs are the caller's to check (finite, within the torque limit).
// Returns the first row whose rates are not finite (beyond the mechanism's scale), or -1.
// Rows are spread over the cores from kParallelRatesFrom on (fewer cost less than the threads).
constexpr long kParallelRatesFrom = 1L << 16;
long stateRates(const Simulator& simulator, const double* states, long n, const double* torque,
                bool per_state, double* out);

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_STATE_RATES_H
