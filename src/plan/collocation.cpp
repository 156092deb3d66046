#include "kane_sim/plan/collocation.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <IpIpoptApplication.hpp>
#include <IpTNLP.hpp>

#include "kane_sim/analysis/equilibria.h"
#include "kane_sim/format_number.h"
#include "kane_sim/model/generated_mechanism.h"

namespace kane_sim {
namespace {

using Ipopt::Index;
using Ipopt::Number;

constexpr int kPointVariables = 5;  // q1, q2, u1, u2, M_m
constexpr double kInfinity = 1e20;
constexpr int kMostSwings = 4;           // first guesses with 0 to this many swings
constexpr int kIterationsPerGuess = 60;  // each guess's share (the last gets what is left)
constexpr int kBlockEntries =
    kPointVariables * (kPointVariables + 1) /
    2;  // a lower triangle  // IPOPT's "no bound" (nlp_upper_bound_inf is 1e19)

const char* statusInWords(Ipopt::SolverReturn status) {
  switch (status) {
    case Ipopt::SUCCESS:
      return "solved (optimal to the tolerances)";
    case Ipopt::STOP_AT_ACCEPTABLE_POINT:
      return "solved to IPOPT's acceptable tolerances";
    case Ipopt::MAXITER_EXCEEDED:
      return "the iteration limit was reached before a solution";
    case Ipopt::CPUTIME_EXCEEDED:
      return "the time limit was reached before a solution";
    case Ipopt::STOP_AT_TINY_STEP:
      return "IPOPT's steps became too small to make progress";
    case Ipopt::LOCAL_INFEASIBILITY:
      return "locally infeasible: no motion near the guess meets the equations, the torque "
             "limit and the bounds (the goal out of reach in this time with this torque?)";
    case Ipopt::USER_REQUESTED_STOP:
      return "stopped at the user's request (Ctrl-C)";
    case Ipopt::FEASIBLE_POINT_FOUND:
      return "a feasible point, not an optimum";
    case Ipopt::DIVERGING_ITERATES:
      return "the iterates diverged";
    case Ipopt::RESTORATION_FAILURE:
      return "IPOPT's feasibility restoration failed (the problem is likely infeasible)";
    case Ipopt::ERROR_IN_STEP_COMPUTATION:
      return "an error in IPOPT's step computation";
    case Ipopt::INVALID_NUMBER_DETECTED:
      return "a non-finite number in the equations";
    case Ipopt::TOO_FEW_DEGREES_OF_FREEDOM:
      return "too few degrees of freedom (more constraints than unknowns)";
    case Ipopt::INVALID_OPTION:
      return "an invalid IPOPT option";
    case Ipopt::OUT_OF_MEMORY:
      return "out of memory";
    default:
      return "an internal IPOPT error";
  }
}

// The nonlinear program: variables z = [x_0, M_0, x_1/2, M_1/2, x_1, M_1, ..., x_N, M_N (, T)],
// constraints per interval i: 4 midpoint defects, 4 Simpson defects; then one gap row per point.
class HermiteSimpsonNlp : public Ipopt::TNLP {
 public:
  HermiteSimpsonNlp(const MechanismModel& model, const CollocationProblem& problem,
                    const std::function<void(const CollocationProgress&)>& progress,
                    const std::function<bool()>& stop)
      : mechanism_(model),
        half_length_(model.parameters().rod_half_length),
        p_(problem),
        points_(2 * problem.intervals + 1),
        free_time_(problem.objective == PlanObjective::kTime),
        progress_(progress),
        stop_(stop),
        rate_(static_cast<size_t>(points_)),
        jacobian_(static_cast<size_t>(points_)) {}

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag,
                    IndexStyleEnum& index_style) override {
    n = variableCount();
    m = 8 * p_.intervals + (p_.gap ? points_ : 0);
    nnz_jac_g = 8 * p_.intervals * (3 * kPointVariables + (free_time_ ? 1 : 0)) +
                (p_.gap ? 2 * points_ : 0);
    nnz_h_lag = kBlockEntries * points_ + (free_time_ ? kPointVariables * points_ : 0);
    index_style = TNLP::C_STYLE;
    return true;
  }

  bool get_bounds_info(Index n, Number* x_l, Number* x_u, Index m, Number* g_l,
                       Number* g_u) override {
    for (Index i = 0; i < n; ++i) {
      x_l[i] = -kInfinity;
      x_u[i] = kInfinity;
    }
    for (int k = 0; k < points_; ++k) {
      Number* lo = x_l + kPointVariables * k;
      Number* hi = x_u + kPointVariables * k;
      if (p_.q2_min) lo[1] = *p_.q2_min;
      if (p_.q2_max) hi[1] = *p_.q2_max;
      lo[4] = -p_.torque_limit;
      hi[4] = p_.torque_limit;
    }
    const double start[4] = {p_.start.q1, p_.start.q2, p_.start.u1, p_.start.u2};
    const double goal[4] = {p_.goal.q1, p_.goal.q2, p_.goal.u1, p_.goal.u2};
    const int last = kPointVariables * (points_ - 1);
    for (int c = 0; c < 4; ++c) {
      x_l[c] = x_u[c] = start[c];
      x_l[last + c] = x_u[last + c] = goal[c];
    }
    if (free_time_) {
      x_l[n - 1] = p_.duration / 100;
      x_u[n - 1] = p_.max_duration > 0 ? p_.max_duration : 10 * p_.duration;
    }
    for (Index j = 0; j < m; ++j) {
      g_l[j] = 0.0;
      g_u[j] = j < 8 * p_.intervals ? 0.0 : kInfinity;
    }
    if (p_.gap)
      for (Index j = 8 * p_.intervals; j < m; ++j) g_l[j] = *p_.gap;
    return true;
  }

  // The first guess: a given one (setGuess), else the crank from start to goal along
  //   q1(s) = q1_a + (q1_b - q1_a) blend(s),  s = t / T,
  // blend a half cosine (rest to rest) for 0 swings; for n swings of growing amplitude (a crank
  // that must pump energy) the half cosine plus D (s cos(pi n (1 - s)) - blend), D = q1_b - q1_a
  // or, for a move shorter than 1 rad, 1 rad its way (so that swings are tried there too);
  // slider 4 blended by the half cosine; the speeds those curves have; no torque.
  bool get_starting_point(Index n, bool, Number* z, bool, Number*, Number*, Index, bool,
                          Number*) override {
    if (static_cast<Index>(guess_.size()) == n) {
      std::copy(guess_.begin(), guess_.end(), z);
      return true;
    }
    const Eigen::Vector2d a(p_.start.q1, p_.start.q2);
    const Eigen::Vector2d b(p_.goal.q1, p_.goal.q2);
    const double T = p_.duration, pi_n = M_PI * swings_;
    const double span = b[0] - a[0];
    const double swing = std::abs(span) >= 1.0 ? span : std::copysign(1.0, span);
    for (int k = 0; k < points_; ++k) {
      const double s = static_cast<double>(k) / (points_ - 1);
      const double smooth = (1 - std::cos(M_PI * s)) / 2;
      const double smooth_rate = M_PI / 2 * std::sin(M_PI * s) / T;
      const double pumped = swings_ == 0 ? smooth : s * std::cos(pi_n * (1 - s));
      const double pumped_rate =
          swings_ == 0 ? smooth_rate
                       : (std::cos(pi_n * (1 - s)) + s * pi_n * std::sin(pi_n * (1 - s))) / T;
      const bool long_move = swing == span;
      Eigen::Vector4d x(
          a[0] + (long_move ? pumped * span : smooth * span + (pumped - smooth) * swing),
          a[1] + smooth * (b[1] - a[1]),
          long_move ? pumped_rate * span : smooth_rate * span + (pumped_rate - smooth_rate) * swing,
          smooth_rate * (b[1] - a[1]));
      if (k == 0) x << p_.start.q1, p_.start.q2, p_.start.u1, p_.start.u2;
      if (k == points_ - 1) x << p_.goal.q1, p_.goal.q2, p_.goal.u1, p_.goal.u2;
      for (int c = 0; c < 4; ++c) z[kPointVariables * k + c] = x[c];
      z[kPointVariables * k + 4] = 0.0;
    }
    if (free_time_) z[n - 1] = p_.duration;
    return true;
  }

  bool eval_f(Index n, const Number* z, bool, Number& value) override {
    value = free_time_ ? z[n - 1] : effort(z, nullptr);
    return true;
  }

  bool eval_grad_f(Index n, const Number* z, bool, Number* grad) override {
    std::fill(grad, grad + n, 0.0);
    if (free_time_)
      grad[n - 1] = 1.0;
    else
      effort(z, grad);
    return true;
  }

  bool eval_g(Index n, const Number* z, bool new_x, Index, Number* g) override {
    evaluateAt(n, z, new_x);
    const double h = duration(n, z) / p_.intervals;
    for (int i = 0; i < p_.intervals; ++i) {
      const int a = 2 * i, m = a + 1, b = a + 2;
      for (int c = 0; c < 4; ++c) {
        const double xa = z[kPointVariables * a + c], xm = z[kPointVariables * m + c],
                     xb = z[kPointVariables * b + c];
        const double fa = rate_[a][c], fm = rate_[m][c], fb = rate_[b][c];
        g[8 * i + c] = xm - (xa + xb) / 2 - h / 8 * (fa - fb);
        g[8 * i + 4 + c] = xb - xa - h / 6 * (fa + 4 * fm + fb);
      }
    }
    if (p_.gap)
      for (int k = 0; k < points_; ++k)
        g[8 * p_.intervals + k] =
            z[kPointVariables * k + 1] - 4 * half_length_ * std::cos(z[kPointVariables * k]);
    return allFinite(g, 8 * p_.intervals);
  }

  bool eval_jac_g(Index n, const Number* z, bool new_x, Index, Index, Index* rows, Index* cols,
                  Number* values) override {
    if (values == nullptr) {
      structure(n, rows, cols);
      return true;
    }
    evaluateAt(n, z, new_x);
    const double h = duration(n, z) / p_.intervals;
    const double per_time = 1.0 / p_.intervals;  // dh/dT
    Index e = 0;
    for (int i = 0; i < p_.intervals; ++i) {
      const int a = 2 * i, m = a + 1, b = a + 2;
      // Midpoint defects, then Simpson's, each row over (z_a, z_m, z_b) and T.
      for (int c = 0; c < 4; ++c) {
        for (int k = 0; k < kPointVariables; ++k) {
          const double identity = k == c ? 1.0 : 0.0;
          values[e++] = -identity / 2 - h / 8 * jacobian_[a](c, k);
          values[e++] = k < 4 ? identity : 0.0;
          values[e++] = -identity / 2 + h / 8 * jacobian_[b](c, k);
        }
        if (free_time_) values[e++] = -per_time / 8 * (rate_[a][c] - rate_[b][c]);
      }
      for (int c = 0; c < 4; ++c) {
        for (int k = 0; k < kPointVariables; ++k) {
          const double identity = k == c ? 1.0 : 0.0;
          values[e++] = -identity - h / 6 * jacobian_[a](c, k);
          values[e++] = -4 * h / 6 * jacobian_[m](c, k);
          values[e++] = identity - h / 6 * jacobian_[b](c, k);
        }
        if (free_time_) values[e++] = -per_time / 6 * (rate_[a][c] + 4 * rate_[m][c] + rate_[b][c]);
      }
    }
    if (p_.gap)
      for (int k = 0; k < points_; ++k) {
        values[e++] = 4 * half_length_ * std::sin(z[kPointVariables * k]);
        values[e++] = 1.0;
      }
    return allFinite(values, e);
  }

  // The Lagrangian's Hessian: per point, the second derivatives of u' (the generated exact
  // Jacobian differenced centrally: 10 evaluations) weighted by the multipliers of the defects
  // that use that point; the effort's diagonal; with free time, the cross terms of T (h = T/N
  // multiplies every rate); the gap's cos. Lower triangles, point by point, then T's row.
  bool eval_h(Index n, const Number* z, bool, Number obj_factor, Index m, const Number* lambda,
              bool, Index, Index* rows, Index* cols, Number* values) override {
    if (values == nullptr) {
      Index e = 0;
      for (int k = 0; k < points_; ++k)
        for (int r = 0; r < kPointVariables; ++r)
          for (int c = 0; c <= r; ++c) {
            rows[e] = kPointVariables * k + r;
            cols[e++] = kPointVariables * k + c;
          }
      if (free_time_)
        for (int k = 0; k < points_; ++k)
          for (int c = 0; c < kPointVariables; ++c) {
            rows[e] = n - 1;
            cols[e++] = kPointVariables * k + c;
          }
      return true;
    }
    evaluateAt(n, z, true);
    // w[p][c]: the sum over the defects using f_c at point p of lambda x its coefficient / h.
    std::vector<Eigen::Vector4d> w(static_cast<size_t>(points_), Eigen::Vector4d::Zero());
    for (int i = 0; i < p_.intervals; ++i) {
      const int a = 2 * i, mid = a + 1, b = a + 2;
      for (int c = 0; c < 4; ++c) {
        const double l_mid = lambda[8 * i + c], l_simpson = lambda[8 * i + 4 + c];
        w[a][c] += -l_mid / 8 - l_simpson / 6;
        w[mid][c] += -4 * l_simpson / 6;
        w[b][c] += l_mid / 8 - l_simpson / 6;
      }
    }
    const double h = duration(n, z) / p_.intervals;
    Index e = 0;
    for (int k = 0; k < points_; ++k) {
      const Number* v = z + kPointVariables * k;
      Eigen::Matrix<double, 5, 5> H = Eigen::Matrix<double, 5, 5>::Zero();
      for (int var = 0; var < kPointVariables; ++var) {
        const double step = 1e-6 * std::max(1.0, std::abs(v[var]));
        Number plus[kPointVariables], minus[kPointVariables];
        std::copy(v, v + kPointVariables, plus);
        std::copy(v, v + kPointVariables, minus);
        plus[var] += step;
        minus[var] -= step;
        const Eigen::Matrix<double, 4, 5> d =
            (pointJacobian(plus) - pointJacobian(minus)) / (2 * step);
        // Only u1' and u2' (rows 2, 3) are nonlinear: q' = u has no curvature.
        H.col(var) = h * (w[k][2] * d.row(2) + w[k][3] * d.row(3)).transpose();
      }
      H = ((H + H.transpose()) / 2).eval();
      const int M = kPointVariables - 1;
      if (!free_time_) {
        const bool knot = k % 2 == 0;
        const int shared = (k == 0 || k == points_ - 1) ? 1 : 2;  // intervals using a knot
        H(M, M) += obj_factor * (knot ? shared * h / 3 : 4 * h / 3) / scale();
      }
      if (p_.gap) {
        const double l = lambda[8 * p_.intervals + k];
        H(0, 0) += l * 4 * half_length_ * std::cos(v[0]);
      }
      for (int r = 0; r < kPointVariables; ++r)
        for (int c = 0; c <= r; ++c) values[e++] = H(r, c);
    }
    if (free_time_)
      for (int k = 0; k < points_; ++k) {
        const Eigen::Matrix<double, 4, 5>& J = jacobian_[static_cast<size_t>(k)];
        const Eigen::Matrix<double, 1, 5> cross = w[k].transpose() * J / p_.intervals;
        for (int c = 0; c < kPointVariables; ++c) values[e++] = cross[c];
      }
    (void)m;
    return allFinite(values, e);
  }

  bool intermediate_callback(Ipopt::AlgorithmMode, Index iter, Number obj_value, Number inf_pr,
                             Number, Number, Number, Number, Number, Number, Index,
                             const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    iterations_ = iter;
    if (progress_) progress_({iter, obj_value, inf_pr, swings_});
    return !(stop_ && stop_());
  }

  void finalize_solution(Ipopt::SolverReturn status, Index n, const Number* z, const Number*,
                         const Number*, Index m, const Number* g, const Number*, Number obj_value,
                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    status_ = status;
    solution_z_.assign(z, z + n);
    solution_.status = statusInWords(status);
    solution_.iterations = iterations_;
    solution_.guess_swings = swings_;
    solution_.duration = duration(n, z);
    solution_.objective = free_time_ ? z[n - 1] : obj_value * scale();
    // The defects of the z returned (moved back within the bounds after IPOPT's last g).
    std::vector<Number> defects(static_cast<size_t>(m));
    evaluate(n, z);
    eval_g(n, z, false, m, defects.data());
    (void)g;
    solution_.max_defect = 0.0;
    for (Index j = 0; j < std::min<Index>(m, 8 * p_.intervals); ++j)
      solution_.max_defect = std::max(solution_.max_defect, std::abs(defects[j]));
    const double h = solution_.duration / p_.intervals;
    for (int k = 0; k < points_; ++k) {
      solution_.time.push_back(k * h / 2);
      solution_.x.emplace_back(z + kPointVariables * k);
      solution_.torque.push_back(z[kPointVariables * k + 4]);
      solution_.rate.push_back(rate_[static_cast<size_t>(k)]);
    }
  }

  // The first guess: a solution of a neighbouring problem (empty: the smooth curve below).
  void setGuess(std::vector<Number> z) { guess_ = std::move(z); }
  void setSwings(int swings) { swings_ = swings; }
  const std::vector<Number>& solutionVariables() const { return solution_z_; }
  Ipopt::SolverReturn status() const { return status_; }
  const CollocationSolution& solution() const { return solution_; }

 private:
  Index variableCount() const { return kPointVariables * points_ + (free_time_ ? 1 : 0); }
  double duration(Index n, const Number* z) const { return free_time_ ? z[n - 1] : p_.duration; }
  // The effort objective in units of the torque limit squared (IPOPT sees numbers near 1).
  double scale() const { return p_.torque_limit * p_.torque_limit; }

  // Simpson's rule on M_m^2 over every interval, divided by scale(); its gradient into `grad`.
  double effort(const Number* z, Number* grad) const {
    const double h = p_.duration / p_.intervals;
    double sum = 0.0;
    for (int i = 0; i < p_.intervals; ++i) {
      const int a = kPointVariables * (2 * i) + 4, m = a + kPointVariables, b = m + kPointVariables;
      sum += h / 6 * (z[a] * z[a] + 4 * z[m] * z[m] + z[b] * z[b]);
      if (grad) {
        grad[a] += h / 3 * z[a] / scale();
        grad[m] += 4 * h / 3 * z[m] / scale();
        grad[b] += h / 3 * z[b] / scale();
      }
    }
    return sum / scale();
  }

  Eigen::Matrix<double, 4, 5> pointJacobian(const Number* v) const {
    const auto l = mechanism_.linearization(State{v[0], v[1], v[2], v[3]}, v[4]);
    Eigen::Matrix<double, 4, 5> J;
    J << l.A, l.B;
    return J;
  }

  // x' and [A | B] at every point, once per iterate: kept for the z they were evaluated at (IPOPT
  // 3.11's derivative checker perturbs z without saying new_x, so z itself is compared).
  void evaluateAt(Index n, const Number* z, bool new_x) {
    if (!new_x && evaluated_ && std::equal(z, z + n, evaluated_at_.begin())) return;
    evaluate(n, z);
  }
  void evaluate(Index n, const Number* z) {
    evaluated_at_.assign(z, z + n);
    for (int k = 0; k < points_; ++k) {
      const Number* v = z + kPointVariables * k;
      const State x{v[0], v[1], v[2], v[3]};
      const OdeState d = mechanism_.stateDerivative(x, v[4]);
      rate_[k] << d[0], d[1], d[2], d[3];
      const auto l = mechanism_.linearization(x, v[4]);
      jacobian_[k].leftCols<4>() = l.A;
      jacobian_[k].col(4) = l.B;
    }
    evaluated_ = true;
  }

  void structure(Index n, Index* rows, Index* cols) const {
    Index e = 0;
    for (int i = 0; i < p_.intervals; ++i)
      for (int part = 0; part < 2; ++part)
        for (int c = 0; c < 4; ++c) {
          const Index row = 8 * i + 4 * part + c;
          for (int k = 0; k < kPointVariables; ++k)
            for (int point = 2 * i; point <= 2 * i + 2; ++point) {
              rows[e] = row;
              cols[e++] = kPointVariables * point + k;
            }
          if (free_time_) {
            rows[e] = row;
            cols[e++] = n - 1;
          }
        }
    if (p_.gap)
      for (int k = 0; k < points_; ++k) {
        rows[e] = 8 * p_.intervals + k;
        cols[e++] = kPointVariables * k;
        rows[e] = 8 * p_.intervals + k;
        cols[e++] = kPointVariables * k + 1;
      }
  }

  static bool allFinite(const Number* values, Index count) {
    for (Index i = 0; i < count; ++i)
      if (!std::isfinite(values[i])) return false;
    return true;
  }

  GeneratedMechanism mechanism_;
  double half_length_;
  CollocationProblem p_;
  int points_;
  bool free_time_;
  std::function<void(const CollocationProgress&)> progress_;
  std::function<bool()> stop_;
  std::vector<Eigen::Vector4d> rate_;
  std::vector<Eigen::Matrix<double, 4, 5>> jacobian_;
  bool evaluated_ = false;
  std::vector<Number> evaluated_at_;
  int iterations_ = 0;
  Ipopt::SolverReturn status_ = Ipopt::UNASSIGNED;
  CollocationSolution solution_;
  std::vector<Number> guess_, solution_z_;
  int swings_ = 0;
};

void requireFinite(double value, const std::string& name) {
  if (!std::isfinite(value))
    throw PlanningError(name + " must be finite, got " + formatNumber(value));
}

struct Attempt {
  bool solved = false;
  Ipopt::SolverReturn status = Ipopt::UNASSIGNED;
  CollocationSolution solution;
  std::vector<double> z;
};

Attempt solveOnce(const MechanismModel& model, const CollocationProblem& problem, int swings,
                  std::vector<double> guess,
                  const std::function<void(const CollocationProgress&)>& progress,
                  const std::function<bool()>& stop) {
  Ipopt::SmartPtr<HermiteSimpsonNlp> nlp = new HermiteSimpsonNlp(model, problem, progress, stop);
  nlp->setSwings(swings);
  nlp->setGuess(std::move(guess));
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetIntegerValue("print_level", 0);
  app->Options()->SetStringValue("sb", "yes");
  app->Options()->SetNumericValue("tol", 1e-8);
  app->Options()->SetNumericValue("constr_viol_tol", 1e-10);
  app->Options()->SetIntegerValue("max_iter", std::max(problem.max_iterations, 1));
  app->Options()->SetStringValue("mu_strategy", "adaptive");
  // IPOPT relaxes the bounds by this factor while it iterates and moves the solution back inside
  // them at the end: a torque on its bound moves by it, and the defects with it. Its default
  // (1e-8) would leave defects of ~1e-8; this leaves ~1e-12.
  app->Options()->SetNumericValue("bound_relax_factor", 1e-12);
  if (app->Initialize() != Ipopt::Solve_Succeeded)
    throw PlanningError("IPOPT could not be initialized");
  app->OptimizeTNLP(nlp);
  Attempt a;
  a.status = nlp->status();
  a.solved = a.status == Ipopt::SUCCESS || a.status == Ipopt::STOP_AT_ACCEPTABLE_POINT;
  a.solution = nlp->solution();
  a.z = nlp->solutionVariables();
  return a;
}

CollocationSolution finish(Attempt& attempt, int iterations, const std::string& note = "") {
  attempt.solution.iterations = iterations;
  if (!attempt.solved)
    throw PlanningError("IPOPT: " + attempt.solution.status + " after " +
                        std::to_string(iterations) + " iterations (largest defect " +
                        formatNumber(attempt.solution.max_defect) + ")" + note);
  return attempt.solution;
}

}  // namespace

void checkCollocationProblem(const CollocationProblem& p) {
  const char* names[] = {"q1", "q2", "u1", "u2"};
  const double start[] = {p.start.q1, p.start.q2, p.start.u1, p.start.u2};
  const double goal[] = {p.goal.q1, p.goal.q2, p.goal.u1, p.goal.u2};
  for (int c = 0; c < 4; ++c) {
    requireFinite(start[c], std::string("the start's ") + names[c]);
    requireFinite(goal[c], std::string("the goal's ") + names[c]);
  }
  if (!(p.duration > 0.0 && p.duration <= 3600.0))
    throw PlanningError("the duration must be in (0, 3600] s, got " + formatNumber(p.duration));
  if (!(p.max_duration == 0.0 || (p.max_duration >= p.duration && p.max_duration <= 36000.0)))
    throw PlanningError("the longest duration must be in [duration, 36000] s, got " +
                        formatNumber(p.max_duration));
  if (p.intervals < 2 || p.intervals > 20000)
    throw PlanningError("the intervals must be in [2, 20000], got " + std::to_string(p.intervals));
  if (!(p.torque_limit >= 1e-6 && std::isfinite(p.torque_limit)))
    throw PlanningError("the torque limit must be finite and >= 1e-06 N m, got " +
                        formatNumber(p.torque_limit));
  if (p.q2_min) requireFinite(*p.q2_min, "slider 4's lowest q2");
  if (p.q2_max) requireFinite(*p.q2_max, "slider 4's highest q2");
  if (p.q2_min && p.q2_max && !(*p.q2_min < *p.q2_max))
    throw PlanningError("slider 4's travel [" + formatNumber(*p.q2_min) + ", " +
                        formatNumber(*p.q2_max) + "] m is empty");
  for (const auto& [q2, what] : {std::pair{p.start.q2, "start"}, std::pair{p.goal.q2, "goal"}}) {
    if ((p.q2_min && q2 < *p.q2_min) || (p.q2_max && q2 > *p.q2_max))
      throw PlanningError(std::string("the ") + what + "'s q2 = " + formatNumber(q2) +
                          " m is outside slider 4's travel");
  }
  if (p.gap) {
    requireFinite(*p.gap, "the gap");
    if (*p.gap < 0) throw PlanningError("the gap must be >= 0 m, got " + formatNumber(*p.gap));
  }
  if (p.max_iterations < 1)
    throw PlanningError("the iteration limit must be >= 1, got " +
                        std::to_string(p.max_iterations));
}

CollocationSolution solveCollocation(
    const MechanismModel& model, const CollocationProblem& problem,
    const std::function<void(const CollocationProgress&)>& progress,
    const std::function<bool()>& stop) {
  checkCollocationProblem(problem);
  if (problem.gap) {
    const double L = model.parameters().rod_half_length;
    for (const auto& [x, what] :
         {std::pair{problem.start, "start"}, std::pair{problem.goal, "goal"}})
      if (x.q2 - 4 * L * std::cos(x.q1) < *problem.gap)
        throw PlanningError(std::string("the ") + what + " has the sliders " +
                            formatNumber(x.q2 - 4 * L * std::cos(x.q1)) +
                            " m apart, closer than the gap " + formatNumber(*problem.gap) + " m");
  }
  // A swing-up with a torque well below gravity's must pump, and IPOPT started from a smooth
  // curve finds no such motion. So first guesses with 0, 1, 2, ... swings, each given a share of
  // the iterations; the first that IPOPT solves is the plan (a local optimum: the guess picks
  // which).
  // Minimum time starts from the move of least effort in the duration guessed: IPOPT finds the
  // bang-bang structure from there, not from a curve.
  CollocationProblem effort = problem;
  effort.objective = PlanObjective::kEffort;
  int iterations = 0;
  Attempt attempt;
  for (int swings = 0; swings <= kMostSwings && iterations < problem.max_iterations; ++swings) {
    effort.max_iterations =
        std::min(problem.max_iterations - iterations,
                 swings == kMostSwings ? problem.max_iterations : kIterationsPerGuess);
    attempt = solveOnce(model, effort, swings, {}, progress, stop);
    iterations += attempt.solution.iterations;
    if (attempt.solved || attempt.status == Ipopt::USER_REQUESTED_STOP) break;
  }
  if (attempt.solved && problem.objective == PlanObjective::kTime) {
    const int swings = attempt.solution.guess_swings;
    std::vector<double> guess = attempt.z;
    guess.push_back(problem.duration);
    CollocationProblem fastest = problem;
    fastest.max_iterations = std::max(problem.max_iterations - iterations, 1);
    attempt = solveOnce(model, fastest, swings, guess, progress, stop);
    iterations += attempt.solution.iterations;
    attempt.solution.guess_swings = swings;
  }
  return finish(attempt, iterations,
                attempt.solved || attempt.status == Ipopt::USER_REQUESTED_STOP
                    ? ""
                    : " from first guesses of 0 to " + std::to_string(kMostSwings) +
                          " swings: allow more time (--duration) or more torque");
}

Eigen::Vector4d CollocationSolution::stateAt(double t) const {
  const int intervals = static_cast<int>(time.size() - 1) / 2;
  const double h = duration / intervals;
  const double clamped = std::clamp(t, 0.0, duration);
  const int i = std::min(static_cast<int>(clamped / h), intervals - 1);
  const double tau = clamped - i * h;
  const size_t a = 2 * i, m = a + 1, b = a + 2;
  // The cubic through x_a with slopes f_a, f_m, f_b at 0, h/2, h (Hermite-Simpson's).
  return x[a] + rate[a] * tau + (-3 * rate[a] + 4 * rate[m] - rate[b]) / (2 * h) * tau * tau +
         (2 * rate[a] - 4 * rate[m] + 2 * rate[b]) / (3 * h * h) * tau * tau * tau;
}

double CollocationSolution::torqueAt(double t) const {
  const int intervals = static_cast<int>(time.size() - 1) / 2;
  const double h = duration / intervals;
  const double clamped = std::clamp(t, 0.0, duration);
  const int i = std::min(static_cast<int>(clamped / h), intervals - 1);
  const double s = (clamped - i * h) / h;  // in [0, 1]
  const size_t a = 2 * i, m = a + 1, b = a + 2;
  // The quadratic through M_a, M_m, M_b at s = 0, 1/2, 1 (Lagrange).
  return torque[a] * 2 * (s - 0.5) * (s - 1) - torque[m] * 4 * s * (s - 1) +
         torque[b] * 2 * s * (s - 0.5);
}

}  // namespace kane_sim
