#!/usr/bin/env bash
# Configures and builds kane_sim into the build folder beside the checkout (scripts/build_dir.sh:
# build-<checkout>, or $KANE_SIM_BUILD_DIR). Then: source <that folder>/devel/setup.bash.
# Usage: scripts/build.sh [extra cmake --build args, e.g. --target all tests]
set -euo pipefail
# shellcheck source=scripts/build_dir.sh
source "$(dirname "$0")/build_dir.sh"
cd "$KANE_SIM_SOURCE_DIR"
build=$KANE_SIM_BUILD_DIR
mkdir -p "$build"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3 >"$build/configure.log" 2>&1 ||
  { cat "$build/configure.log"; exit 1; }
cmake --build "$build" -j2 "$@" >"$build/build.log" 2>&1 || { tail -60 "$build/build.log"; exit 1; }
echo "build: ok in $build (log: $build/build.log)"
# The browser twin into $build/web (when emscripten is installed).
bash "$KANE_SIM_SOURCE_DIR/scripts/build_web.sh"
