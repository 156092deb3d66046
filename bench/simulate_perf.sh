#!/usr/bin/env bash
# The offline tool at length: 600 s simulated at 1 kHz, as CSV at 1 Hz and as a bag at 100 Hz.
# Usage: bench/simulate_perf.sh BUILD_DIR
set -euo pipefail
build_dir=$(cd "${1:-$KANE_SIM_BUILD_DIR}" && pwd)
config="$(dirname "$0")/../config/mechanism.yaml"
simulate="$build_dir/devel/lib/kane_sim/simulate"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
echo "| output | wall time (loop, from simulate) | physics steps/s | file |"
echo "|---|---|---|---|"
for spec in "csv 1" "bag 100"; do
  set -- $spec
  start=$(date +%s.%N)
  "$simulate" --config "$config" --duration 600 --torque-sine 10,0.5 --output-rate "$2" \
    --"$1" "$work/out.$1" 2>"$work/err"
  end=$(date +%s.%N)
  loop=$(sed -n 's/.*wall time \([0-9.e+-]*\) s, \([0-9.e+-]*\) steps\/s.*/\1 s|\2/p' "$work/err")
  printf "| %s at %s Hz | %s (process %.2f s) | %s | %s |\n" "$1" "$2" "${loop%%|*}" \
    "$(echo "$end - $start" | bc)" "${loop##*|}" "$(du -h "$work/out.$1" | cut -f1)"
done
