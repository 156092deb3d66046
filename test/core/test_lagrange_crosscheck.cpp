// An independent derivation: Lagrange's equations from T(q, u) and V(q), built only from the
// body positions of the mechanism (written here again on purpose, from doc/theory/mechanism.md)
// and numeric differentiation. Nothing in this file calls the Kane assembly except to compare.
//
//   M(q) u' = Q - dV/dq + dT/dq - d/dt(dT/du)|_(u' = 0)
//
// Tolerances: central differences with h = 1e-5 have truncation error ~h^2 = 1e-10 and
// rounding error ~1e-16/h = 1e-11 relative; two nested differences stay below ~1e-8. A wrong
// term in the model (a sign, a factor, a missing body) is O(1) relative, so 1e-6 separates them.
#include <cmath>
#include <functional>
#include <random>

#include <gtest/gtest.h>

#include "kane_sim/model/generated_mechanism.h"
#include "kane_sim/model/mechanism_model.h"
#include "test_helpers.h"

namespace kane_sim {
namespace {

using Vec2 = Eigen::Vector2d;

class LagrangeModel {
 public:
  explicit LagrangeModel(const Config& c) : p_(c.mechanism), x0_(c.initial_state) {}

  // T(q, u): velocities by central differences of positions along u, ω from the rod angles.
  double kinetic(const Vec2& q, const Vec2& u) const {
    const double h = 1e-5;
    const Points plus = points(q + h * u), minus = points(q - h * u);
    double t = 0;
    const double masses[4] = {p_.rod_mass, p_.rod_mass, p_.slider3_mass, p_.slider4_mass};
    for (int i = 0; i < 4; ++i) {
      const Vec2 v = (plus.center[i] - minus.center[i]) / (2 * h);
      t += 0.5 * masses[i] * v.squaredNorm();
    }
    for (int rod = 0; rod < 2; ++rod) {
      const double omega = (plus.rod_angle[rod] - minus.rod_angle[rod]) / (2 * h);
      t += 0.5 * p_.rod_inertia * omega * omega;
    }
    return t;
  }

  // V(q): gravity along +x (potential -m g x) and the spring, unstretched at (q10, q20).
  double potential(const Vec2& q) const {
    const Points now = points(q), rest = points(Vec2(x0_.q1, x0_.q2));
    const double masses[4] = {p_.rod_mass, p_.rod_mass, p_.slider3_mass, p_.slider4_mass};
    double v = 0;
    for (int i = 0; i < 4; ++i) v -= masses[i] * p_.gravity * now.center[i].x();
    const double e =
        (now.center[2].x() - now.center[3].x()) - (rest.center[2].x() - rest.center[3].x());
    return v + 0.5 * p_.spring_stiffness * e * e;
  }

  Eigen::Matrix2d massMatrix(const Vec2& q) const {
    // T is quadratic in u, so this second difference with unit steps is exact.
    Eigen::Matrix2d m;
    for (int r = 0; r < 2; ++r)
      for (int s = 0; s < 2; ++s) {
        const Vec2 er = Vec2::Unit(r), es = Vec2::Unit(s);
        m(r, s) = (kinetic(q, er + es) - kinetic(q, er - es) - kinetic(q, -er + es) +
                   kinetic(q, -er - es)) /
                  4.0;
      }
    return m;
  }

  Vec2 accelerations(const Vec2& q, const Vec2& u, double torque) const {
    const double h = 1e-5;
    Vec2 rhs(torque, 0.0);  // Q: M_m does work only through q1
    for (int r = 0; r < 2; ++r) {
      const Vec2 dq = h * Vec2::Unit(r);
      rhs[r] -= (potential(q + dq) - potential(q - dq)) / (2 * h);
      rhs[r] += (kinetic(q + dq, u) - kinetic(q - dq, u)) / (2 * h);
      // d/dt (dT/du_r) at u' = 0 is the derivative of dT/du_r along q' = u.
      auto dT_du = [&](const Vec2& qq) {
        const Vec2 e = Vec2::Unit(r);
        return (kinetic(qq, u + e) - kinetic(qq, u - e)) / 2.0;  // exact: T quadratic in u
      };
      rhs[r] -= (dT_du(q + h * u) - dT_du(q - h * u)) / (2 * h);
    }
    return massMatrix(q).ldlt().solve(rhs);
  }

 private:
  struct Points {
    Vec2 center[4];  // C1, C2, B, C
    double rod_angle[2];
  };
  Points points(const Vec2& q) const {
    const double L = p_.rod_half_length;
    const Vec2 a(2 * L * std::cos(q[0]), 2 * L * std::sin(q[0]));
    const Vec2 b(4 * L * std::cos(q[0]), 0.0);
    Points pts;
    pts.center[0] = a / 2;        // middle of OA
    pts.center[1] = (a + b) / 2;  // middle of AB
    pts.center[2] = b;
    pts.center[3] = Vec2(q[1], 0.0);
    pts.rod_angle[0] = std::atan2(a.y(), a.x());
    pts.rod_angle[1] = std::atan2(b.y() - a.y(), b.x() - a.x());
    return pts;
  }

  MechanismParameters p_;
  State x0_;
};

class LagrangeCrossCheck : public ::testing::TestWithParam<const char*> {};

TEST_P(LagrangeCrossCheck, MassMatrixAndAccelerationsAgree) {
  const Config config = loadConfigFile(test::configPath(GetParam())).config;
  const MechanismModel kane = mechanismModel(config);
  const LagrangeModel lagrange(config);
  std::mt19937 rng(7);
  // The rod angles come from atan2, which jumps by 2π at q1 = ±π: keep |q1| < 2.8 so that no
  // difference quotient straddles the cut.
  std::uniform_real_distribution<double> angle(-2.8, 2.8), position(0.2, 1.8), speed(-15, 15),
      torque(-40, 40);
  for (int i = 0; i < 300; ++i) {
    const State x{angle(rng), position(rng), speed(rng), speed(rng)};
    const double tau = torque(rng);
    const Vec2 q(x.q1, x.q2), u(x.u1, x.u2);

    const auto forces = kane.equations(x, tau);
    const Eigen::Matrix2d m_lagrange = lagrange.massMatrix(q);
    EXPECT_LT((forces.mass_matrix - m_lagrange).norm(), 1e-8 * m_lagrange.norm())
        << "q1 = " << x.q1;

    const Vec2 kane_accel = forces.solveAccelerations();
    const Vec2 lagrange_accel = lagrange.accelerations(q, u, tau);
    EXPECT_LT((kane_accel - lagrange_accel).norm(), 1e-6 * (1 + lagrange_accel.norm()))
        << "q1 = " << x.q1 << " u1 = " << x.u1 << " kane " << kane_accel.transpose() << " lagrange "
        << lagrange_accel.transpose();
    // The generated equations (the integrators' default) against the same independent model.
    const OdeState generated = GeneratedMechanism(kane).stateDerivative(x, tau);
    EXPECT_LT((Vec2(generated[2], generated[3]) - lagrange_accel).norm(),
              1e-6 * (1 + lagrange_accel.norm()))
        << "generated, q1 = " << x.q1 << " u1 = " << x.u1;
  }
}

// Also the total energy: T + V from the independent model equals the model's energy terms
// (V's zero is the level of O in both).
TEST_P(LagrangeCrossCheck, EnergyAgrees) {
  const Config config = loadConfigFile(test::configPath(GetParam())).config;
  const MechanismModel kane = mechanismModel(config);
  const LagrangeModel lagrange(config);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(-2.8, 2.8), position(0.2, 1.8), speed(-15, 15);
  for (int i = 0; i < 100; ++i) {
    const State x{angle(rng), position(rng), speed(rng), speed(rng)};
    const EnergyTerms e = kane.energy(x);
    const Vec2 q(x.q1, x.q2), u(x.u1, x.u2);
    EXPECT_NEAR(e.kinetic, lagrange.kinetic(q, u), 1e-7 * (1 + e.kinetic));
    EXPECT_NEAR(e.potentialTotal(), lagrange.potential(q), 1e-10);
  }
}

INSTANTIATE_TEST_SUITE_P(BothInertias, LagrangeCrossCheck,
                         ::testing::Values("mechanism.yaml", "textbook.yaml"));

}  // namespace
}  // namespace kane_sim
