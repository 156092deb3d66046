#!/usr/bin/env bash
# Pre-release check: builds kane_sim with AddressSanitizer + UndefinedBehaviorSanitizer
# (-fsanitize=address,undefined,float-cast-overflow) outside the package tree and runs the
# ROS-free unit tests, the `simulate` tests and the config fuzzer against that build. Any
# sanitizer report fails it. Not part of scripts/test.sh: a second full build roughly doubles
# the test command's time, and the fuzzer already runs on the normal build there.
# Usage: bash scripts/sanitize.sh [BUILD_DIR]   (default /tmp/kane_sim_sanitize)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-/tmp/kane_sim_sanitize}
bash scripts/install_deps.sh --tests
flags="-fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=all -fno-omit-frame-pointer -g -O1"
mkdir -p "$build"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=address,undefined" \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3 >"$build/configure.log" 2>&1 ||
  { tail -30 "$build/configure.log"; exit 1; }
cmake --build "$build" -j2 --target all tests >"$build/build.log" 2>&1 || { tail -40 "$build/build.log"; exit 1; }
export ASAN_OPTIONS=detect_leaks=0:abort_on_error=1  # leaks: ROS's singletons are never freed
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export ROS_HOSTNAME=localhost
set +u
# shellcheck disable=SC1091
source "$build/devel/setup.bash"
set -u
cd "$build"
ctest --output-on-failure -R "gtest_test_|config_fuzz"
