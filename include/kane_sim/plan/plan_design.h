// `design plan`'s work, ROS-free: the collocation's optimal move (plan/collocation.h) sampled
// on the controller's grid, the LQR at the goal, and the time-varying LQR gains along the move
// (design/tvlqr.h) — the plan a tracking controller follows (design/plan.h).
#ifndef KANE_SIM_PLAN_PLAN_DESIGN_H
#define KANE_SIM_PLAN_PLAN_DESIGN_H

#include <functional>
#include <string>

#include "kane_sim/design/lqr.h"
#include "kane_sim/design/plan.h"
#include "kane_sim/plan/collocation.h"

namespace kane_sim {

struct PlanDesign {
  CollocationSolution solution;
  LqrDesign goal_lqr;  // the law that holds the goal, the plan's last row
  Plan plan;
};

// The goal must be the crank held at rest (equilibriumAt(model, goal q1)); rows every
// 1 / row_rate seconds: the state of the collocation's interpolant at each row's time and the
// torque at the middle of the row's step (what a command held over the step should be, to
// second order; between the collocation's points it can pass the problem's torque limit a little
// where it turns at the bound, never the drive's), then one row at the goal with its holding
// torque, held from then on. The gains come from the Riccati equation stepped at most 1 ms at a
// time (rows further apart get the gain of their instant on that finer grid).
// Why rows every 1 / row_rate seconds cannot be the plan of `problem`, or "": a rate outside
// [1, 1e6] Hz, or more rows than a plan may have (kMaxPlanRows) over the longest the move may
// take. What designPlan checks first, for a tool to refuse before anything runs.
std::string planRateProblem(const CollocationProblem& problem, double row_rate);

PlanDesign designPlan(const MechanismModel& model, const CollocationProblem& problem,
                      double row_rate, const LqrWeights& weights,
                      const std::function<void(const CollocationProgress&)>& progress,
                      const std::function<bool()>& stop);

}  // namespace kane_sim

#endif  // KANE_SIM_PLAN_PLAN_DESIGN_H
