// The textbook example's mechanism in MuJoCo (Debian's libmujoco-dev), from the same config:
// the peer of bench/bench_peers.cpp. MuJoCo works in maximal-ish (joint) coordinates with the
// loop closed by an equality constraint, so the mechanism is an open chain O -> rod 1 -> rod 2
// plus the two sliders on their own rails, and rod 2's end B is tied to slider 3 by a `connect`
// constraint (soft: solref/solimp); the spring is a fixed tendon on the sliders' joints with
// stiffness k whose rest length is its length at their springref (x_B0, x_C0). Gravity along +x,
// the textbook's down-pointing i. No geoms, no contacts: inertias are given explicitly.
#ifndef KANE_SIM_BENCH_MUJOCO_MECHANISM_H
#define KANE_SIM_BENCH_MUJOCO_MECHANISM_H

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include <mujoco/mujoco.h>

#include "kane_sim/config/config.h"
#include "kane_sim/description/joint_values.h"

namespace kane_sim {
namespace bench {

// The config's initial state as the four joints (the peers' joint coordinates are these).
inline JointValues initialJoints(const Config& c) {
  const MechanismModel model = mechanismModel(c);
  return jointValues(model.kinematics(c.initial_state), c.initial_state, 0.0);
}

// How hard the loop closure is enforced: MuJoCo's defaults, or as stiff as its integrator
// safety allows at this time step (solref time constant 2 dt, impedance near 1).
enum class LoopClosure { kMujocoDefault, kStiff };

inline std::string mechanismMjcf(const Config& c, double dt, LoopClosure closure) {
  const MechanismParameters& p = c.mechanism;
  const double L = p.rod_half_length;
  const double x_b0 = initialJoints(c).position[kSlider3Joint];
  std::ostringstream x;
  x.precision(17);
  const std::string eq_params =
      closure == LoopClosure::kStiff
          ? " solref=\"" + std::to_string(2 * dt) + " 1\" solimp=\"0.9999 0.9999 0.001\""
          : "";
  x << "<mujoco model=\"kane_sim textbook example\">\n"
    << "  <option timestep=\"" << dt << "\" integrator=\"RK4\" gravity=\"" << p.gravity
    << " 0 0\"/>\n"
    << "  <worldbody>\n"
    // Rod 1 (OA): hinge at O about z; mass center at L along its own x.
    << "    <body name=\"rod1\">\n"
    << "      <joint name=\"crank\" type=\"hinge\" axis=\"0 0 1\"/>\n"
    << "      <inertial pos=\"" << L << " 0 0\" mass=\"" << p.rod_mass << "\" diaginertia=\"1e-9 "
    << p.rod_inertia << " " << p.rod_inertia
    << "\"/>\n"
    // Rod 2 (AB): hinge at A, its angle relative to rod 1 (-2 q1 when B is on the rail).
    << "      <body name=\"rod2\" pos=\"" << 2 * L << " 0 0\">\n"
    << "        <joint name=\"coupler\" type=\"hinge\" axis=\"0 0 1\"/>\n"
    << "        <inertial pos=\"" << L << " 0 0\" mass=\"" << p.rod_mass << "\" diaginertia=\"1e-9 "
    << p.rod_inertia << " " << p.rod_inertia << "\"/>\n"
    << "        <site name=\"rod2_end\" pos=\"" << 2 * L << " 0 0\"/>\n"
    << "      </body>\n"
    << "    </body>\n"
    // The sliders: particles on the x rail, springref at the initial configuration. MuJoCo
    // places connect's anchor on body 2 where it is in the reference configuration (qpos = 0,
    // both rods along x, B at 4L): slider 3's body sits there, its qpos is x_B - 4L.
    << "    <body name=\"slider3\" pos=\"" << 4 * L << " 0 0\">\n"
    << "      <joint name=\"slider3\" type=\"slide\" axis=\"1 0 0\" springref=\"" << x_b0 - 4 * L
    << "\"/>\n"
    << "      <inertial pos=\"0 0 0\" mass=\"" << p.slider3_mass
    << "\" diaginertia=\"1e-9 1e-9 1e-9\"/>\n"
    << "      <site name=\"slider3\"/>\n"
    << "    </body>\n"
    << "    <body name=\"slider4\">\n"
    << "      <joint name=\"slider4\" type=\"slide\" axis=\"1 0 0\" springref=\""
    << c.initial_state.q2 << "\"/>\n"
    << "      <inertial pos=\"0 0 0\" mass=\"" << p.slider4_mass
    << "\" diaginertia=\"1e-9 1e-9 1e-9\"/>\n"
    << "    </body>\n"
    << "  </worldbody>\n"
    << "  <equality>\n"
    << "    <connect body1=\"rod2\" body2=\"slider3\" anchor=\"" << 2 * L << " 0 0\"" << eq_params
    << "/>\n"
    << "  </equality>\n"
    << "  <tendon>\n"
    << "    <fixed name=\"spring\" stiffness=\"" << p.spring_stiffness << "\">\n"
    << "      <joint joint=\"slider4\" coef=\"1\"/>\n"
    << "      <joint joint=\"slider3\" coef=\"-1\"/>\n"
    << "    </fixed>\n"
    << "  </tendon>\n"
    << "  <actuator>\n"
    << "    <motor name=\"crank_motor\" joint=\"crank\" gear=\"1\"/>\n"
    << "  </actuator>\n"
    << "</mujoco>\n";
  return x.str();
}

// A loaded model and its data, set to the config's initial state.
class MujocoMechanism {
 public:
  MujocoMechanism(const Config& c, double dt, LoopClosure closure) {
    char path[] = "/tmp/kane_sim_mechanism_XXXXXX.xml";
    const int fd = mkstemps(path, 4);
    if (fd < 0) throw std::runtime_error("cannot create a temporary MJCF file");
    close(fd);
    std::ofstream(path) << mechanismMjcf(c, dt, closure);
    char error[1000] = "";
    model_ = mj_loadXML(path, nullptr, error, sizeof(error));
    std::remove(path);
    if (!model_) throw std::runtime_error(std::string("MuJoCo refused the model: ") + error);
    data_ = mj_makeData(model_);
    // The MJCF's joints are joint_states' four, in that order; slider 3's body sits at 4L.
    const JointValues j = initialJoints(c);
    for (int i = 0; i < kNumJoints; ++i) {
      data_->qpos[model_->jnt_qposadr[i]] = j.position[i];
      data_->qvel[model_->jnt_dofadr[i]] = j.velocity[i];
    }
    data_->qpos[model_->jnt_qposadr[kSlider3Joint]] -= 4 * c.mechanism.rod_half_length;
    mj_forward(model_, data_);
  }
  ~MujocoMechanism() {
    mj_deleteData(data_);
    mj_deleteModel(model_);
  }
  MujocoMechanism(const MujocoMechanism&) = delete;
  MujocoMechanism& operator=(const MujocoMechanism&) = delete;

  void setTorque(double torque) { data_->ctrl[0] = torque; }
  void step() { mj_step(model_, data_); }
  double q1() const { return data_->qpos[model_->jnt_qposadr[kCrankJoint]]; }
  double q2() const { return data_->qpos[model_->jnt_qposadr[kSlider4Joint]]; }
  double time() const { return data_->time; }
  // |B on rod 2 - slider 3| [m]: how far the soft constraint lets the loop open.
  double loopClosureError() const {
    const double* a = data_->site_xpos + 3 * 0;  // rod2_end
    const double* b = data_->site_xpos + 3 * 1;  // slider3
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                     (a[2] - b[2]) * (a[2] - b[2]));
  }

 private:
  mjModel* model_ = nullptr;
  mjData* data_ = nullptr;
};

}  // namespace bench
}  // namespace kane_sim

#endif  // KANE_SIM_BENCH_MUJOCO_MECHANISM_H
