// The physical parameters of the textbook example's mechanism (symbols as in the textbook).
// Required values have no default here: the config loader (config/load_config.h) reads them
// from the config file, which is their one source.
#ifndef KANE_SIM_MODEL_MECHANISM_PARAMETERS_H
#define KANE_SIM_MODEL_MECHANISM_PARAMETERS_H

#include <limits>

namespace kane_sim {

struct MechanismParameters {
  static constexpr double kUnset = std::numeric_limits<double>::quiet_NaN();

  double rod_mass = kUnset;          // m  [kg], each of rods 1 (OA) and 2 (AB)
  double rod_half_length = kUnset;   // L  [m], the rods are 2L long
  double slider3_mass = kUnset;      // M1 [kg]
  double slider4_mass = kUnset;      // M2 [kg]
  double spring_stiffness = kUnset;  // k  [N/m]
  double gravity = kUnset;           // g  [m/s^2], along +i (down)
  // I1z = I2z [kg m^2], central moment of inertia of each rod about k. A uniform slender rod 2L
  // long has m (2L)^2 / 12 (the loader's default); the textbook's script uses m L^2 / 12.
  double rod_inertia = kUnset;

  static double slenderRodInertia(double mass, double half_length) {
    return mass * (2.0 * half_length) * (2.0 * half_length) / 12.0;
  }
};

}  // namespace kane_sim

#endif  // KANE_SIM_MODEL_MECHANISM_PARAMETERS_H
