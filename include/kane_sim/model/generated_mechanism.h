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
      : constants_(constantsOf(model)),
        motor_(model.parameters().motor),
        damped_(model.parameters().damping.any()) {}

  // As MechanismModel::stateDerivative: q' = u, u' (eq 18), W' = M_m u1, D' (dampers' power),
  // with M_m the motor line's torque at u1 for the command.
  OdeState stateDerivative(const State& x, double motor_command) const {
    const double torque = motorLineTorque(motor_, motor_command, x.u1);  // M_m
    // Without dampers the shorter generated variant (the branch is the same every call).
    const generated::Rates r =
        damped_ ? generated::rates(constants_, x.q1, x.q2, x.u1, x.u2, torque)
                : generated::ratesUndamped(constants_, x.q1, x.q2, x.u1, x.u2, torque);
    return {x.u1, x.u2, r.u1_dot, r.u2_dot, torque * x.u1, r.dissipated_power};
  }

  const generated::Constants& constants() const { return constants_; }

 private:
  static generated::Constants constantsOf(const MechanismModel& model) {
    const MechanismParameters& p = model.parameters();
    generated::Constants c;
    c.rod_mass = p.rod_mass;                  // m
    c.rod_half_length = p.rod_half_length;    // L
    c.rod_inertia = p.rod_inertia;            // I1z = I2z
    c.slider3_mass = p.slider3_mass;          // M1
    c.slider4_mass = p.slider4_mass;          // M2
    c.spring_stiffness = p.spring_stiffness;  // k
    c.gravity = p.gravity;                    // g
    c.spring_rest_length = model.springRestLength();
    c.crank_damping = p.damping.crank;      // c_O
    c.coupler_damping = p.damping.coupler;  // c_A
    c.slider3_damping = p.damping.slider3;  // c_B
    c.slider4_damping = p.damping.slider4;  // c_C
    c.spring_damping = p.damping.spring;    // c_S
    return c;
  }

  generated::Constants constants_;
  MotorLine motor_;
  bool damped_;  // any damper non-zero
};

}  // namespace kane_sim

#endif  // KANE_SIM_MODEL_GENERATED_MECHANISM_H
