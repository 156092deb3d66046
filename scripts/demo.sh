#!/usr/bin/env bash
# The README's "main job": installs what is missing, builds, runs the live demo headless
# (sim + PD controller holding the crank at 1 rad + rosbag record from the initial state, 10 s),
# prints where the bag is and a short summary.  Usage: bash scripts/demo.sh [DURATION_S]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh
# shellcheck source=scripts/build_dir.sh
source scripts/build_dir.sh
duration=${1:-10}
bag="$KANE_SIM_BUILD_DIR/demo.bag"
log="$KANE_SIM_BUILD_DIR/demo.log"
export ROS_HOSTNAME=${ROS_HOSTNAME:-localhost}
set +u  # ROS's setup scripts read unset variables
# shellcheck disable=SC1091
source "$KANE_SIM_BUILD_DIR/devel/setup.bash"
set -u
roslaunch kane_sim demo.launch duration:="$duration" bag:="$bag" setpoint:=1.0 > "$log" 2>&1 ||
  { tail -30 "$log"; exit 1; }
echo "demo finished (log: $log)"
rosrun kane_sim bag_summary "$bag" --setpoint 1.0
