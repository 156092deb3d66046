// The config's choices: each enum once, with its names (indexed by the enum's value) and the noun
// a message uses for it. The loader parses them, the schema lists them, the tools print them, and
// the simulator switches on them: this is their vocabulary, so it belongs to config/.
#ifndef KANE_SIM_CONFIG_CHOICES_H
#define KANE_SIM_CONFIG_CHOICES_H

#include <array>

namespace kane_sim {

// simulation.integrator: rk4, one fixed step; dopri5, error-controlled inside each step.
enum class IntegratorType { kRk4, kDopri5 };
// simulation.equations: which equations of motion the integrators step: the ones generated from
// a SymPy KanesMethod derivation (model/generated_equations.h, the fast path) or the generic Kane
// assembly term by term (model/mechanism_model.h, the readable reference). They agree to rounding.
enum class EquationsSource { kGenerated, kGeneric };
// simulation.lockstep_fallback: without an answer in time, keep the last command or command 0.
enum class LockstepFallback { kHold, kZero };
// command.mode: what the crank's drive is commanded in (ros_control's habits): a torque
// (torque_command), or a speed or an angle (servo_setpoint) that a servo in the drive turns into
// torque at every physics step — through the same torque limit and motor line.
enum class CommandMode { kEffort, kVelocity, kPosition };
// command.feedforward: none, or the moment that holds gravity and the spring where the crank is.
enum class Feedforward { kNone, kHolding };

// Choice<E>::names[static_cast<int>(e)] is e's name in the config; noun names E in messages.
template <class E>
struct Choice;
template <>
struct Choice<IntegratorType> {
  static constexpr std::array<const char*, 2> names = {"rk4", "dopri5"};
  static constexpr const char* noun = "an unknown integrator";
};
template <>
struct Choice<EquationsSource> {
  static constexpr std::array<const char*, 2> names = {"generated", "generic"};
  static constexpr const char* noun = "unknown equations";
};
template <>
struct Choice<LockstepFallback> {
  static constexpr std::array<const char*, 2> names = {"hold", "zero"};
  static constexpr const char* noun = "an unknown lockstep fallback";
};
template <>
struct Choice<CommandMode> {
  static constexpr std::array<const char*, 3> names = {"effort", "velocity", "position"};
  static constexpr const char* noun = "an unknown command mode";
};
template <>
struct Choice<Feedforward> {
  static constexpr std::array<const char*, 2> names = {"none", "holding"};
  static constexpr const char* noun = "an unknown feedforward";
};

template <class E>
constexpr const char* choiceName(E value) {
  return Choice<E>::names[static_cast<int>(value)];
}
constexpr const char* integratorName(IntegratorType t) { return choiceName(t); }
constexpr const char* equationsName(EquationsSource s) { return choiceName(s); }
constexpr const char* lockstepFallbackName(LockstepFallback f) { return choiceName(f); }
constexpr const char* commandModeName(CommandMode m) { return choiceName(m); }
constexpr const char* feedforwardName(Feedforward f) { return choiceName(f); }

}  // namespace kane_sim

#endif  // KANE_SIM_CONFIG_CHOICES_H
