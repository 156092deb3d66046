// The output grid of an offline run (`simulate`, the Python module's Simulator.run): rows every
// 1/output_rate s from t = 0 to the duration, on the physics grid. One place for the rules, so
// both refuse the same runs with the same words.
#ifndef KANE_SIM_SIM_OUTPUT_GRID_H
#define KANE_SIM_SIM_OUTPUT_GRID_H

#include <string>

namespace kane_sim {

// The longest offline run [s] (~4 months of sim time; beyond that is a typo): simulate's
// --duration, a sweep's and the Python module's duration.
constexpr double kMaxRunDuration = 1e7;

// Throws std::invalid_argument "NAME must be in [0, 10000000] s, got V" for a duration that is
// not finite, negative or longer than kMaxRunDuration.
void checkRunDuration(double duration, const std::string& name);

struct OutputGrid {
  long steps_per_row = 1;  // physics steps between two rows
  long rows = 0;           // rows after the initial one: duration * output_rate
  long steps() const { return rows * steps_per_row; }
};

// Throws std::invalid_argument naming the argument (`duration_name`, `rate_name`: "--duration"
// on the command line, "duration" in Python) and the value: an output rate that does not divide
// physics_rate into a whole number of steps, a duration off the output grid (with the two
// nearest that are on it), non-finite or non-positive values, durations checkRunDuration refuses.
OutputGrid outputGrid(double physics_rate, double duration, double output_rate,
                      const std::string& duration_name, const std::string& rate_name);

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_OUTPUT_GRID_H
