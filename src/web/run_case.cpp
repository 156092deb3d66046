#include "kane_sim/web/run_case.h"

#include <set>
#include <stdexcept>

#include "kane_sim/config/load_config.h"
#include "kane_sim/format_number.h"
#include "kane_sim/sim/config_check.h"
#include "kane_sim/sim/csv_format.h"
#include "kane_sim/sim/output_grid.h"
#include "kane_sim/sim/profile_commands.h"
#include "kane_sim/sim/sim_driver.h"

namespace kane_sim {
namespace web {

CaseTable runCase(const std::string& yaml_text, const std::string& config_name, double duration,
                  const std::optional<TorqueProfile>& profile, double output_rate,
                  const std::atomic<bool>* stop) {
  CaseTable table;
  LoadedConfig loaded = loadSimulationConfig(loadYamlText(yaml_text, config_name));
  table.warnings = loaded.warnings;
  const Config& config = loaded.config;
  const OutputGrid grid =
      outputGrid(config.simulation.physics_rate, duration, output_rate, "duration", "outputRate");
  if (grid.rows + 1 > kMaxCaseRows)
    throw std::invalid_argument("duration x outputRate gives " + std::to_string(grid.rows + 1) +
                                " rows; one run returns at most " + std::to_string(kMaxCaseRows) +
                                " (a lower outputRate, or a shorter duration)");
  const std::vector<CsvColumn>& columns = csvColumns();
  for (const CsvColumn& c : columns) table.columns.push_back(c.name);
  table.values.reserve(static_cast<size_t>(grid.rows + 1) * columns.size());
  std::set<SimEvent::Kind> reported;  // each kind of event once, as simulate prints them
  SimDriver driver(config, [&table, &reported](const SimEvent& event) {
    if (event.kind == SimEvent::Kind::kStepRefused)
      table.refused = event.message;
    else if (reported.insert(event.kind).second)
      table.warnings.push_back(event.message + " (at t = " + formatTime(event.time) + " s)");
  });
  const RunEnd end = runOnGrid(
      driver, profileOrHold(driver, profile), grid, stop, [](const SimDriver&) {},
      [&](const SimDriver& d) {
        const Snapshot snapshot = d.snapshot();
        for (const CsvColumn& c : columns) table.values.push_back(c.value(snapshot));
      });
  table.stopped = end == RunEnd::kStopped;
  return table;
}

}  // namespace web
}  // namespace kane_sim
