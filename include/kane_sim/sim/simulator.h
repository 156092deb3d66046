// Fixed-rate time stepping of the mechanism with Boost.Odeint.
//
// One physics step advances sim time by exactly 1/physics_rate. The commanded driver moment is
// held constant over a step (zero-order hold); what the drive delivers may still vary within
// it (the motor line). The energy ledger's motor work W and dissipated energy D are integrated
// with the motion (model's stateDerivative), so E + D - W is constant to the integrator's order.
// With contact on, a step in which the sliders close to the gap is split at the instant of
// touch (found by bisection), the impact applied there (its loss added to D), and the rest of
// the step integrated: the separation never falls below the gap at a step's end.
#ifndef KANE_SIM_SIM_SIMULATOR_H
#define KANE_SIM_SIM_SIMULATOR_H

#include <cstdint>
#include <memory>
#include <string>

#include "kane_sim/config/config.h"
#include "kane_sim/model/generated_mechanism.h"
#include "kane_sim/model/mechanism_model.h"
#include "kane_sim/model/state.h"
#include "kane_sim/sim/snapshot.h"

namespace kane_sim {

// The outcome of a call that may refuse its input; `error` says why (nothing changed then).
struct Status {
  bool ok = true;
  std::string error;
};

class Simulator {
 public:
  explicit Simulator(const Config& config);
  ~Simulator();
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;

  // M_m [N m], held from the next step on until changed. Non-finite values are refused.
  Status setTorque(double torque);
  double torque() const { return torque_; }

  // Advances one physics step. A step that would leave a non-finite state (or that the
  // error-controlled integrator cannot complete) is refused and the last good state kept.
  Status step();

  // Back to the initial state with motor work 0 and torque 0. Sim time keeps running (it never
  // goes backwards, so tf listeners and bags downstream see a monotonic clock).
  void reset();

  // Puts the mechanism into `state` (like reset, to a chosen state): motor work, dissipated
  // energy, crossings and impacts 0; the torque in force and the spring's rest length are kept.
  // Refused (naming the field and the value; nothing changes) unless checkState accepts it.
  Status setState(const State& state);
  // Whether the mechanism can be put into `state`: finite values, q1 within kMaxCrankAngle, a
  // finite energy and finite u', the sliders at least contact.gap apart when contact is on, and
  // with rk4 the motion's fastest rate there within rk4's stability at this step size.
  Status checkState(const State& state) const;
  // The part of checkState that holds whatever the integrator: finite values within scale, q1
  // within kMaxCrankAngle, finite energy and u', the sliders apart when contact is on. The one
  // check of a state: set_state, and the config's initial state (sim/config_check.h).
  Status checkUsable(const State& state) const;
  // "q1 = 0.5, q2 = 1.2, u1 = 0, u2 = 0": how refusals name a state.
  static std::string stateText(const State& state);
  static constexpr double kMaxCrankAngle = 2 * M_PI * 1e6;  // [rad] a million turns

  // New physical parameters from the next step on, at the current state (the spring's rest
  // length is kept). The total energy E jumps at that instant; the jump is added to
  // parameter_energy so that E - W - parameter_energy stays the conserved quantity.
  void setParameters(const MechanismParameters& parameters);

  const State& state() const { return state_; }
  double time() const { return static_cast<double>(ticks_) * step_size_; }
  std::uint64_t ticks() const { return ticks_; }
  double stepSize() const { return step_size_; }
  double motorWork() const { return motor_work_; }
  double dissipatedEnergy() const { return dissipated_energy_; }
  double impactEnergy() const { return impact_energy_; }  // [J] the impacts' share of D
  std::uint64_t sliderCrossings() const { return slider_crossings_; }
  std::uint64_t contactImpacts() const { return contact_impacts_; }
  // With contact on, at most this many contact events (impacts, the start or the end of a
  // resting contact) are resolved within one physics step; a step that needs more is refused
  // with the reason (never accepted with the sliders inside the gap).
  static constexpr int kMaxContactEventsPerStep = 16;
  // dopri5 gives up on a physics step after this many rejected or accepted sub-steps; reaching
  // it means the tolerances ask for more than double precision can give at this state.
  static constexpr int kMaxSubstepsPerTick = 100000;
  // True while the sliders rest on each other (contact on): held at the gap by the constraint
  // force of Kane's equations until that force would pull.
  bool restingContact() const { return resting_contact_; }
  // rk4 resolves the motion only while the crank turns well under a tenth of a radian per step
  // (its error grows as (u1 h)^4); past that, energy is no longer conserved. True once the
  // crank has exceeded kMaxCrankAnglePerStep since start or reset; dopri5 refines by itself.
  static constexpr double kMaxCrankAnglePerStep = 0.05;  // [rad]
  // Past this rk4 does not integrate the motion at all: a step that would reach it is refused.
  static constexpr double kMaxCrankTurnPerStep = 1.0;  // [rad]
  // Why a step that would turn the crank further is refused (rk4), in the words every path uses.
  static constexpr const char* kCrankTurnRefusal =
      "the crank would turn more than 1 rad in one rk4 step, which rk4 cannot resolve (use "
      "simulation.integrator dopri5 or a higher simulation.physics_rate)";
  bool stepTooCoarse() const { return step_too_coarse_; }
  const MechanismModel& model() const { return model_; }
  EquationsSource equations() const { return equations_; }
  // f(equations) with the equations the integrators step: the GeneratedMechanism or the
  // MechanismModel (both have stateDerivative(x, torque)). The one place that picks.
  template <class F>
  decltype(auto) withEquations(F&& f) const {
    return equations_ == EquationsSource::kGenerated ? f(generated_) : f(model_);
  }

  // Everything a step depends on beyond the config (sim/checkpoint.h writes it down): restored
  // into a Simulator built from the same config, the two step alike, bit for bit.
  struct Dynamics {
    State state;
    std::uint64_t ticks = 0;
    double torque = 0.0, motor_work = 0.0, dissipated_energy = 0.0, impact_energy = 0.0,
           parameter_energy = 0.0;
    std::uint64_t slider_crossings = 0, contact_impacts = 0, parameter_changes = 0;
    bool step_too_coarse = false, slider4_below = false, resting_contact = false;
    double dopri5_substep = 0.0;  // [s] dopri5's step size suggestion for the next tick
  };
  Dynamics dynamics() const;
  void restore(const Dynamics& dynamics);

  // The physics of this instant (command fields left at their defaults: see SimDriver).
  Snapshot snapshot() const;
  // The joints alone (what a sensor samples): the snapshot's joint values, cheaper.
  JointValues joints() const;

 private:
  class Integrator;
  template <class Equations>
  Status stepWith(const Equations& equations);
  template <class Equations>
  const char* advanceThroughContact(const Equations& equations, OdeState* x);
  template <class System>
  const char* advanceChecked(const System& system, OdeState* x, double t, double span,
                             bool reuse_derivative);
  // x_C - x_B >= threshold at x (the cosine only when q2's bounds leave it open).
  bool separationAtLeast(const OdeState& x, double threshold) const;
  // q2, u2 of x set from q1, u1 on the resting contact (MechanismModel::onContact).
  void putOnContact(OdeState* x) const;
  template <class Equations>
  RestingContact restingContactAt(const Equations& equations, const State& held) const;
  // The sliders at the gap, approaching: an impact, or the start of a resting contact.
  template <class Equations>
  void touch(const Equations& equations, OdeState* x);
  template <class System, class Holds>
  double lastInstantWhere(const System& system, OdeState x, double t, double span,
                          const Holds& holds, OdeState* at);

  MechanismModel model_;
  GeneratedMechanism generated_;  // the same model as generated equations: the fast path
  EquationsSource equations_;     // which of the two the integrators step
  IntegratorType integrator_type_;
  State initial_state_;
  State state_;
  double step_size_;  // [s] 1 / physics_rate
  std::uint64_t ticks_ = 0;
  double torque_ = 0.0;
  double motor_work_ = 0.0;          // W [J]
  double dissipated_energy_ = 0.0;   // D [J]
  double impact_energy_ = 0.0;       // [J] the slider impacts' share of D
  double step_impact_energy_ = 0.0;  // that of the step being taken (booked when it is accepted)
  std::uint64_t slider_crossings_ = 0;
  std::uint64_t contact_impacts_ = 0;
  bool step_too_coarse_ = false;
  // dopri5 may start the next step from the derivative it ended the last one with ("first same
  // as last") only while the state is where it left it and the torque is unchanged.
  bool last_derivative_valid_ = false;
  std::unique_ptr<Integrator> integrator_;
  bool slider4_below_;  // x_C - x_B >= 0 at the current state (crossings count its changes)
  bool resting_contact_ = false;
  bool resting_contact_at_start_of_step_ = false;  // restored when a step is refused
  double parameter_energy_ = 0.0;
  std::uint64_t parameter_changes_ = 0;
};

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_SIMULATOR_H
