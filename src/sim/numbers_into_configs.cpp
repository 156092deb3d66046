// A batch's configs from a table of numbers: the loader's rule per number, its derived inertia,
// the start-up check; no YAML.
#include "kane_sim/sim/numbers_into_configs.h"

#include "kane_sim/config/load_config.h"
#include "kane_sim/model/mechanism_laws.h"
#include "kane_sim/sim/config_check.h"
#include "kane_sim/sim/parallel.h"

namespace kane_sim {

bool takenDirectly(const ParameterSpec& spec) {
  switch (spec.role) {
    case ParameterRole::kInertial:
    case ParameterRole::kGeometric:
    case ParameterRole::kGravity:
    case ParameterRole::kStiffness:
    case ParameterRole::kDissipative:
    case ParameterRole::kInitialState:
      return spec.field.number != nullptr;
    default:
      return false;
  }
}

Config configWithNumbers(const Config& base, bool inertia_from_mass,
                         const std::vector<const ParameterSpec*>& specs, const double* values) {
  Config c = base;
  bool inertia_given = false;  // as the loader: an inertia written in is kept, not derived
  for (std::size_t j = 0; j < specs.size(); ++j) {
    storeNumber(specs[j]->path(), *specs[j], values[j], &c);
    inertia_given = inertia_given || specs[j]->path() == "mechanism.rod_inertia";
  }
  if (inertia_from_mass && !inertia_given)
    c.mechanism.rod_inertia = slenderRodInertia(c.mechanism.rod_mass, c.mechanism.rod_half_length);
  checkSimulatable(c);
  return c;
}

bool inertiaFollowsMass(const YAML::Node& base) {
  const YAML::Node mechanism = base["mechanism"];
  return !(mechanism && mechanism.IsMap() && mechanism["rod_inertia"]);
}

std::vector<Config> configsWithNumbers(const Config& base, bool inertia_from_mass,
                                       const std::vector<const ParameterSpec*>& specs,
                                       const double* values, std::size_t n, unsigned threads,
                                       const std::atomic<bool>* stop) {
  std::vector<Config> out(n, base);
  const std::size_t k = specs.size();
  parallelBlocks(static_cast<long>(n), threads, [&](long begin, long end) {
    for (long i = begin; i < end; ++i) {
      if (stop && stop->load(std::memory_order_relaxed)) return;
      try {
        out[static_cast<std::size_t>(i)] = configWithNumbers(
            base, inertia_from_mass, specs, values + static_cast<std::size_t>(i) * k);
      } catch (const ConfigError& e) {
        throw MechanismConfigError("mechanism " + std::to_string(i) + ": " + e.what());
      }
    }
  });
  return out;
}

}  // namespace kane_sim
