// n configs from one base and a table of numbers, one column per parameter: a batch's domain
// randomisation (10^6 mechanisms with their own masses and k) without a YAML round trip and a
// Python Config per row (0.5 ms and ~50 KB each). Each row is the base's Config with the numbers
// stored by the loader's own rule (storeNumber: the same checks, the same words), the rod's
// inertia following m and L when the base's file left it out (as the loader derives it), then
// the start-up check of a simulation (checkSimulatable). Only rows of the physics and the
// initial state are taken this way (takenDirectly); the rest go through the loader.
#ifndef KANE_SIM_SIM_NUMBERS_INTO_CONFIGS_H
#define KANE_SIM_SIM_NUMBERS_INTO_CONFIGS_H

#include <atomic>
#include <cstddef>
#include <stdexcept>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "kane_sim/config/config.h"
#include "kane_sim/config/parameter_schema.h"

namespace kane_sim {

// Masses, inertia, L, g, k, dampers, friction coefficients, the initial state: numbers whose
// only ties to other rows are the rod's derived inertia and the start-up check.
bool takenDirectly(const ParameterSpec& spec);

// A row the loader's rules refuse: "mechanism 17: config key 'mechanism.rod_mass' must be
// positive, got -1" (the loader's ConfigError, its row named).
struct MechanismConfigError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// `values` (one per spec) into a copy of `base`, then the start-up check: the loader's config
// of the base's file with those values written in. Throws the loader's ConfigError.
Config configWithNumbers(const Config& base, bool inertia_from_mass,
                         const std::vector<const ParameterSpec*>& specs, const double* values);

// Whether a base file lets the rod's inertia follow its mass and L (it sets no
// mechanism.rod_inertia): what configWithNumbers' inertia_from_mass asks.
bool inertiaFollowsMass(const YAML::Node& base);

// Row i of `values` (n x specs.size(), row-major) into a copy of `base`; MechanismConfigError
// names the row. `inertia_from_mass`: the
// base's file has no mechanism.rod_inertia (it follows the rod's mass and L). Rows are built on
// up to `threads` threads. `stop` (when not null) set: the rows not yet built are left as the
// base (the caller drops the result).
std::vector<Config> configsWithNumbers(const Config& base, bool inertia_from_mass,
                                       const std::vector<const ParameterSpec*>& specs,
                                       const double* values, std::size_t n, unsigned threads,
                                       const std::atomic<bool>* stop = nullptr);

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_NUMBERS_INTO_CONFIGS_H
