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

struct LoadPowers {
  double gravity = 0.0;         // [W] Σ G_b · v_b (G1 ... G4), = -dV_g/dt
  double spring = 0.0;          // [W] F_eB · v_B + F_eC · v_C, = -dV_s/dt
  double motor = 0.0;           // [W] M_m u1
  double crank_damper = 0.0;    // [W] <= 0, pin O
  double coupler_damper = 0.0;  // [W] <= 0, pin A (its torques on both rods)
  double slider3_damper = 0.0;  // [W] <= 0
  double slider4_damper = 0.0;  // [W] <= 0
  double contact = 0.0;         // [W] N (v_C - v_B): 0 while the sliders rest on each other

  double dampers() const { return crank_damper + coupler_damper + slider3_damper + slider4_damper; }
  double total() const { return gravity + spring + motor + dampers() + contact; }  // = dT/dt
};

// The loads' powers at speeds u. `contact` is left 0: the resting contact's force is not one of
// MechanismLoads (the simulator adds it, contactPower).
LoadPowers loadPowers(const MechanismLoads& loads, const State& x);
// N J u: the power of the resting contact's force N on slider 4 along +x (and -N on slider 3).
double contactPower(const MechanismKinematics& k, const State& x, double contact_force);

// T of rod 1, rod 2, slider 3, slider 4 (indexed by Body) [J].
std::array<double, kNumBodies> bodyKineticEnergies(const MechanismKinematics& k, const State& x);

}  // namespace kane_sim

#endif  // KANE_SIM_MODEL_POWER_FLOW_H
