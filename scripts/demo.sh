#!/usr/bin/env bash
# The README's "main job": installs what is missing, builds, runs the live demo headless
# (sim + PD controller holding the crank at 1 rad + rosbag record, 10 s), prints where the bag
# is and a short summary.  Usage: scripts/demo.sh [DURATION_S]
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
scripts/build.sh
duration=${1:-10}
bag="$PWD/_build/demo.bag"
export ROS_HOSTNAME=${ROS_HOSTNAME:-localhost}
set +u  # ROS's setup scripts read unset variables
# shellcheck disable=SC1091
source _build/devel/setup.bash
set -u
roslaunch kane_sim demo.launch duration:="$duration" bag:="$bag" setpoint:=1.0 > _build/demo.log 2>&1 ||
  { tail -30 _build/demo.log; exit 1; }
echo "demo finished (log: _build/demo.log)"
scripts/bag_summary "$bag" --setpoint 1.0
