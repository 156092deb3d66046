// Optimal moves by direct collocation, as Drake's DirectCollocation and opty pose them: the motion
// from a start state to a goal state over N intervals, each a Hermite-Simpson segment (the state
// cubic, the torque quadratic), its defects
//
//   x_m - (x_a + x_b)/2 - h/8 (f_a - f_b) = 0,   x_b - x_a - h/6 (f_a + 4 f_m + f_b) = 0
//
// constraints of a nonlinear program that IPOPT solves (its C++ TNLP interface), f = x' the
// generated equations and their Jacobian the generated exact derivatives (every load; the motor
// line chained in). Minimum effort (the integral of M_m^2, the duration fixed) or minimum time;
// |M_m| <= the torque limit, slider 4's travel and the sliders' gap as bounds and constraints.
// ROS-free; the only part of the package that needs IPOPT.
#ifndef KANE_SIM_PLAN_COLLOCATION_H
#define KANE_SIM_PLAN_COLLOCATION_H

#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "kane_sim/model/mechanism_model.h"
#include "kane_sim/model/state.h"

namespace kane_sim {

// No plan: the problem is refused, or IPOPT did not solve it (its status in words).
class PlanningError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class PlanObjective { kEffort, kTime };

struct CollocationProblem {
  State start;
  State goal;
  PlanObjective objective = PlanObjective::kEffort;
  double duration = 3.0;                 // [s] fixed (effort); the first guess (time)
  double max_duration = 0.0;             // [s] time: the longest allowed (0: 10 x duration)
  int intervals = 100;                   // N
  double torque_limit = 0.0;             // [N m] |M_m| bound (> 0)
  std::optional<double> q2_min, q2_max;  // [m] slider 4's travel
  std::optional<double> gap;             // [m] x_C - x_B >= gap along the whole move
  int max_iterations = 3000;
};

// Checks what IPOPT would be handed: PlanningError naming the field and the value.
void checkCollocationProblem(const CollocationProblem& problem);

// One IPOPT iteration, for a progress line.
struct CollocationProgress {
  int iteration = 0;
  double objective = 0.0;
  double infeasibility = 0.0;  // the largest defect or bound violation
  int swings = 0;              // the first guess's swings (0, 1, 2, ...: tried in turn)
};

struct CollocationSolution {
  std::vector<double> time;           // 2N + 1 points: knots (even) and midpoints (odd)
  std::vector<Eigen::Vector4d> x;     // (q1, q2, u1, u2) at each point
  std::vector<double> torque;         // M_m at each point
  std::vector<Eigen::Vector4d> rate;  // x' at each point
  double duration = 0.0;
  double objective = 0.0;   // integral of M_m^2 [N^2 m^2 s] (effort) or the duration [s] (time)
  double max_defect = 0.0;  // the largest |defect| at the solution
  int iterations = 0;
  int guess_swings = 0;  // the first guess IPOPT solved from (its swings)
  std::string status;    // IPOPT's, in words

  // The Hermite-Simpson interpolants: the state (cubic on each interval) and the torque
  // (quadratic); t clamped to [0, duration].
  Eigen::Vector4d stateAt(double t) const;
  double torqueAt(double t) const;
};

// Solves the problem; `progress` is called every iteration (may be empty); `stop` asked every
// iteration (Ctrl-C: true stops IPOPT, PlanningError "stopped"). Throws PlanningError when
// IPOPT does not report a solution, with its status and where it stopped.
CollocationSolution solveCollocation(
    const MechanismModel& model, const CollocationProblem& problem,
    const std::function<void(const CollocationProgress&)>& progress,
    const std::function<bool()>& stop);

}  // namespace kane_sim

#endif  // KANE_SIM_PLAN_COLLOCATION_H
