#include "kane_sim/model/power_flow.h"

namespace kane_sim {
namespace {

// A load that is off (a zero coefficient, no torque) times a negative speed is -0.0, which
// `rostopic echo` and CSVs print as "-0.0" W: x + 0.0 is +0.0 for both zeros, x otherwise.
double unsignedZero(double x) { return x + 0.0; }

}  // namespace

LoadPowers loadPowers(const MechanismLoads& loads, const State& x) {
  const SpeedVector u = x.speeds();
  LoadPowers p;
  for (const MechanismLoad& l : loads) p[l.name] += kane::power(l.load, u);
  for (double& power : p.by_name) power = unsignedZero(power);
  return p;
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
