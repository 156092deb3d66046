// The equations of motion the integrators step by default: generated from a SymPy KanesMethod
// derivation of the same mechanism (model/generated_equations.h, codegen/generate_equations.py),
// bound to one model's parameters. Everything here is inline so the compiler sees through it
// into the integrator's stages; the generic assembly (MechanismModel) is the reference it is
// tested against (u' and the ledger's rates to rounding) and what the publish rate uses.
#ifndef KANE_SIM_MODEL_GENERATED_MECHANISM_H
#define KANE_SIM_MODEL_GENERATED_MECHANISM_H

#include "kane_sim/model/generated_equations.h"
#include "kane_sim/model/mechanism_model.h"
#include "kane_sim/model/state.h"

namespace kane_sim {

class GeneratedMechanism {
 public:
  explicit GeneratedMechanism(const MechanismModel& model)
      : constants_(generated::constantsFrom(model.parameters(), model.springRestLength())),
        motor_(model.parameters().motor),
        variant_(generated::variantFor(constants_)) {}

  // As MechanismModel::stateDerivative: q' = u, u' (eq 18), W' = M_m u1, D' (the resistances'
  // power), with M_m the motor line's torque at u1 for the command.
  OdeState stateDerivative(const State& x, double motor_command) const {
    const double torque = motorLineTorque(motor_, motor_command, x.u1);  // M_m
    // The shortest generated variant that holds every non-zero resistance (the branch is the
    // same every call).
    const generated::Rates r =
        generated::ratesFor(variant_, constants_, x.q1, x.q2, x.u1, x.u2, torque);
    return {x.u1, x.u2, r.u1_dot, r.u2_dot, torque * x.u1, r.dissipated_power};
  }

  const generated::Constants& constants() const { return constants_; }
  generated::RatesVariant variant() const { return variant_; }

 private:
  generated::Constants constants_;
  MotorLine motor_;
  generated::RatesVariant variant_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_MODEL_GENERATED_MECHANISM_H
