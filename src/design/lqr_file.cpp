#include "kane_sim/design/lqr_file.h"

#include <cmath>
#include <iterator>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "kane_sim/config/input_file.h"
#include "kane_sim/format_number.h"

namespace kane_sim {
namespace {

template <class Vector>
void emitRow(YAML::Emitter& out, const Vector& v) {
  out << YAML::Flow << YAML::BeginSeq;
  for (Eigen::Index i = 0; i < v.size(); ++i) out << formatNumber(v[i] + 0.0);  // no -0
  out << YAML::EndSeq;
}

void emitMatrix(YAML::Emitter& out, const Eigen::MatrixXd& m) {
  out << YAML::BeginSeq;
  for (Eigen::Index r = 0; r < m.rows(); ++r) emitRow(out, Eigen::VectorXd(m.row(r).transpose()));
  out << YAML::EndSeq;
}

void emitEigenvalues(YAML::Emitter& out, const std::vector<std::complex<double>>& values) {
  out << YAML::BeginSeq;
  for (const auto& v : values) emitRow(out, Eigen::Vector2d(v.real(), v.imag()));
  out << YAML::EndSeq;
}

double finiteNumber(const YAML::Node& node, const std::string& field) {
  if (!node || !node.IsScalar())
    throw std::invalid_argument("state_feedback." + field + " is missing or not a number");
  double value = 0.0;
  if (!YAML::convert<double>::decode(node, value))
    throw std::invalid_argument("state_feedback." + field + " = '" + node.Scalar() +
                                "' is not a number");
  if (!std::isfinite(value))
    throw std::invalid_argument("state_feedback." + field + " = " + node.Scalar() +
                                " is not finite");
  return value;
}

Eigen::Vector4d fourNumbers(const YAML::Node& node, const std::string& field) {
  if (!node || !node.IsSequence() || node.size() != 4)
    throw std::invalid_argument("state_feedback." + field +
                                " must be a list of 4 numbers (q1, q2, u1, u2)");
  Eigen::Vector4d v;
  for (int i = 0; i < 4; ++i) v[i] = finiteNumber(node[i], field + "[" + std::to_string(i) + "]");
  return v;
}

}  // namespace

void writeLqrYaml(std::ostream& stream, const LqrDesign& d, const std::string& config_path) {
  YAML::Emitter out;
  out << YAML::Comment(std::string("kane_sim design lqr: M_m = torque - K (x - state), x = (q1, "
                                   "q2, u1, u2)") +
                       (d.feedback.periodic ? "; the crank's error within (-pi, pi]"
                                            : "; not periodic (a crank spring)"));
  out << YAML::BeginMap << YAML::Key << "state_feedback" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "state" << YAML::Value;
  emitRow(out, d.feedback.state);
  out << YAML::Key << "torque" << YAML::Value << formatNumber(d.feedback.torque);
  out << YAML::Key << "K" << YAML::Value;
  emitRow(out, d.feedback.K);
  out << YAML::Key << "periodic" << YAML::Value << d.feedback.periodic << YAML::EndMap;
  out << YAML::Key << "design" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "method" << YAML::Value << "lqr";
  out << YAML::Key << "config" << YAML::Value << config_path;
  out << YAML::Key << "Q" << YAML::Value;
  emitMatrix(out, d.weights.Q);
  out << YAML::Key << "R" << YAML::Value << formatNumber(d.weights.R);
  out << YAML::Key << "A" << YAML::Value;
  emitMatrix(out, d.A);
  out << YAML::Key << "B" << YAML::Value;
  emitRow(out, d.B);
  out << YAML::Key << "P" << YAML::Value;
  emitMatrix(out, d.P);
  out << YAML::Key << "open_loop_eigenvalues" << YAML::Value;
  emitEigenvalues(out, d.open_loop);
  out << YAML::Key << "closed_loop_eigenvalues" << YAML::Value;
  emitEigenvalues(out, d.closed_loop);
  out << YAML::Key << "riccati_residual" << YAML::Value << formatNumber(d.riccati_residual);
  out << YAML::Key << "sample_rate_needed" << YAML::Value << formatNumber(d.sample_rate_needed);
  out << YAML::Key << "notes" << YAML::Value << YAML::BeginSeq;
  for (const std::string& note : d.notes) out << note;
  out << YAML::EndSeq << YAML::EndMap << YAML::EndMap;
  stream << out.c_str() << "\n";
}

StateFeedback stateFeedbackFromYaml(const std::string& text) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument(std::string("not YAML: ") + e.what());
  }
  if (!root.IsMap() || !root["state_feedback"] || !root["state_feedback"].IsMap())
    throw std::invalid_argument(
        "no state_feedback section (a file `rosrun kane_sim design lqr` writes has one)");
  const YAML::Node law = root["state_feedback"];
  StateFeedback f;
  f.state = fourNumbers(law["state"], "state");
  f.torque = finiteNumber(law["torque"], "torque");
  f.K = fourNumbers(law["K"], "K").transpose();
  const YAML::Node periodic = law["periodic"];
  if (!periodic || !periodic.IsScalar() || !YAML::convert<bool>::decode(periodic, f.periodic))
    throw std::invalid_argument("state_feedback.periodic must be true or false");
  return f;
}

StateFeedback readStateFeedbackFile(const std::string& path) {
  std::ifstream in = openInputFile(path, "gain file", kMaxConfigBytes);
  const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  try {
    return stateFeedbackFromYaml(text);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("gain file '" + path + "': " + e.what());
  }
}

}  // namespace kane_sim
