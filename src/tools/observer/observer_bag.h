// `observer --bag`: a recorded rig's joint_states through the estimator, offline (no master).
#ifndef KANE_SIM_TOOLS_OBSERVER_OBSERVER_BAG_H
#define KANE_SIM_TOOLS_OBSERVER_OBSERVER_BAG_H

namespace kane_sim {

// True when the command line asks for the offline replay (it holds --bag).
bool wantsBagReplay(int argc, char** argv);
// The replay's main: exit codes 0 ok, 1 bad config, 2 bad command line, 3 the bag cannot be
// read, 4 the output cannot be written, 130 / 143 stopped by SIGINT / SIGTERM (the rows so far
// written).
int runBagReplay(int argc, char** argv);

}  // namespace kane_sim

#endif  // KANE_SIM_TOOLS_OBSERVER_OBSERVER_BAG_H
