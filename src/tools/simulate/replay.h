// `simulate --replay BAG`: the inputs a node logged on ~input_log (torque commands, servo
// setpoints, resets, set_state, each with the physics tick it arrived at) fed to the driver at the
// same ticks, and every mechanism_state of the bag compared with the replayed state at its sim
// time. The driver starts at the bag's first ~checkpoint (its config and state; a recording may
// begin mid-run) and restarts from each later one (resets, reconfigurations, every 10 s); a bag
// without checkpoints starts a fresh driver of --config at t = 0. A bag of the node replays bit for
// bit: the node steps the same driver, and what arrives between two ticks is applied before the
// second, in both.
#ifndef KANE_SIM_TOOLS_SIMULATE_REPLAY_H
#define KANE_SIM_TOOLS_SIMULATE_REPLAY_H

#include <atomic>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "kane_sim/config/config.h"

namespace simulate {

struct ReplayError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct ReplayResult {
  std::uint64_t inputs = 0;     // inputs fed to the driver
  std::uint64_t compared = 0;   // mechanism_state messages compared
  std::uint64_t skipped = 0;    // at a tick with a reset or set_state (the bag holds both sides)
  double largest = 0.0;         // largest |difference| of q1, q2, u1, u2
  double largest_at = 0.0;      // [s] sim time of the first largest difference
  const char* largest_of = "";  // which of q1, q2, u1, u2
  std::uint64_t parameter_changes = 0;        // runtime reconfigurations in the bag (not replayed)
  std::uint64_t inputs_after_last_state = 0;  // recorded after the last state: not replayed
  bool interrupted = false;                   // `stop` was set: compared up to there
  double interrupted_at = 0.0;                // [s] the replay's sim time then
  std::uint64_t start_tick = 0;               // where it began: 0, or the first checkpoint's
  std::uint64_t resynchronised = 0;           // later checkpoints the replay restarted from
  std::uint64_t checkpoints_passed_over = 0;  // earlier ones whose next input is missing
  // Inputs the bag lacks after the start (rosbag filter, a dropped connection): each gap named
  // ("inputs 120-129 of /kane_sim/input_log were not recorded (a gap in the bag) ..."); the
  // states from the last input before a gap to the next checkpoint after it were not compared.
  std::vector<std::string> gaps;
  std::uint64_t uncompared = 0;                            // states in those stretches
  std::string input_topic, state_topic, checkpoint_topic;  // the last "" without checkpoints
};

// Throws ReplayError naming what the bag lacks or what is wrong with it (no input log, no
// states, several sims, inputs not recorded, states at impossible times or with NaN). Stops
// (result.interrupted) when `stop` is set, checked before every step.
ReplayResult replayBag(const std::string& bag_path, const kane_sim::Config& config,
                       const std::atomic<bool>* stop = nullptr);

}  // namespace simulate

#endif  // KANE_SIM_TOOLS_SIMULATE_REPLAY_H
