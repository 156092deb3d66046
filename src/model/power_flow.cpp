#include "kane_sim/model/power_flow.h"

namespace kane_sim {
namespace {

// A load that is off (a zero coefficient, no torque) times a negative speed is -0.0, which
// `rostopic echo` and CSVs print as "-0.0" W: x + 0.0 is +0.0 for both zeros, x otherwise.
double unsignedZero(double x) { return x + 0.0; }

}  // namespace

LoadPowers loadPowers(const MechanismLoads& l, const State& x) {
  const SpeedVector u = x.speeds();
  LoadPowers p;
  for (const auto& g : l.gravity) p.gravity += kane::power(g, u);
  p.spring = kane::power(l.spring_on_slider3, u) + kane::power(l.spring_on_slider4, u);
  p.motor = kane::power(l.motor, u);
  p.crank_damper = kane::power(l.crank_damper, u);
  p.coupler_damper =
      kane::power(l.coupler_damper_on_rod1, u) + kane::power(l.coupler_damper_on_rod2, u);
  p.slider3_damper = kane::power(l.slider3_damper, u);
  p.slider4_damper = kane::power(l.slider4_damper, u);
  for (double* power : {&p.gravity, &p.spring, &p.motor, &p.crank_damper, &p.coupler_damper,
                        &p.slider3_damper, &p.slider4_damper})
    *power = unsignedZero(*power);
  return p;
}

double contactPower(const MechanismKinematics& k, const State& x, double contact_force) {
  return unsignedZero(contact_force * MechanismModel::separationJacobian(k).dot(x.speeds()));
}

std::array<double, kNumBodies> bodyKineticEnergies(const MechanismKinematics& k, const State& x) {
  const SpeedVector u = x.speeds();
  std::array<double, kNumBodies> t{};
  t[kRod1] = kane::kineticEnergy(k.rod1, u);
  t[kRod2] = kane::kineticEnergy(k.rod2, u);
  t[kSlider3] = kane::kineticEnergy(k.slider3, u);
  t[kSlider4] = kane::kineticEnergy(k.slider4, u);
  return t;
}

}  // namespace kane_sim
