#!/usr/bin/env bash
# Configures and builds kane_sim into _build/ (never build/: rosrun skips <pkg>/build/).
# Usage: scripts/build.sh [extra cmake --build args, e.g. --target all tests]
set -euo pipefail
cd "$(dirname "$0")/.."
mkdir -p _build
cmake -S . -B _build -DCMAKE_BUILD_TYPE=Release \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3 >_build/configure.log 2>&1 ||
  { cat _build/configure.log; exit 1; }
cmake --build _build -j2 "$@" >_build/build.log 2>&1 || { tail -60 _build/build.log; exit 1; }
echo "build: ok (_build/build.log)"
