// The output grid of an offline run (`simulate`, the Python module's Simulator.run): rows every
// 1/output_rate s from t = 0 to the duration, on the physics grid. One place for the rules, so
// both refuse the same runs with the same words.
#ifndef KANE_SIM_SIM_OUTPUT_GRID_H
#define KANE_SIM_SIM_OUTPUT_GRID_H

#include <string>

namespace kane_sim {

struct OutputGrid {
  long steps_per_row = 1;  // physics steps between two rows
  long rows = 0;           // rows after the initial one: duration * output_rate
  long steps() const { return rows * steps_per_row; }
};

// Throws std::invalid_argument naming the argument (`duration_name`, `rate_name`: "--duration"
// on the command line, "duration" in Python) and the value: an output rate that does not divide
// physics_rate into a whole number of steps, a duration off the output grid (with the two
// nearest that are on it), non-finite or non-positive values.
OutputGrid outputGrid(double physics_rate, double duration, double output_rate,
                      const std::string& duration_name, const std::string& rate_name);

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_OUTPUT_GRID_H
