// The equations of motion the integrators step by default: generated from a SymPy KanesMethod
// derivation of the same mechanism (model/generated_equations.h, codegen/generate_equations.py),
// bound to one model's parameters. Everything here is inline so the compiler sees through it
// into the integrator's stages; the generic assembly (MechanismModel) is the reference it is
// tested against (u' and the ledger's rates to rounding) and what the publish rate uses.
#ifndef KANE_SIM_MODEL_GENERATED_MECHANISM_H
#define KANE_SIM_MODEL_GENERATED_MECHANISM_H

#include "kane_sim/model/generated_equations.h"
#include "kane_sim/model/generated_jacobian.h"
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
    return derivative(variant_, constants_, motor_, x, motor_command);
  }

  // The same equations with the variant fixed at compile time.
  template <generated::RatesVariant Variant>
  struct Bound {
    const GeneratedMechanism* mechanism;
    OdeState stateDerivative(const State& x, double motor_command) const {
      return derivative(Variant, mechanism->constants_, mechanism->motor_, x, motor_command);
    }
  };

  // f(bound), bound a Bound of this mechanism's variant: for a body that evaluates the equations
  // several times (an integrator's stages), which then takes the variant's branch once instead
  // of at every evaluation (~6 ns of a ~110 ns rk4 step).
  template <class F>
  decltype(auto) withBound(F&& f) const {
    using generated::RatesVariant;
    switch (variant_) {
      case RatesVariant::kUndamped:
        return f(Bound<RatesVariant::kUndamped>{this});
      case RatesVariant::kViscous:
        return f(Bound<RatesVariant::kViscous>{this});
      case RatesVariant::kCoulomb:
        return f(Bound<RatesVariant::kCoulomb>{this});
      default:
        break;
    }
    static_assert(generated::kEveryTerm == RatesVariant::kElastic, "the last variant");
    return f(Bound<RatesVariant::kElastic>{this});
  }

  const generated::Constants& constants() const { return constants_; }
  generated::RatesVariant variant() const { return variant_; }

  // x' = (q', u') linearized at x under `motor_command`: A = d x'/d x (rows and columns q1, q2,
  // u1, u2) and B = d x'/d command, from the generated equations' exact derivatives (every load
  // at a site; generated_jacobian.h), the motor line's slopes chained in (at its corner, the
  // side motorLineTorque takes).
  struct Linearization {
    Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
    Eigen::Vector4d B = Eigen::Vector4d::Zero();
  };
  Linearization linearization(const State& x, double motor_command) const {
    const MotorLineSlopes motor = motorLineSlopes(motor_, motor_command, x.u1);
    const generated::RateJacobian rates = generated::rateJacobian(
        constants_, x.q1, x.q2, x.u1, x.u2, motorLineTorque(motor_, motor_command, x.u1));
    Linearization l;
    l.A.topRightCorner<2, 2>().setIdentity();  // q' = u
    for (int row = 0; row < 2; ++row) {
      const double* d = rates.d[row];  // d u'/d (q1, q2, u1, u2, M_m)
      l.A.row(2 + row) << d[0], d[1], d[2] + d[4] * motor.per_speed, d[3];
      l.B[2 + row] = d[4] * motor.per_command;
    }
    return l;
  }

 private:
  static OdeState derivative(generated::RatesVariant variant, const generated::Constants& constants,
                             const MotorLine& motor, const State& x, double motor_command) {
    const double torque = motorLineTorque(motor, motor_command, x.u1);  // M_m
    // The shortest generated variant that holds every non-zero resistance (a constant in a
    // Bound; otherwise the same branch every call).
    const generated::Rates r =
        generated::ratesFor(variant, constants, x.q1, x.q2, x.u1, x.u2, torque);
    return {x.u1, x.u2, r.u1_dot, r.u2_dot, torque * x.u1, r.dissipated_power};
  }

  generated::Constants constants_;
  MotorLine motor_;
  generated::RatesVariant variant_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_MODEL_GENERATED_MECHANISM_H
