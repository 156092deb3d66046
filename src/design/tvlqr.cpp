#include "kane_sim/design/tvlqr.h"

#include <vector>

#include "kane_sim/design/riccati.h"
#include "kane_sim/model/generated_mechanism.h"

namespace kane_sim {
namespace {

struct Linear {
  Eigen::Matrix4d A;
  Eigen::Vector4d B;
};

// -P' (so P' backward in time): A' P + P A - P B R^-1 B' P + Q.
Eigen::Matrix4d riccatiRate(const Linear& l, const Eigen::Matrix4d& P, const LqrWeights& w) {
  const Eigen::RowVector4d BtP = l.B.transpose() * P;
  return l.A.transpose() * P + P * l.A - BtP.transpose() * BtP / w.R + w.Q;
}

}  // namespace

void fillTimeVaryingLqr(const MechanismModel& model, const LqrWeights& weights,
                        const Eigen::Matrix4d& P_final, Plan* plan) {
  checkRiccatiWeights(weights.Q, Eigen::MatrixXd::Constant(1, 1, weights.R));
  std::vector<PlanPoint>& points = plan->points;
  if (points.empty()) return;
  const GeneratedMechanism mechanism(model);
  std::vector<Linear> linear(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector4d& x = points[i].x;
    const auto l = mechanism.linearization(State{x[0], x[1], x[2], x[3]}, points[i].torque);
    linear[i] = {l.A, l.B};
  }
  Eigen::Matrix4d P = P_final;
  points.back().K = linear.back().B.transpose() * P / weights.R;
  for (size_t i = points.size() - 1; i > 0; --i) {
    // Backward from row i to row i - 1: s = T - t runs forward, dP/ds = riccatiRate.
    const double h = points[i].t - points[i - 1].t;
    const Linear& end = linear[i];
    const Linear& begin = linear[i - 1];
    const Linear middle{(end.A + begin.A) / 2, (end.B + begin.B) / 2};
    const Eigen::Matrix4d k1 = riccatiRate(end, P, weights);
    const Eigen::Matrix4d k2 = riccatiRate(middle, P + h / 2 * k1, weights);
    const Eigen::Matrix4d k3 = riccatiRate(middle, P + h / 2 * k2, weights);
    const Eigen::Matrix4d k4 = riccatiRate(begin, P + h * k3, weights);
    P += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    P = (P + P.transpose()).eval() / 2;
    if (!P.allFinite())
      throw RiccatiError("the Riccati equation along the plan blew up at t = " +
                         std::to_string(points[i - 1].t) + " s (weights far apart in scale?)");
    points[i - 1].K = begin.B.transpose() * P / weights.R;
  }
}

}  // namespace kane_sim
