#include "kane_sim/sim/output_grid.h"

#include <cmath>
#include <stdexcept>

#include "kane_sim/config/config.h"
#include "kane_sim/format_number.h"

namespace kane_sim {
namespace {

// More physics steps than this between two rows is no output grid (and would overflow a long).
constexpr double kMaxStepsPerRow = 1e12;
// More rows than this would overflow the step count.
constexpr double kMaxRows = 1e15;

}  // namespace

void checkRunDuration(double duration, const std::string& name) {
  if (!(duration >= 0 && duration <= kMaxRunDuration))
    throw std::invalid_argument(name + " must be in [0, " + formatNumber(kMaxRunDuration) +
                                "] s, got " + formatNumber(duration));
}

OutputGrid outputGrid(double physics_rate, double duration, double output_rate,
                      const std::string& duration_name, const std::string& rate_name) {
  const auto num = [](double v) { return formatNumber(v); };
  if (!(output_rate > 0) || !std::isfinite(output_rate))
    throw std::invalid_argument(rate_name + " must be a finite number > 0 [Hz], got " +
                                num(output_rate));
  checkRunDuration(duration, duration_name);
  // The output grid must sit on the physics grid.
  const double whole_steps = wholeStepsPerPeriod(physics_rate, output_rate);
  if (!(whole_steps >= 1 && whole_steps <= kMaxStepsPerRow))
    throw std::invalid_argument(rate_name + " " + num(output_rate) +
                                " Hz must divide simulation.physics_rate " + num(physics_rate) +
                                " Hz into a whole number of physics steps");
  // A duration off the output grid is refused rather than cut short.
  const double periods = duration * output_rate;
  const double whole = std::round(periods);
  if (std::abs(periods - whole) > 1e-9 * std::max(1.0, periods))
    throw std::invalid_argument(
        duration_name + " " + num(duration) + " s is not a whole number of output periods (" +
        num(1.0 / output_rate) + " s at " + rate_name + " " + num(output_rate) + " Hz): use " +
        num(std::floor(periods) / output_rate) + " or " + num(std::ceil(periods) / output_rate) +
        " s");
  if (whole * whole_steps > kMaxRows)
    throw std::invalid_argument(duration_name + " " + num(duration) + " s is " +
                                num(whole * whole_steps) + " physics steps, more than " +
                                num(kMaxRows));
  OutputGrid grid;
  grid.steps_per_row = static_cast<long>(whole_steps);
  grid.rows = static_cast<long>(whole);
  return grid;
}

}  // namespace kane_sim
