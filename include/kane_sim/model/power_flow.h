// Where the mechanism's energy flows at one instant: the power of each load of Kane's
// equations (the same loads, with the same partial velocities, as F_r) and each body's kinetic
// energy. The work-energy theorem is Kane's equations dotted with u: Σ_r F*_r u_r = -dT/dt and
// Σ_r F_r u_r = Σ load powers, so Σ load powers = dT/dt (gravity's and the spring's powers are
// -dV_g/dt and -dV_s/dt).
#ifndef KANE_SIM_MODEL_POWER_FLOW_H
#define KANE_SIM_MODEL_POWER_FLOW_H

#include <array>

#include "kane_sim/model/mechanism_model.h"
#include "kane_sim/model/state.h"

namespace kane_sim {

// The power of each named load [W] (MechanismLoads' names): gravity's is -dV_g/dt, the spring's
// -dV_s/dt, the motor's M_m u1, each damper's <= 0, the contact's N (v_C - v_B) (0 while the
// sliders rest on each other).
struct LoadPowers {
  std::array<double, kNumLoadNames> by_name{};

  double operator[](LoadName name) const { return by_name[static_cast<int>(name)]; }
  double& operator[](LoadName name) { return by_name[static_cast<int>(name)]; }
  double dissipative() const {  // <= 0: every dissipative load (dampers, friction)
    double sum = 0.0;
    for (int n = 0; n < kNumLoadNames; ++n)
      if (kLoadInfo[n].dissipative) sum += by_name[n];
    return sum;
  }
  double total() const {  // = dT/dt
    double sum = 0.0;
    for (double p : by_name) sum += p;
    return sum;
  }
};

// Each named load's power at speeds u: the sum over its entries of F · v_P (T · ω).
LoadPowers loadPowers(const MechanismLoads& loads, const State& x);

// T of rod 1, rod 2, slider 3, slider 4 (indexed by Body) [J].
std::array<double, kNumBodies> bodyKineticEnergies(const MechanismKinematics& k, const State& x);

}  // namespace kane_sim

#endif  // KANE_SIM_MODEL_POWER_FLOW_H
