#include "kane_sim/plan/plan_design.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "kane_sim/design/plan_file.h"
#include "kane_sim/design/tvlqr.h"
#include "kane_sim/format_number.h"

namespace kane_sim {

std::string planRateProblem(const CollocationProblem& problem, double row_rate) {
  if (!(row_rate >= 1.0 && row_rate <= 1e6))
    return "the plan's row rate must be in [1, 1e6] Hz, got " + formatNumber(row_rate);
  const double longest = problem.objective == PlanObjective::kEffort ? problem.duration
                         : problem.max_duration > 0                  ? problem.max_duration
                                                                     : 10 * problem.duration;
  if (longest * row_rate > static_cast<double>(kMaxPlanRows) - 2)
    return "rows at " + formatNumber(row_rate) + " Hz over " + formatNumber(longest) +
           " s are more than the " + std::to_string(kMaxPlanRows) +
           " a plan may have (its file within 64 MiB): lower the rate";
  return "";
}

namespace {

// The plan's rows on a grid of at most 1 ms (the rows' step divided evenly), for the Riccati
// equation's steps: the state of the collocation's interpolant and its torque at each instant.
Plan fineGrid(const CollocationSolution& solution, const Plan& plan) {
  const int per_row = static_cast<int>(std::ceil(plan.step / 1e-3 - 1e-9));
  Plan fine;
  fine.step = plan.step / per_row;
  fine.periodic = plan.periodic;
  const size_t rows = plan.points.size();
  for (size_t k = 0; k + 1 < rows; ++k)
    for (int j = 0; j < per_row; ++j) {
      PlanPoint p;
      p.t = plan.points[k].t + j * fine.step;
      p.x = j == 0 ? plan.points[k].x : solution.stateAt(p.t);
      p.torque = j == 0 ? plan.points[k].torque
                        : solution.torqueAt(std::min(p.t + fine.step / 2, solution.duration));
      fine.points.push_back(p);
    }
  fine.points.push_back(plan.points.back());
  return fine;
}

}  // namespace

PlanDesign designPlan(const MechanismModel& model, const CollocationProblem& problem,
                      double row_rate, const LqrWeights& weights,
                      const std::function<void(const CollocationProgress&)>& progress,
                      const std::function<bool()>& stop) {
  checkCollocationProblem(problem);
  const std::string rate_problem = planRateProblem(problem, row_rate);
  if (!rate_problem.empty()) throw PlanningError(rate_problem);
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
  if (d.plan.step <= 1e-3 + 1e-12) {
    fillTimeVaryingLqr(model, weights, d.goal_lqr.P, &d.plan);
  } else {
    Plan fine = fineGrid(d.solution, d.plan);
    fillTimeVaryingLqr(model, weights, d.goal_lqr.P, &fine);
    const size_t per_row = (fine.points.size() - 1) / (d.plan.points.size() - 1);
    for (size_t k = 0; k < d.plan.points.size(); ++k)
      d.plan.points[k].K = fine.points[k * per_row].K;
  }
  return d;
}

}  // namespace kane_sim
