// The textbook example's mechanism ("Kane equations - Example 1") written on the generic Kane
// method of kane/kane_method.h.
//
// Frame (0): origin O at the crank pivot, i vertical pointing down (gravity is +g i), j
// horizontal, k = i x j. Bodies in the textbook's numbering: 1 = rod OA, 2 = rod AB (both 2L
// long, mass m, rigid bodies), 3 = slider at B (M1), 4 = slider at C (M2) (both particles on the
// i axis). A massless spring k joins 3 and 4; it is unstretched when the sliders are
// `spring_rest_length` apart (the initial configuration (q10, q20) in the config).
#ifndef KANE_SIM_MODEL_MECHANISM_MODEL_H
#define KANE_SIM_MODEL_MECHANISM_MODEL_H

#include <array>
#include <cmath>
#include <optional>
#include <string>

#include <Eigen/Core>
#include <boost/container/static_vector.hpp>

#include "kane_sim/kane/kane_method.h"
#include "kane_sim/model/generated_equations.h"
#include "kane_sim/model/joint_names.h"
#include "kane_sim/model/mechanism_laws.h"
#include "kane_sim/model/slider_geometry.h"
#include "kane_sim/model/state.h"

namespace kane_sim {

enum Body { kRod1 = 0, kRod2 = 1, kSlider3 = 2, kSlider4 = 3, kNumBodies = 4 };

// Where everything is for given (q1, q2), in frame (0): the one source of positions for the
// dynamics, the energy, tf and markers.
struct MechanismGeometry {
  double rod_length = 0.0;                                // 2L [m]
  Eigen::Vector3d pivot_o = Eigen::Vector3d::Zero();      // O, the crank's ground pivot
  Eigen::Vector3d pin_a = Eigen::Vector3d::Zero();        // A = 2L (cos q1, sin q1)
  Eigen::Vector3d pin_b = Eigen::Vector3d::Zero();        // B = (4L cos q1, 0): slider 3
  Eigen::Vector3d point_c = Eigen::Vector3d::Zero();      // C = (q2, 0): slider 4
  Eigen::Vector3d rod1_center = Eigen::Vector3d::Zero();  // C1
  Eigen::Vector3d rod2_center = Eigen::Vector3d::Zero();  // C2
  double rod1_angle = 0.0;  // angle of rod 1 (O -> A) about k, from i:  q1
  double rod2_angle = 0.0;  // angle of rod 2 (A -> B) about k, from i: -q1

  // x_C - x_B [m]: > 0 while slider 4 is below slider 3.
  double sliderSeparation() const { return point_c.x() - pin_b.x(); }
};

MechanismGeometry mechanismGeometry(double rod_half_length, double q1, double q2);

// The four bodies at one instant (kinematics, eqs 1-4).
struct MechanismKinematics {
  MechanismGeometry geometry;
  kane::RigidBody<kNumSpeeds> rod1;    // body 1, OA: ω10 = u1 k
  kane::RigidBody<kNumSpeeds> rod2;    // body 2, AB: ω20 = -u1 k
  kane::Particle<kNumSpeeds> slider3;  // body 3 at B: v_B = -4 L u1 sin q1 i
  kane::Particle<kNumSpeeds> slider4;  // body 4 at C: v_C = u2 i
};

// The loads, one named list as SymPy's `kanes_equations(bodies, loads)` takes: each entry a force
// at a point or a torque on a frame, under the name of the quantity it belongs to. Several entries
// can share a name (gravity's four, the spring's pair, a damper's torque and its reaction): each
// name's power is their sum. The names, their kinds and, for the resistances (dampers, friction),
// their sites, laws and coefficients are one table, declared once in
// codegen/generate_equations.py's LOADS and generated into generated_equations.h (LoadName,
// kLoadInfo): MechanismModel::loads() applies it, and every per-load output (power flow, the
// ledger's dissipation, the CSV's and the message's powers, Python's Result.powers()) iterates
// it, so a new resistance is a row there and its parameter.
using generated::kLoadInfo;
using generated::kNumLoadNames;
using generated::LoadInfo;
using generated::LoadKind;
using generated::LoadLaw;
using generated::LoadName;
using generated::LoadSite;
inline const LoadInfo& loadInfo(LoadName name) { return kLoadInfo[static_cast<int>(name)]; }
// The law of the load at a site whose coefficient is the config key `key` ("viscous",
// "coulomb" or "elastic": LAWS' names), or "" when it is no such load's coefficient. What a
// parameter does to the motion beyond its role (a damper's and friction's are both
// "dissipative"; identification starts friction, the least told, at the base's value).
std::string lawOfCoefficient(const std::string& key);

// One entry of the list: the load, its name, and the body it acts on (for the reactions).
struct MechanismLoad {
  LoadName name;
  Body body;
  kane::Load<kNumSpeeds> load;
};
// The list at one instant, every entry present (zero when its option is off) so that the
// layout never depends on the parameters. Fixed capacity: no allocation in the integrators.
using MechanismLoads = boost::container::static_vector<MechanismLoad, 24>;

// Σ of the vectors of the entries named `name` acting on `body` (e.g. the spring's force on
// slider 4).
Eigen::Vector3d loadVector(const MechanismLoads& loads, LoadName name, Body body);

// One impact of the sliders (contact on): the speeds just after it.
struct SliderImpact {
  State after;                  // q unchanged, u after the impulse
  double approach_speed = 0.0;  // [m/s] -(v_C - v_B) before, > 0
  double impulse = 0.0;         // [N s] on slider 4 along +i (the opposite on slider 3)
  double energy_loss = 0.0;     // [J] T before - T after = ½ (1 - e²) m_eff v²
};

// Resting contact (contact on, the sliders held together at the gap): the contact as a
// unilateral constraint x_C - x_B = gap, i.e. J u = 0 with J_r = ∂(v_C - v_B)/∂u_r · i. Kane's
// equations with the constraint force N along J^T: M u' = forcing + J^T N, and J u' + J' u = 0
// give N = -(J u'_free + J' u) / (J M^-1 J^T), u' = u'_free + M^-1 J^T N.
struct RestingContact {
  SpeedVector u_dot = SpeedVector::Zero();  // u' with the sliders held together
  double force = 0.0;  // N [N] on slider 4 along +i (pushing it away from slider 3; the
                       // opposite on slider 3); < 0 would pull: the contact lets go
  // -(J u'_free + J' u) [m/s^2]: how fast the free motion would close the gap (> 0: N > 0).
  double closing_acceleration = 0.0;
};

// The kinetic energy and each conservative load's potential energy (a load whose LoadInfo names
// an energy column): gravity's V_g = -Σ M g (r · i), zero at the level of O; the spring's
// V_s = ½ k e²; an elastic law's ½ c (x - x0)². Sums run in the load list's order.
struct EnergyTerms {
  double kinetic = 0.0;                           // T [J]
  std::array<double, kNumLoadNames> potential{};  // [J] by LoadName; 0 for the other loads

  double operator[](LoadName name) const { return potential[static_cast<int>(name)]; }
  double& operator[](LoadName name) { return potential[static_cast<int>(name)]; }
  double gravitational() const { return (*this)[LoadName::kGravity]; }
  double spring() const { return (*this)[LoadName::kSpring]; }
  // V, the sum of the conservative loads' potential energies.
  double potentialTotal() const {
    double sum = 0.0;
    for (int n = 0; n < kNumLoadNames; ++n)
      if (kLoadInfo[n].energy_column) sum += potential[n];
    return sum;
  }
  // E = T + V, summed from T in the list's order (so that with the loads of the textbook example
  // it is T + V_g + V_s, bit for bit).
  double total() const {
    double sum = kinetic;
    for (int n = 0; n < kNumLoadNames; ++n)
      if (kLoadInfo[n].energy_column) sum += potential[n];
    return sum;
  }
};

// Where the power goes at one instant: d(E)/dt = motor - dissipated (at fixed parameters).
struct PowerTerms {
  double motor = 0.0;       // M_m u1 [W], the applied torque's power
  double dissipated = 0.0;  // [W] >= 0: dampers and friction (impacts dissipate at instants)
};

class MechanismModel {
 public:
  using Equations = kane::KaneEquations<kNumSpeeds>;

  // spring_rest_length: x_C - x_B [m] at which the spring is unstretched.
  MechanismModel(const MechanismParameters& parameters, double spring_rest_length);

  MechanismGeometry geometry(double q1, double q2) const {
    return mechanismGeometry(parameters_.rod_half_length, q1, q2);
  }
  MechanismKinematics kinematics(const State& x) const;
  // motor_command: M_m as commanded (already within the torque limit); the motor line, when
  // on, limits it at u1 (appliedMotorTorque). The contact's entries are not in it (the
  // simulator adds them once N is known: addContactLoads).
  MechanismLoads loads(const MechanismKinematics& k, const State& x, double motor_command) const;
  // The resting contact's force N [N]: +N i on slider 4 at C, -N i on slider 3 at B.
  static void addContactLoads(const MechanismKinematics& k, double contact_force,
                              MechanismLoads* loads);

  // A load at a site: its coefficient (its LoadInfo's), and the force or torque it opposes the
  // site's rate `rate` or coordinate `coordinate` with: c v (viscous), F_c tanh(v / v_s)
  // (Coulomb, smoothed) or c (x - x0) (elastic); and its potential energy, ½ c (x - x0)² for
  // an elastic law (0 for the others: they have none).
  double resistanceCoefficient(const LoadInfo& load) const;
  double siteLoad(const LoadInfo& load, double rate, double coordinate) const;
  double sitePotential(const LoadInfo& load, double coordinate) const;

  // The torque the drive delivers at crank speed u1 for a command (MotorLine).
  double appliedMotorTorque(double command, double u1) const;
  static PowerTerms power(const MechanismLoads& loads, const State& x);

  // Contact on and the sliders at the gap, approaching: the impact (Newton's restitution law
  // in Kane's impulsive form: M Δu = J^T λ, J_r = ∂(v_C - v_B)/∂u_r · i, J u+ = -e J u-).
  // `restitution` defaults to contact.restitution; 0 gives the plastic impact that starts a
  // resting contact.
  std::optional<SliderImpact> sliderImpact(const State& x) const {
    return sliderImpact(x, parameters_.contact.restitution);
  }
  std::optional<SliderImpact> sliderImpact(const State& x, double restitution) const;

  // J_r = ∂(v_C - v_B)/∂u_r · i = (4 L sin q1, 1): the separation rate is J u.
  static SpeedVector separationJacobian(const MechanismKinematics& k);
  // The state with slider 4 held at the gap below slider 3 (q2 = 4L cos q1 + gap, u2 from
  // J u = 0), q1 and u1 as given: the configuration manifold of resting contact.
  State onContact(const State& x) const;
  // The constraint force and u' of resting contact at x (x on the contact: onContact(x) == x),
  // from u'_free, the unconstrained u' of the equations in use (M from the assembly).
  RestingContact restingContact(const State& x, const SpeedVector& u_dot_free,
                                double motor_command) const;

  // F*_r (as mass matrix and remainder) and F_r, eqs (12) and (16), term by term.
  static Equations equations(const MechanismKinematics& k, const MechanismLoads& loads,
                             const State& x);
  Equations equations(const State& x, double motor_command) const;

  // The crank moment M_m that balances gravity and the spring at x's configuration: with
  // u = 0 the active force F_1 (eq 16) of those loads plus M_m is zero, so M_m = -F_1. The
  // servo's feedforward (command.feedforward).
  double holdingMoment(const State& x) const {
    return -equations(State{x.q1, x.q2, 0.0, 0.0}, 0.0).active_forces[0];
  }

  // u' from F*_r + F_r = 0, eq (18).
  SpeedVector accelerations(const State& x, double motor_command) const {
    return equations(x, motor_command).solveAccelerations();
  }
  // The first-order system the integrators step: q' = u (eq 1), u' (eq 18), and the ledger's
  // W' = M_m u1 and D' = dissipated power, integrated with the motion so E + D - W stays
  // constant to the integrator's order.
  OdeState stateDerivative(const State& x, double motor_command) const;

  // e = (x_B - x_C) - (x_B0 - x_C0) [m], eq (15): F_eB = -k e i, F_eC = +k e i. Positive when
  // the spring is shorter than its rest length (compressed).
  double springElongation(const MechanismGeometry& g) const {
    return spring_rest_length_ - g.sliderSeparation();
  }

  double springRestLength() const { return spring_rest_length_; }
  // x with slider 4 where the spring is unstretched for its q1: q2 = x_B + the rest length.
  State withSpringAtRest(const State& x) const {
    State relaxed = x;
    relaxed.q2 = geometry(x.q1, 0.0).pin_b.x() + spring_rest_length_;
    return relaxed;
  }
  const MechanismParameters& parameters() const { return parameters_; }
  // The same parameters by the equations' symbols (generated::Constants).
  const generated::Constants& constants() const { return constants_; }

  EnergyTerms energy(const MechanismKinematics& k, const State& x) const;
  EnergyTerms energy(const State& x) const { return energy(kinematics(x), x); }

 private:
  MechanismParameters parameters_;
  double spring_rest_length_;       // x_C0 - x_B0 [m]
  generated::Constants constants_;  // the same parameters by the equations' symbols
};

}  // namespace kane_sim

#endif  // KANE_SIM_MODEL_MECHANISM_MODEL_H
