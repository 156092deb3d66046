// The textbook example's mechanism in Simbody (Debian's libsimbody-dev), from the same config:
// the accuracy peer of bench/bench_peers.cpp. Simbody also works in joint coordinates with the
// loop closed by constraints, but enforces them exactly (constraint projection to a tolerance),
// unlike MuJoCo's soft constraints. Rod 1 pinned to ground at O, rod 2 pinned to rod 1 at A,
// each slider on its own slider mobilizer along x; rod 2's end B is held on slider 3 by two
// point-in-plane constraints (y_B = 0, x_B = x_3); the spring is a two-point linear spring
// between the sliders (rest length x_C0 - x_B0); gravity along +x; the motor a constant
// mobility force on rod 1's pin. Integrated with Runge-Kutta-Merson at a set accuracy.
#ifndef KANE_SIM_BENCH_SIMBODY_MECHANISM_H
#define KANE_SIM_BENCH_SIMBODY_MECHANISM_H

#include <memory>

#include <Simbody.h>

#include "kane_sim/config/config.h"
#include "kane_sim/description/joint_values.h"

namespace kane_sim {
namespace bench {

class SimbodyMechanism {
 public:
  SimbodyMechanism(const Config& c, double torque, double accuracy)
      : L_(c.mechanism.rod_half_length), matter_(system_), forces_(system_) {
    using SimTK::Vec3;
    const MechanismParameters& p = c.mechanism;
    const double L = p.rod_half_length;
    SimTK::Force::UniformGravity(forces_, matter_, Vec3(p.gravity, 0, 0));
    // A rod along its own x from its pin, mass center at L: inertia about the pin.
    const double tiny = 1e-9;  // the rods' and sliders' unused moments (planar motion)
    const SimTK::MassProperties rod(p.rod_mass, Vec3(L, 0, 0),
                                    SimTK::Inertia(tiny, p.rod_inertia + p.rod_mass * L * L,
                                                   p.rod_inertia + p.rod_mass * L * L));
    rod1_ = SimTK::MobilizedBody::Pin(matter_.Ground(), SimTK::Transform(), SimTK::Body::Rigid(rod),
                                      SimTK::Transform());
    rod2_ = SimTK::MobilizedBody::Pin(rod1_, SimTK::Transform(Vec3(2 * L, 0, 0)),
                                      SimTK::Body::Rigid(rod), SimTK::Transform());
    const auto point_mass = [tiny](double mass) {
      return SimTK::Body::Rigid(SimTK::MassProperties(mass, Vec3(0), SimTK::Inertia(tiny)));
    };
    slider3_ = SimTK::MobilizedBody::Slider(matter_.Ground(), SimTK::Transform(),
                                            point_mass(p.slider3_mass), SimTK::Transform());
    slider4_ = SimTK::MobilizedBody::Slider(matter_.Ground(), SimTK::Transform(),
                                            point_mass(p.slider4_mass), SimTK::Transform());
    SimTK::Constraint::PointInPlane(matter_.Ground(), SimTK::UnitVec3(0, 1, 0), 0.0, rod2_,
                                    Vec3(2 * L, 0, 0));
    SimTK::Constraint::PointInPlane(slider3_, SimTK::UnitVec3(1, 0, 0), 0.0, rod2_,
                                    Vec3(2 * L, 0, 0));
    const MechanismModel model = mechanismModel(c);
    SimTK::Force::TwoPointLinearSpring(forces_, slider3_, Vec3(0), slider4_, Vec3(0),
                                       p.spring_stiffness, model.springRestLength());
    SimTK::Force::MobilityConstantForce(forces_, rod1_, SimTK::MobilizerUIndex(0), torque);
    system_.realizeTopology();

    // The mobilizers' coordinates are joint_states' four joints.
    SimTK::State state = system_.getDefaultState();
    const JointValues j = jointValues(model.kinematics(c.initial_state), c.initial_state, 0.0);
    const SimTK::MobilizedBody* mobilizers[kNumJoints] = {&rod1_, &rod2_, &slider3_, &slider4_};
    for (int i = 0; i < kNumJoints; ++i) {
      mobilizers[i]->setOneQ(state, 0, j.position[i]);
      mobilizers[i]->setOneU(state, 0, j.velocity[i]);
    }
    integrator_ = std::make_unique<SimTK::RungeKuttaMersonIntegrator>(system_);
    integrator_->setAccuracy(accuracy);
    integrator_->setConstraintTolerance(accuracy * 1e-2);
    stepper_ = std::make_unique<SimTK::TimeStepper>(system_, *integrator_);
    stepper_->initialize(state);
  }

  void advanceTo(double t) { stepper_->stepTo(t); }
  double q1() const { return rod1_.getOneQ(state(), 0); }
  double q2() const { return slider4_.getOneQ(state(), 0); }
  // |B on rod 2 - slider 3| [m].
  double loopClosureError() const {
    system_.realize(state(), SimTK::Stage::Position);
    const SimTK::Vec3 b = rod2_.findStationLocationInGround(state(), SimTK::Vec3(2 * L_, 0, 0));
    const SimTK::Vec3 s = slider3_.getBodyOriginLocation(state());
    return (b - s).norm();
  }

 private:
  const SimTK::State& state() const { return integrator_->getState(); }

  double L_;  // [m] rod half length
  SimTK::MultibodySystem system_;
  SimTK::SimbodyMatterSubsystem matter_;
  SimTK::GeneralForceSubsystem forces_;
  SimTK::MobilizedBody::Pin rod1_, rod2_;
  SimTK::MobilizedBody::Slider slider3_, slider4_;
  std::unique_ptr<SimTK::RungeKuttaMersonIntegrator> integrator_;
  std::unique_ptr<SimTK::TimeStepper> stepper_;
};

}  // namespace bench
}  // namespace kane_sim

#endif  // KANE_SIM_BENCH_SIMBODY_MECHANISM_H
