// Identification's linear form of Kane's equations. F*_r + F_r = 0 (eq 18) is linear in the
// masses (m, M1, M2), the rod inertia (I1z = I2z), the spring's stiffness k and its preload
// k s0 (k times the rest length), each damper (c_O, c_A, c_B, c_C, c_S) and a constant torque
// offset added to the measured driver moment M_m: at a state x with rates u' and measured M_m,
//
//   F*_r + F_r = Σ_j Y_rj(x, u') θ_j + y0_r(x, u', M_m) = 0      (r = 1, 2)
//
// so a recorded motion gives the least-squares problem Y θ = -y0. Column j is not derived a
// second time: it is the model's own F*_r + F_r (MechanismModel::equations, the loads list) with
// θ_j = 1 and the other chosen parameters 0, minus the same with θ_j = 0; y0 is the model with
// the chosen parameters 0 and the rest at the base config's values (L, g and the rod's shape are
// measured, not identified).
//
// The work-energy form (Kane's equations dotted with u, power_flow.h) needs no u': per sample
// the energy E = T + V_g + V_s and the non-conservative power P (the motor's and the dampers')
// are linear in the same θ, and E(b) - E(a) = ∫_a^b P dt over any window.
//
// The parameters are the schema's (config/parameter_schema.h: the mechanism section but the
// measured L and g, and the damping section), by their config paths, plus two that are not
// config keys: "spring_rest_length" (identified through the preload k s0) and "torque_offset"
// (a constant added to the measured M_m: a torque sensor's bias or a constant drag).
#ifndef KANE_SIM_IDENTIFY_REGRESSOR_H
#define KANE_SIM_IDENTIFY_REGRESSOR_H

#include <string>
#include <vector>

#include <Eigen/Core>

#include "kane_sim/config/config.h"
#include "kane_sim/model/mechanism_model.h"

namespace kane_sim {

constexpr const char* kSpringRestLength = "spring_rest_length";  // s0 = x_C0 - x_B0 [m]
constexpr const char* kTorqueOffset = "torque_offset";           // [N m] added to the measured M_m

struct IdentifiableParameter {
  std::string name;  // the config path ("mechanism.rod_mass"), or kSpringRestLength, kTorqueOffset
  std::string unit;
  std::string symbol;       // the textbook's (m, M1, k, c_O, ...)
  bool by_default = false;  // identified unless the caller names the parameters
};

// Every parameter identification can estimate, in a fixed order: the schema's physical ones,
// then the rest length and the torque offset. By default all but the rod inertia (tied to m
// through the rod's radius of gyration, which the base gives) and the rest length (the base's
// initial state gives it).
const std::vector<IdentifiableParameter>& identifiableParameters();

// Throws std::invalid_argument naming an unknown or repeated name, or the rest length without
// the stiffness.
void checkIdentifiedNames(const std::vector<std::string>& names);

class Regressor {
 public:
  // base: the measured geometry (L, g, the rod's radius of gyration, the rest length from the
  // initial state) and the values of the parameters not identified. The motor line is not
  // used: the data's torque is what the drive delivered.
  Regressor(const Config& base, const std::vector<std::string>& identified);

  const std::vector<std::string>& names() const { return names_; }
  int size() const { return static_cast<int>(names_.size()); }

  // The 2 x size() block of Y and y0 at one sample (M_m: the measured torque).
  void equationRows(const State& x, const SpeedVector& u_dot, double torque,
                    Eigen::Ref<Eigen::Matrix<double, kNumSpeeds, Eigen::Dynamic>> y,
                    Eigen::Ref<SpeedVector> y0) const;
  // Per unit θ_j: E_j (the energy, J) and P_j (the non-conservative power, W); e0 and p0 the
  // known parts (p0 includes the measured torque's power).
  void energyRow(const State& x, double torque, Eigen::Ref<Eigen::RowVectorXd> energy,
                 Eigen::Ref<Eigen::RowVectorXd> power, double* e0, double* p0) const;

 private:
  struct Column {
    MechanismModel on;        // θ_j = 1
    MechanismModel off;       // θ_j = 0 (differs from a zero model only for the preload)
    double command_on = 0.0;  // the torque offset's unit torque
  };
  std::vector<std::string> names_;
  std::vector<Column> columns_;
  MechanismModel known_;  // the chosen parameters 0, the rest at the base's values
};

// A config's value of an identifiable parameter (the rest length: the initial state's
// separation; the torque offset: 0). std::invalid_argument names an unknown name.
double identificationBaseValue(const Config& config, const std::string& name);

}  // namespace kane_sim

#endif  // KANE_SIM_IDENTIFY_REGRESSOR_H
