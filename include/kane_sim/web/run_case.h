// One offline run as `simulate` makes it, from text in memory: a config's YAML, a duration, a
// torque profile and an output rate -> simulate's CSV columns and rows as numbers. The browser's
// kaneSim.run; the same loader (the same refusals, word for word), the same driver and the same
// loop (runOnGrid) as simulate.
#ifndef KANE_SIM_WEB_RUN_CASE_H
#define KANE_SIM_WEB_RUN_CASE_H

#include <atomic>
#include <optional>
#include <string>
#include <vector>

#include "kane_sim/sim/torque_profile.h"

namespace kane_sim {
namespace web {

struct CaseTable {
  std::vector<std::string> columns;   // simulate's CSV header
  std::vector<double> values;         // the rows, one after the other: rows() x columns.size()
  std::vector<std::string> warnings;  // the loader's (unknown keys) and the driver's events
  std::string refused;                // a refused step: why (the rows before it are kept)
  bool stopped = false;               // `stop` was set: the rows until then
  size_t rows() const { return columns.empty() ? 0 : values.size() / columns.size(); }
};

// The most rows one call returns: about 1 KB each in the page (a Float64Array copy, the rows as
// arrays and the plots' columns), so at most ~200 MB: an hour at 50 Hz, 200 s at 1 kHz. A run
// past it is refused before it starts (std::invalid_argument naming outputRate).
constexpr long kMaxCaseRows = 200000;

// Throws ConfigError for a config the loader or the start-up check refuses (what() as simulate
// prints it after the file's name; `config_name` stands where simulate names the file), and
// std::invalid_argument naming "duration" or "outputRate" for a grid outputGrid refuses. No
// profile: 0 N m, or a servo's initial setpoint, as simulate.
CaseTable runCase(const std::string& yaml_text, const std::string& config_name, double duration,
                  const std::optional<TorqueProfile>& profile, double output_rate,
                  const std::atomic<bool>* stop = nullptr);

}  // namespace web
}  // namespace kane_sim

#endif  // KANE_SIM_WEB_RUN_CASE_H
