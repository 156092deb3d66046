#!/usr/bin/env bash
# Configures and builds kane_sim into _build/ (never build/: rosrun skips <pkg>/build/).
# Usage: scripts/build.sh [extra cmake --build args, e.g. --target tests]
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B _build -DCMAKE_BUILD_TYPE=Release \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 -DPython3_EXECUTABLE=/usr/bin/python3 >/dev/null
cmake --build _build -j2 "$@"
