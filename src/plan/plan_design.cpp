#include "kane_sim/plan/plan_design.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "kane_sim/design/tvlqr.h"
#include "kane_sim/format_number.h"

namespace kane_sim {

PlanDesign designPlan(const MechanismModel& model, const CollocationProblem& problem,
                      double row_rate, const LqrWeights& weights,
                      const std::function<void(const CollocationProgress&)>& progress,
                      const std::function<bool()>& stop) {
  if (!(row_rate >= 1.0 && row_rate <= 1e6))
    throw PlanningError("the plan's row rate must be in [1, 1e6] Hz, got " +
                        formatNumber(row_rate));
  PlanDesign d;
  // The goal's law first: a goal that cannot be held is refused before IPOPT runs.
  d.goal_lqr = designLqr(model, problem.goal.q1, weights);
  const State& held = d.goal_lqr.equilibrium.state;
  const State& goal = problem.goal;
  if (std::abs(goal.q2 - held.q2) > 1e-9 || goal.u1 != 0.0 || goal.u2 != 0.0)
    throw PlanningError("the goal must be the crank held at rest at q1 = " + formatNumber(goal.q1) +
                        " rad (slider 4 at q2 = " + formatNumber(held.q2) + " m, no speed)");
  d.solution = solveCollocation(model, problem, progress, stop);
  const double step = 1.0 / row_rate;
  const double duration = d.solution.duration;
  const long rows = static_cast<long>(std::floor(duration / step + 1e-9));
  d.plan.step = step;
  d.plan.periodic = model.parameters().crank_spring_stiffness == 0.0;
  for (long k = 0; k <= rows; ++k) {
    PlanPoint p;
    p.t = static_cast<double>(k) * step;
    p.x = d.solution.stateAt(p.t);
    // The quadratic through the collocation's torques is the motion's torque, and where it
    // turns at the bound it overshoots it between the points a little (~0.6 % at the swing-up's
    // 8 N m): kept, as planned, and clamped only where the drive would clamp it.
    const double drive_limit = model.parameters().motor.torque_limit;
    p.torque = std::clamp(d.solution.torqueAt(std::min(p.t + step / 2, duration)), -drive_limit,
                          drive_limit);
    d.plan.points.push_back(p);
  }
  PlanPoint end;
  end.t = static_cast<double>(rows + 1) * step;
  end.x << held.q1, held.q2, 0.0, 0.0;
  end.torque = d.goal_lqr.equilibrium.torque;
  d.plan.points.push_back(end);
  fillTimeVaryingLqr(model, weights, d.goal_lqr.P, &d.plan);
  return d;
}

}  // namespace kane_sim
