// The file `design lqr` writes and a controller reads: the law (state_feedback: state, torque,
// K, periodic) and how it was designed (design: the weights, A, B, the eigenvalues; read by no
// controller). YAML.
#ifndef KANE_SIM_DESIGN_LQR_FILE_H
#define KANE_SIM_DESIGN_LQR_FILE_H

#include <ostream>
#include <string>

#include "kane_sim/design/lqr.h"
#include "kane_sim/design/state_feedback.h"

namespace kane_sim {

// `config_path`: the mechanism's config the design is for (a comment for the reader).
void writeLqrYaml(std::ostream& out, const LqrDesign& design, const std::string& config_path);

// The state_feedback of a file `design lqr` wrote (YAML text). Throws std::invalid_argument
// naming the field and the value: a missing or non-numeric entry, a list of another length, a
// non-finite number.
StateFeedback stateFeedbackFromYaml(const std::string& text);
// The same from a file (a regular file of at most 1 MiB).
StateFeedback readStateFeedbackFile(const std::string& path);

}  // namespace kane_sim

#endif  // KANE_SIM_DESIGN_LQR_FILE_H
