#!/usr/bin/env bash
# The README's "main job": installs what is missing, builds, and simulates 5 s of the default
# mechanism offline, printing a few rows of the CSV and the energy balance.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install_deps.sh
scripts/build.sh
csv=_build/demo.csv
_build/devel/lib/kane_sim/simulate --config config/mechanism.yaml --duration 5 --torque 0 \
  --output-rate 100 --csv "$csv"
echo "CSV written to $csv ($(($(wc -l <"$csv") - 1)) rows); every 100th row:"
awk -F, 'NR == 1 || (NR - 2) % 100 == 0 { printf "%-6s %-22s %-22s %-22s\n", $1, $2, $3, $6 }' "$csv"
