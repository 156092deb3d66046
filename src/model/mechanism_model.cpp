#include "kane_sim/model/mechanism_model.h"

#include "kane_sim/model/math_functions.h"
#include "kane_sim/model/power_flow.h"

#include <algorithm>
#include <cmath>

namespace kane_sim {
namespace {

const Eigen::Vector3d kI = Eigen::Vector3d::UnitX();  // i, vertical, down
const Eigen::Vector3d kK = Eigen::Vector3d::UnitZ();  // k, out of the plane

// Principal central moments of a slender rod in the plane: only I_z matters for planar motion
// (ω and α are along k), the in-plane moments are left zero.
Eigen::Vector3d planarInertia(double i_z) { return Eigen::Vector3d(0, 0, i_z); }

MechanismGeometry geometryFromTrig(double L, double q1, double c, double s, double q2) {
  MechanismGeometry g;
  g.rod_length = 2 * L;
  g.pin_a = Eigen::Vector3d(2 * L * c, 2 * L * s, 0);
  g.pin_b = Eigen::Vector3d(slider3Position(L, c), 0, 0);  // r_B
  g.point_c = Eigen::Vector3d(q2, 0, 0);                   // r_C
  g.rod1_center = Eigen::Vector3d(L * c, L * s, 0);        // r_C1
  g.rod2_center = Eigen::Vector3d(3 * L * c, L * s, 0);    // r_C2
  g.rod1_angle = q1;
  g.rod2_angle = -q1;
  return g;
}

}  // namespace

MechanismGeometry mechanismGeometry(double rod_half_length, double q1, double q2) {
  double s, c;
  math::sinCos(q1, &s, &c);  // the equations' own sin and cos (model/math_functions.h)
  return geometryFromTrig(rod_half_length, q1, c, s, q2);
}

MechanismModel::MechanismModel(const MechanismParameters& parameters, double spring_rest_length)
    : parameters_(parameters),
      spring_rest_length_(spring_rest_length),
      constants_(generated::constantsFrom(parameters, spring_rest_length)) {}

std::string lawOfCoefficient(const std::string& key) {
  for (const LoadInfo& load : kLoadInfo) {
    if (load.coefficient < 0 || key != generated::kConstantKeys[load.coefficient]) continue;
    switch (load.law) {
      case LoadLaw::kViscous:
        return "viscous";
      case LoadLaw::kCoulomb:
        return "coulomb";
      case LoadLaw::kElastic:
        return "elastic";
      case LoadLaw::kNone:
        break;
    }
  }
  return "";
}

double MechanismModel::resistanceCoefficient(const LoadInfo& load) const {
  return (&constants_.rod_mass)[load.coefficient];
}

double MechanismModel::siteLoad(const LoadInfo& load, double rate, double coordinate) const {
  const double c = resistanceCoefficient(load);
  switch (load.law) {
    case LoadLaw::kViscous:  // c v
      return c * rate;
    case LoadLaw::kCoulomb:  // F_c tanh(v / v_s); none at all when off, whatever v_s
      return c == 0.0 ? 0.0 : c * math::tanh(rate / (&constants_.rod_mass)[load.rate_scale]);
    case LoadLaw::kElastic:  // c (x - x0); none at all when off, wherever its rest
      return c == 0.0 ? 0.0 : c * (coordinate - (&constants_.rod_mass)[load.rest]);
    case LoadLaw::kNone:
      break;
  }
  return 0.0;
}

double MechanismModel::sitePotential(const LoadInfo& load, double coordinate) const {
  const double c = resistanceCoefficient(load);
  if (load.law != LoadLaw::kElastic || c == 0.0) return 0.0;
  const double stretch = coordinate - (&constants_.rod_mass)[load.rest];  // x - x0
  return 0.5 * c * stretch * stretch;
}

namespace {

// A site's coordinate x (its rate is x'): the crank's q1, the coupler pin's relative angle
// -2 q1 (rod 2 at -q1 against rod 1 at q1), x_B, x_C, and x_C - x_B beside the spring.
double siteCoordinate(LoadSite site, const MechanismGeometry& g) {
  switch (site) {
    case LoadSite::kCrank:
      return g.rod1_angle;
    case LoadSite::kCoupler:
      return g.rod2_angle - g.rod1_angle;
    case LoadSite::kSlider3:
      return g.pin_b.x();
    case LoadSite::kSlider4:
      return g.point_c.x();
    case LoadSite::kSpring:
      return g.sliderSeparation();
    case LoadSite::kNone:
      break;
  }
  return 0.0;
}

}  // namespace

MechanismKinematics MechanismModel::kinematics(const State& x) const {
  const MechanismParameters& p = parameters_;
  const double L = p.rod_half_length;  // L
  double s, c;
  math::sinCos(x.q1, &s, &c);
  const double u1_sq = x.u1 * x.u1;

  MechanismKinematics k;
  k.geometry = geometryFromTrig(L, x.q1, c, s, x.q2);
  const MechanismGeometry& g = k.geometry;

  // Rigid body 1, rod OA: v_C1 = u1 L (-sin q1, cos q1), ω10 = u1 k (eqs 1, 3, 4).
  k.rod1.mass_center.mass = p.rod_mass;  // m
  k.rod1.mass_center.position = g.rod1_center;
  k.rod1.mass_center.partial_velocity.col(0) << -L * s, L * c, 0;                  // ∂v_C1/∂u1
  k.rod1.mass_center.acceleration_remainder << -L * u1_sq * c, -L * u1_sq * s, 0;  // a_C1, u1'=0
  k.rod1.principal_moments = planarInertia(p.rod_inertia);                         // I1z
  k.rod1.partial_angular_velocity.col(0) = kK;                                     // ∂ω10/∂u1

  // Rigid body 2, rod AB: v_C2 = u1 L (-3 sin q1, cos q1), ω20 = -u1 k.
  k.rod2.mass_center.mass = p.rod_mass;
  k.rod2.mass_center.position = g.rod2_center;
  k.rod2.mass_center.partial_velocity.col(0) << -3 * L * s, L * c, 0;
  k.rod2.mass_center.acceleration_remainder << -3 * L * u1_sq * c, -L * u1_sq * s, 0;
  k.rod2.principal_moments = planarInertia(p.rod_inertia);  // I2z
  k.rod2.partial_angular_velocity.col(0) = -kK;

  // Body 3, slider at B: v_B = -4 L u1 sin q1 i.
  k.slider3.mass = p.slider3_mass;  // M1
  k.slider3.position = g.pin_b;
  k.slider3.partial_velocity.col(0) << -4 * L * s, 0, 0;
  k.slider3.acceleration_remainder << -4 * L * u1_sq * c, 0, 0;

  // Body 4, slider at C: v_C = u2 i.
  k.slider4.mass = p.slider4_mass;  // M2
  k.slider4.position = g.point_c;
  k.slider4.partial_velocity.col(1) = kI;  // ∂v_C/∂u2
  return k;
}

double MechanismModel::appliedMotorTorque(double command, double u1) const {
  return motorLineTorque(parameters_.motor, command, u1);
}

MechanismLoads MechanismModel::loads(const MechanismKinematics& k, const State& x,
                                     double motor_command) const {
  const MechanismParameters& p = parameters_;
  const SpeedVector u = x.speeds();
  MechanismLoads l;
  auto add = [&l](LoadName name, Body body, const kane::Load<kNumSpeeds>& load) {
    l.push_back({name, body, load});
  };
  // Eq (14): gravity at each mass center, along +i: G1 = m g i, ..., G4 = M2 g i.
  add(LoadName::kGravity, kRod1, kane::forceAt(k.rod1.mass_center, p.rod_mass * p.gravity * kI));
  add(LoadName::kGravity, kRod2, kane::forceAt(k.rod2.mass_center, p.rod_mass * p.gravity * kI));
  add(LoadName::kGravity, kSlider3, kane::forceAt(k.slider3, p.slider3_mass * p.gravity * kI));
  add(LoadName::kGravity, kSlider4, kane::forceAt(k.slider4, p.slider4_mass * p.gravity * kI));
  // Eq (15): F_eB = -k e i at B, F_eC = -F_eB at C.
  const Eigen::Vector3d spring_on_b = -p.spring_stiffness * springElongation(k.geometry) * kI;
  add(LoadName::kSpring, kSlider3, kane::forceAt(k.slider3, spring_on_b));
  add(LoadName::kSpring, kSlider4, kane::forceAt(k.slider4, -spring_on_b));
  // The driver moment M_m k on rod 1 (through the motor line, when on).
  add(LoadName::kMotor, kRod1,
      kane::torqueOn(k.rod1, appliedMotorTorque(motor_command, x.u1) * kK));

  // The loads at a site (dampers, friction, elastic springs), opposing their sites' rates or
  // pulling their coordinates back to rest: torques on the rods' frames, forces at the
  // sliders, and the reactions where a site joins two bodies.
  const double w1 = k.rod1.angularVelocity(u).z(), w2 = k.rod2.angularVelocity(u).z();
  const double v_b = k.slider3.velocity(u).x(), v_c = k.slider4.velocity(u).x();
  for (int n = 0; n < kNumLoadNames; ++n) {
    const LoadInfo& info = kLoadInfo[n];
    if (info.site == LoadSite::kNone) continue;
    const LoadName name = static_cast<LoadName>(n);
    const double x = siteCoordinate(info.site, k.geometry);
    switch (info.site) {
      case LoadSite::kCrank:  // pin O: -F k on rod 1, F from w1
        add(name, kRod1, kane::torqueOn(k.rod1, Eigen::Vector3d(-siteLoad(info, w1, x) * kK)));
        break;
      case LoadSite::kCoupler: {  // pin A: -F k on rod 2 from w2 - w1, its reaction on rod 1
        const Eigen::Vector3d on_rod2 = -siteLoad(info, w2 - w1, x) * kK;
        add(name, kRod2, kane::torqueOn(k.rod2, on_rod2));
        add(name, kRod1, kane::torqueOn(k.rod1, Eigen::Vector3d(-on_rod2)));
        break;
      }
      case LoadSite::kSlider3:  // -F i at B, F from v_B
        add(name, kSlider3,
            kane::forceAt(k.slider3, Eigen::Vector3d(-siteLoad(info, v_b, x) * kI)));
        break;
      case LoadSite::kSlider4:  // -F i at C, F from v_C
        add(name, kSlider4,
            kane::forceAt(k.slider4, Eigen::Vector3d(-siteLoad(info, v_c, x) * kI)));
        break;
      case LoadSite::kSpring: {  // -F i on slider 4 from v_C - v_B, the opposite on slider 3
        const Eigen::Vector3d on_c = -siteLoad(info, v_c - v_b, x) * kI;
        add(name, kSlider3, kane::forceAt(k.slider3, Eigen::Vector3d(-on_c)));
        add(name, kSlider4, kane::forceAt(k.slider4, on_c));
        break;
      }
      case LoadSite::kNone:
        break;
    }
  }
  return l;
}

void MechanismModel::addContactLoads(const MechanismKinematics& k, double contact_force,
                                     MechanismLoads* loads) {
  const Eigen::Vector3d on_c = contact_force * kI;
  loads->push_back({LoadName::kContact, kSlider3, kane::forceAt(k.slider3, -on_c)});
  loads->push_back({LoadName::kContact, kSlider4, kane::forceAt(k.slider4, on_c)});
}

Eigen::Vector3d loadVector(const MechanismLoads& loads, LoadName name, Body body) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const MechanismLoad& l : loads)
    if (l.name == name && l.body == body) sum += l.load.vector;
  return sum;
}

PowerTerms MechanismModel::power(const MechanismLoads& l, const State& x) {
  const LoadPowers each = loadPowers(l, x);
  return {each[LoadName::kMotor], -each.dissipative()};
}

std::optional<SliderImpact> MechanismModel::sliderImpact(const State& x, double restitution) const {
  const SliderContact& contact = parameters_.contact;
  if (!contact.enabled) return std::nullopt;
  const MechanismKinematics k = kinematics(x);
  const SpeedVector J = separationJacobian(k);
  const SpeedVector u = x.speeds();
  const double closing = -J.dot(u);  // approach speed
  if (!(closing > 0.0)) return std::nullopt;
  const Equations eq = equations(k, loads(k, x, 0.0), x);
  const SpeedVector minv_j = eq.mass_matrix.inverse() * J;
  // λ from J (u + M^-1 J λ) = e · closing: the impulse on slider 4 along +i.
  const double lambda = (1.0 + restitution) * closing / J.dot(minv_j);
  SliderImpact impact;
  impact.after = x;
  const SpeedVector u_after = u + minv_j * lambda;
  impact.after.u1 = u_after[0];
  impact.after.u2 = u_after[1];
  impact.approach_speed = closing;
  impact.impulse = lambda;
  impact.energy_loss = energy(x).kinetic - energy(impact.after).kinetic;
  return impact;
}

SpeedVector MechanismModel::separationJacobian(const MechanismKinematics& k) {
  // The partial velocities of the separation rate, (∂v_C/∂u_r - ∂v_B/∂u_r) · i.
  return (k.slider4.partial_velocity.row(0) - k.slider3.partial_velocity.row(0)).transpose();
}

State MechanismModel::onContact(const State& x) const {
  const MechanismKinematics k = kinematics(x);  // J does not depend on q2
  State held = x;
  held.q2 = k.geometry.pin_b.x() + parameters_.contact.gap;  // x_C = x_B + gap
  held.u2 = -separationJacobian(k)[0] * x.u1;                // J u = 0 (J_2 = 1)
  return held;
}

RestingContact MechanismModel::restingContact(const State& x, const SpeedVector& u_dot_free,
                                              double motor_command) const {
  const MechanismKinematics k = kinematics(x);
  const SpeedVector J = separationJacobian(k);
  // J' u: the separation's acceleration at u' = 0, from the acceleration remainders of C and B.
  const double bias = (k.slider4.acceleration_remainder - k.slider3.acceleration_remainder).x();
  const SpeedVector minv_j = equations(k, loads(k, x, motor_command), x).mass_matrix.inverse() * J;
  RestingContact contact;
  contact.closing_acceleration = -(J.dot(u_dot_free) + bias);
  contact.force = contact.closing_acceleration / J.dot(minv_j);
  contact.u_dot = u_dot_free + minv_j * contact.force;
  return contact;
}

MechanismModel::Equations MechanismModel::equations(const MechanismKinematics& k,
                                                    const MechanismLoads& loads, const State& x) {
  const SpeedVector u = x.speeds();
  Equations eq;
  // F*_r, eq (12): the sum over the four bodies of eqs (5)-(7).
  kane::addInertiaForces(k.rod1, u, &eq);
  kane::addInertiaForces(k.rod2, u, &eq);
  kane::addInertiaForces(k.slider3, &eq);
  kane::addInertiaForces(k.slider4, &eq);
  // F_r, eq (16): each load on the partial velocities of where it acts.
  for (const MechanismLoad& l : loads) kane::addActiveForces(l.load, &eq);
  return eq;
}

MechanismModel::Equations MechanismModel::equations(const State& x, double motor_command) const {
  const MechanismKinematics k = kinematics(x);
  return equations(k, loads(k, x, motor_command), x);
}

OdeState MechanismModel::stateDerivative(const State& x, double motor_command) const {
  const MechanismKinematics k = kinematics(x);
  const MechanismLoads l = loads(k, x, motor_command);
  const SpeedVector u_dot = equations(k, l, x).solveAccelerations();
  const PowerTerms p = power(l, x);
  // q1' = u1, q2' = u2 (eq 1); u1', u2' (eq 18); W' and D' of the ledger.
  return {x.u1, x.u2, u_dot[0], u_dot[1], p.motor, p.dissipated};
}

EnergyTerms MechanismModel::energy(const MechanismKinematics& k, const State& x) const {
  const double g = parameters_.gravity;
  EnergyTerms e;
  for (double body : bodyKineticEnergies(k, x)) e.kinetic += body;
  for (const kane::Particle<kNumSpeeds>* p :
       {&k.rod1.mass_center, &k.rod2.mass_center, &k.slider3, &k.slider4})
    e[LoadName::kGravity] -= p->mass * g * p->position.dot(kI);
  const double elongation = springElongation(k.geometry);
  e[LoadName::kSpring] = 0.5 * parameters_.spring_stiffness * elongation * elongation;
  // Each conservative load at a site: its law's potential at its site's coordinate.
  for (int n = 0; n < kNumLoadNames; ++n)
    if (kLoadInfo[n].site != LoadSite::kNone && kLoadInfo[n].energy_column)
      e.potential[n] = sitePotential(kLoadInfo[n], siteCoordinate(kLoadInfo[n].site, k.geometry));
  return e;
}

}  // namespace kane_sim
