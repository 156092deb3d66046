#include "kane_sim/sim/state_rates.h"

#include <algorithm>
#include <cmath>

#include "kane_sim/sim/parallel.h"

namespace kane_sim {

long stateRates(const Simulator& simulator, const double* states, long n, const double* torque,
                bool per_state, double* out) {
  const auto range = [&](long begin, long end) {
    simulator.withEquations([&](const auto& equations) {
      for (long i = begin; i < end; ++i) {
        const double* x = states + 4 * i;
        const OdeState d =
            equations.stateDerivative(State{x[0], x[1], x[2], x[3]}, torque[per_state ? i : 0]);
        std::copy(d.begin(), d.begin() + 4, out + 4 * i);
      }
      return 0;
    });
  };
  parallelBlocks(n, n >= kParallelRatesFrom ? coreCount() : 1, range);
  for (long i = 0; i < n; ++i)
    if (!std::all_of(out + 4 * i, out + 4 * i + 4, [](double v) { return std::isfinite(v); }))
      return i;
  return -1;
}

}  // namespace kane_sim
