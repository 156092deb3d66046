// How the simulator integrates: which integrator and which equations of motion. Sim's choices,
// in a header of their own (CMake target kane_sim_integration, header-only) so that the config,
// below sim, can read and check them by name (config/parameter_schema.cpp) without linking sim.
#ifndef KANE_SIM_SIM_INTEGRATION_H
#define KANE_SIM_SIM_INTEGRATION_H

namespace kane_sim {

enum class IntegratorType { kRk4, kDopri5 };

constexpr const char* integratorName(IntegratorType type) {
  return type == IntegratorType::kRk4 ? "rk4" : "dopri5";
}

// Which equations of motion the integrators step: the ones generated from a SymPy KanesMethod
// derivation (model/generated_equations.h, the fast path) or the generic Kane assembly term by
// term (model/mechanism_model.h, the readable reference). They agree to rounding.
enum class EquationsSource { kGenerated, kGeneric };

constexpr const char* equationsName(EquationsSource source) {
  return source == EquationsSource::kGenerated ? "generated" : "generic";
}

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_INTEGRATION_H
