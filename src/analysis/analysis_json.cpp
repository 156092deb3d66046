#include "kane_sim/analysis/analysis_json.h"

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "kane_sim/format_number.h"

namespace kane_sim {
namespace {

// JSON numbers: the shortest exact form; JSON has no NaN or infinity, so a non-finite value is
// null and `notes` says which and why.
class JsonNumbers {
 public:
  std::string operator()(double value, const std::string& what) {
    if (!std::isfinite(value)) {
      notes_.push_back(what + " is " + (std::isnan(value) ? "undefined" : "infinite") + " (null)");
      return "null";
    }
    return formatNumber(value);
  }
  std::string row(const Eigen::VectorXd& v, const std::string& what) {
    std::string out = "[";
    for (Eigen::Index i = 0; i < v.size(); ++i)
      out += (i ? ", " : "") + (*this)(v[i], what + "[" + std::to_string(i) + "]");
    return out + "]";
  }
  void note(const std::string& text) { notes_.push_back(text); }
  std::string notes() const {
    std::string out = "[";
    for (size_t i = 0; i < notes_.size(); ++i) out += (i ? ", \"" : "\"") + notes_[i] + "\"";
    return out + "]";
  }

 private:
  std::vector<std::string> notes_;  // plain text: no quotes or backslashes are written into them
};

}  // namespace

std::string analysisJson(const LinearModel& l, const ModalAnalysis& modal) {
  JsonNumbers number;
  for (const std::string& note : l.notes) number.note(note);
  if (modal.stability == "unstable")
    number.note("the operating point is an unstable equilibrium: no natural frequencies or modes");
  const auto jsonRow = [&number](const Eigen::VectorXd& v, const std::string& what) {
    return number.row(v, what);
  };
  std::ostringstream out;
  out << "{\n  \"torque\": " << number(l.torque, "torque") << ",\n";
  out << "  \"equilibrium\": {\"q1\": " << number(l.operating_point.q1, "equilibrium q1")
      << ", \"q2\": " << number(l.operating_point.q2, "equilibrium q2") << "},\n";
  out << "  \"stability\": \"" << modal.stability << "\",\n";
  out << "  \"state\": [\"q1\", \"q2\", \"u1\", \"u2\"],\n  \"A\": [";
  for (int r = 0; r < 4; ++r)
    out << (r ? ",\n        " : "")
        << jsonRow(l.A.row(r).transpose(), "A[" + std::to_string(r) + "]");
  out << "],\n  \"B\": " << jsonRow(l.B, "B") << ",\n  \"eigenvalues\": [";
  for (size_t i = 0; i < modal.eigenvalues.size(); ++i)
    out << (i ? ", " : "") << "[" << number(modal.eigenvalues[i].real(), "an eigenvalue") << ", "
        << number(modal.eigenvalues[i].imag(), "an eigenvalue") << "]";
  std::string frequencies, ratios, shapes, neutral;
  for (size_t i = 0; i < modal.modes.size(); ++i) {
    const Mode& m = modal.modes[i];
    const std::string sep = i ? ", " : "";
    const std::string name = "mode " + std::to_string(i + 1);
    frequencies += sep + number(m.natural_frequency_hz, name + "'s frequency");
    if (m.neutral) {
      number.note(name +
                  " is neutral: no restoring stiffness along its shape, frequency 0, no "
                  "damping ratio");
      ratios += sep + "null";
    } else {
      ratios += sep + number(m.damping_ratio, name + "'s damping ratio");
    }
    shapes += sep + jsonRow(m.shape, name + "'s shape");
    neutral += sep + (m.neutral ? "true" : "false");
  }
  out << "],\n  \"natural_frequencies_hz\": [" << frequencies << "],\n  \"damping_ratios\": ["
      << ratios << "],\n  \"neutral\": [" << neutral << "],\n  \"mode_shapes\": [" << shapes
      << "],\n  \"notes\": " << number.notes() << "\n}\n";
  return out.str();
}

}  // namespace kane_sim
