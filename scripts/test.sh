#!/usr/bin/env bash
# The README's test command: installs what is missing, builds, runs every test (unit tests,
# node tests under rostest) and exits non-zero when any test fails or crashes.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
scripts/build.sh --target all tests
# Nodes must resolve their own host name; rostest starts its own master on a free port.
export ROS_HOSTNAME=localhost
set +u  # ROS's setup scripts read unset variables
# shellcheck disable=SC1091
source _build/devel/setup.bash
set -u
rm -rf _build/test_results
cd _build
# ctest is the gate: catkin's run_tests target exits 0 even when tests fail.
ctest --output-on-failure
