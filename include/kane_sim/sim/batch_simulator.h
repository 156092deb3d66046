// Many mechanisms stepped together for learning loops and Monte Carlo: lane i is a single
// SimDriver of configs[i] that receives action i (set_torque, or the servo's setpoint) and then
// steps; every lane is that driver's run bit for bit. Cases that SIMD lanes run as their single
// run would (batch/lanes.h: rk4, generated equations, effort mode, no contact, motor line,
// command latency or sensors, one physics rate) step W at a time there; the rest step as
// drivers. A lane whose step is refused or whose sliders cross stops (terminated, with the
// reason) until it is reset: reported, never thrown.
#ifndef KANE_SIM_SIM_BATCH_SIMULATOR_H
#define KANE_SIM_SIM_BATCH_SIMULATOR_H

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "kane_sim/batch/lanes.h"
#include "kane_sim/config/config.h"
#include "kane_sim/model/state.h"
#include "kane_sim/sim/sim_driver.h"
#include "kane_sim/sim/worker_pool.h"

namespace kane_sim {

struct BatchSettings {
  std::string simd = "auto";  // an instruction set (parseLaneArch), or "off": drivers only
  bool vector_trig = false;   // SIMD lanes with xsimd's sin/cos (not the single run's bits)
  int threads = 1;            // lanes split over this many threads per step (>= 1)
};

class BatchSimulator {
 public:
  // One config per lane (validated); throws std::invalid_argument naming a bad setting.
  BatchSimulator(std::vector<Config> configs, const BatchSettings& settings);
  ~BatchSimulator();

  std::size_t size() const { return configs_.size(); }
  // Mechanism `lane`'s config (with the sensors.seed a reseed gave it).
  const Config& config(std::size_t lane) const { return configs_[lane]; }
  // "avx512 lanes", "drivers (command.mode is position)", ...: how lanes step, and why.
  const std::string& path() const { return path_; }
  bool onLanes() const { return on_lanes_; }
  unsigned threads() const { return static_cast<unsigned>(settings_.threads); }

  // Each running lane i takes actions[i] (a torque [N m], or in servo modes a setpoint) and
  // steps `steps` physics steps, as a single Simulator's set_torque then step(steps) (the
  // command re-sent within command.timeout); terminated lanes stay as they are. Refused before
  // anything moves (std::invalid_argument naming the lane and value): a non-finite action (of
  // any lane), steps < 1, a setpoint the servo refuses. `active` (when not null): only lanes
  // with active[i] step. `stop` (when not null) is checked at every step (drivers) or every 256
  // (lanes): set, each lane ends where it is; returns false then. `states_out` (when not null):
  // every lane's state after the call, as states() writes it (on lanes, by the threads that
  // stepped them: no serial pass after the step).
  bool step(const double* actions, long steps, const std::vector<bool>* active = nullptr,
            const std::atomic<bool>* stop = nullptr, double* states_out = nullptr);

  // Lanes with mask[i] back to their initial state (the driver's reset: sim time runs on), or
  // with seeds rebuilt from their config with sensors.seed = seeds[i] (time 0 again).
  void reset(const std::vector<bool>& mask);
  void reseed(const std::vector<bool>& mask, const std::vector<std::uint64_t>& seeds);
  // Mechanisms lanes[k] take configs[k] (validated by the loader) and start afresh from it, as
  // reseed: its initial state (or starts[k] when given), time 0, running again (domain
  // randomisation between episodes at the cost of the mechanisms that change). Throws
  // std::invalid_argument, changing nothing, naming the mechanism, when a config would take it
  // off the SIMD lanes the batch runs on or its new config refuses starts[k].
  void reconfigure(const std::vector<std::size_t>& lanes, const std::vector<Config>& configs,
                   const std::vector<State>* starts = nullptr);
  // Whether lane `lane` can be put into `state`: what a Simulator of its config's set_state
  // accepts (finite, within scale, the sliders apart, within rk4's reach at this step).
  Status checkState(std::size_t lane, const State& state) const;
  // Lane `lane` put into `state` (a Simulator's set_state: an episode started anywhere), running
  // again; its time runs on. Refused (nothing changes; the reason names the state) unless
  // checkState accepts it.
  Status setState(std::size_t lane, const State& state);

  State state(std::size_t lane) const;
  // Every lane's q1, q2, u1, u2 into out[4 i .. 4 i + 3] (size() rows): state(i) for each, in
  // one pass over the lanes path's chunks.
  void states(double* out) const;
  double time(std::size_t lane) const;
  bool terminated(std::size_t lane) const { return terminated_[lane] != 0; }
  const std::string& reason(std::size_t lane) const { return lanes_[lane].reason; }
  // With sensors: the last reading that reached the lane's joint_states (the true joints at
  // the start until the first arrives): positions and velocities of crank, coupler, slider 3,
  // slider 4.
  // (The lanes path has no sensors: its reading stays the empty one.)
  const JointValues& reading(std::size_t lane) const {
    static const JointValues kNone{};
    return readings_.empty() ? kNone : readings_[lane];
  }
  bool sensorsEnabled() const { return sensors_; }

 private:
  // What a step seldom touches. A call of one physics step reads and writes per lane only the
  // dense arrays (terminated_, a chunk's states and clocks): a strided walk over these cost
  // ~10 ns a mechanism a call in cache misses.
  struct Lane {
    std::size_t chunk = 0, slot = 0;  // the lanes path: the lane is chunks_[chunk]'s slot-th
    std::string reason;
    std::unique_ptr<SimDriver> driver;  // the drivers path
  };
  void buildDriver(std::size_t lane, const Config& config);
  // The lanes path's chunks for lanes of these constants (one per lane), each lane's state and
  // clock taken from `states` and `ticks` (one per lane).
  void layoutLanes(const std::vector<generated::Constants>& constants,
                   const std::vector<LaneState>& states, const std::vector<std::uint64_t>& ticks);
  void resetLane(std::size_t lane);
  // The lanes path's state of `lane` (q1, q2, u1, u2, W, D) and its clock [physics steps].
  OdeState& laneState(std::size_t lane) {
    return chunks_[lanes_[lane].chunk].run.start[lanes_[lane].slot];
  }
  const OdeState& laneState(std::size_t lane) const {
    return chunks_[lanes_[lane].chunk].run.start[lanes_[lane].slot];
  }
  std::uint64_t& laneTicks(std::size_t lane) {
    return chunks_[lanes_[lane].chunk].ticks[lanes_[lane].slot];
  }
  std::uint64_t laneTicks(std::size_t lane) const {
    return chunks_[lanes_[lane].chunk].ticks[lanes_[lane].slot];
  }
  // Why lane `lane`'s step from x under `action` was refused, in a single run's words.
  std::string refusalText(std::size_t lane, const State& x, double action) const;
  bool stepping(std::size_t lane) const {
    return !terminated_[lane] && (!active_ || (*active_)[lane]);
  }
  void stepDrivers(const double* actions, long steps, std::size_t begin, std::size_t end);
  void stepLanes(const double* actions, long steps, std::size_t chunk, double* states_out);
  template <class F>
  void parallel(std::size_t count, const F& work);

  std::vector<Config> configs_;
  BatchSettings settings_;
  std::vector<Lane> lanes_;
  std::vector<char> terminated_;       // per lane: its first refused step or crossing has ended it
  std::vector<JointValues> readings_;  // the drivers path: per lane, as reading() says
  bool on_lanes_ = false;
  bool sensors_ = false;
  LaneArch arch_ = LaneArch::kScalar;
  std::string path_;
  double step_size_ = 0.0;
  // The lanes path: lanes grouped by equations variant (damped or not), each group cut into one
  // chunk per thread; a chunk's LaneRun holds its constants once and its lanes' states (run.start,
  // slot k the state of lane members[k]: q1, q2, u1, u2, W, D), stepped in place.
  struct Chunk {
    std::vector<std::size_t> members;
    LaneRun run;
    std::vector<std::uint64_t> ticks;   // per slot: the lane's clock (physics steps)
    std::vector<LaneOutcome> outcomes;  // per slot: the last call's, kept to spare an allocation
  };
  std::vector<Chunk> chunks_;
  const std::vector<bool>* active_ = nullptr;  // during step()
  const std::atomic<bool>* stop_ = nullptr;    // during step()
  // settings_.threads workers, started once: a call of one physics step starts no thread.
  std::unique_ptr<WorkerPool> pool_;
};

}  // namespace kane_sim

#endif  // KANE_SIM_SIM_BATCH_SIMULATOR_H
