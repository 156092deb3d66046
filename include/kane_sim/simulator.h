// Fixed-rate time stepping of the mechanism with Boost.Odeint.
//
// One physics step advances sim time by exactly 1/physics_rate. The driver moment M_m is held
// constant over a step (zero-order hold), which also makes the accumulated motor work exact:
// W = Σ M_m Δq1.
#ifndef KANE_SIM_SIMULATOR_H
#define KANE_SIM_SIMULATOR_H

#include <cstdint>
#include <memory>
#include <string>

#include "kane_sim/config.h"
#include "kane_sim/mechanism_model.h"
#include "kane_sim/state.h"

namespace kane_sim {

// Everything a caller may want to publish or log about one instant.
struct MechanismSnapshot {
  double time = 0.0;  // [s] sim time
  State state;
  SpeedVector u_dot = SpeedVector::Zero();           // u1' [rad/s^2], u2' [m/s^2]
  double torque = 0.0;                               // M_m [N m] applied from this instant on
  SpeedVector active_forces = SpeedVector::Zero();   // F_r: F_1 [N m], F_2 [N]
  SpeedVector inertia_forces = SpeedVector::Zero();  // F*_r at u': F*_1 [N m], F*_2 [N]
  EnergyTerms energy;
  double motor_work = 0.0;         // ∫ M_m u1 dt since start or reset [J]
  double motor_power = 0.0;        // M_m u1 [W]
  double spring_elongation = 0.0;  // e [m], positive = stretched
  // x_C - x_B [m]: slider 4 below slider 3 when > 0. The seed models no contact between the
  // sliders, so a hard-driven crank can pull one through the other; each sign change counts.
  double slider_separation = 0.0;
  std::uint64_t slider_crossings = 0;  // since start or reset
};

struct StepResult {
  bool ok = true;
  std::string error;  // why the step was refused; the state is then unchanged
};

class Simulator {
 public:
  explicit Simulator(const Config& config);
  ~Simulator();
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;

  // M_m [N m], held from the next step on until changed. Non-finite values are refused.
  StepResult setTorque(double torque);
  double torque() const { return torque_; }

  // Advances one physics step. A step that would leave a non-finite state (or that the
  // error-controlled integrator cannot complete) is refused and the last good state kept.
  StepResult step();

  // Back to the initial state with motor work 0 and torque 0. Sim time keeps running (it never
  // goes backwards, so tf listeners and bags downstream see a monotonic clock).
  void reset();

  const State& state() const { return state_; }
  double time() const { return static_cast<double>(ticks_) * step_size_; }
  std::uint64_t ticks() const { return ticks_; }
  double stepSize() const { return step_size_; }
  double motorWork() const { return motor_work_; }
  std::uint64_t sliderCrossings() const { return slider_crossings_; }
  // rk4 resolves the motion only while the crank turns well under a tenth of a radian per step
  // (its error grows as (u1 h)^4); past that, energy is no longer conserved. True once the
  // crank has exceeded kMaxCrankAnglePerStep since start or reset; dopri5 refines by itself.
  static constexpr double kMaxCrankAnglePerStep = 0.05;  // [rad]
  bool stepTooCoarse() const { return step_too_coarse_; }
  const MechanismModel& model() const { return model_; }
  const SimulationSettings& settings() const { return settings_; }

  MechanismSnapshot snapshot() const;

 private:
  class Integrator;
  double sliderSeparation(const State& x) const;  // x_C - x_B

  MechanismModel model_;
  SimulationSettings settings_;
  State initial_state_;
  State state_;
  double step_size_;  // [s] 1 / physics_rate
  std::uint64_t ticks_ = 0;
  double torque_ = 0.0;
  double motor_work_ = 0.0;
  std::uint64_t slider_crossings_ = 0;
  bool step_too_coarse_ = false;
  bool continues_ = false;  // the next step starts where the last one ended, same torque
  std::unique_ptr<Integrator> integrator_;
  double slider_separation_;  // x_C - x_B at the current state
};

}  // namespace kane_sim

#endif  // KANE_SIM_SIMULATOR_H
