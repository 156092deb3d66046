#!/usr/bin/env bash
# The offline tool at length, as whole processes (start-up and output included):
#  - 600 s simulated at 1 kHz, as CSV at 1 Hz and as a bag at 100 Hz;
#  - 3600 s at 1 kHz with CSV at 1 Hz against the floor: the closed-form rk4 step of bench_core
#    (measured in the same run) times the step count;
#  - a sweep of 1000 cases x 10 s at 1 kHz on every core, in one process.
# Usage: bash bench/simulate_perf.sh BUILD_DIR
# shellcheck source=common.sh
source "$(dirname "$0")/common.sh"
echo "| output | wall time (loop, from simulate) | physics steps/s | file |"
echo "|---|---|---|---|"
for spec in "csv 1" "bag 100"; do
  set -- $spec
  start=$(now)
  "$simulate" --config "$config" --duration 600 --torque-sine 10,0.5 --output-rate "$2" \
    --"$1" "$work/out.$1" 2>"$work/err"
  end=$(now)
  loop=$(sed -n 's/.*wall time \([0-9.e+-]*\) s, \([0-9.e+-]*\) steps\/s.*/\1 s|\2/p' "$work/err")
  printf "| %s at %s Hz | %s (process %.2f s) | %s | %s |\n" "$1" "$2" "${loop%%|*}" \
    "$(echo "$end - $start" | bc)" "${loop##*|}" "$(du -h "$work/out.$1" | cut -f1)"
done

echo
floor_ns=$("$build_dir/bench_bin/bench_core" --benchmark_filter=Floor \
  --benchmark_min_time=1 --benchmark_format=json 2>/dev/null |
  /usr/bin/python3 -c 'import json,sys; print(json.load(sys.stdin)["benchmarks"][0]["real_time"])')
best=""
for i in 1 2 3; do  # best of three whole processes
  start=$(now)
  "$simulate" --config "$config" --duration 3600 --torque 2 --output-rate 1 --csv "$work/long.csv" \
    2>/dev/null
  end=$(now)
  t=$(echo "$end - $start" | bc)
  if [ -z "$best" ] || [ "$(echo "$t < $best" | bc)" = 1 ]; then best=$t; fi
done
floor_s=$(echo "$floor_ns * 3600000 / 1000000000" | bc -l)
printf "simulate 3600 s at 1 kHz, CSV at 1 Hz, whole process (best of 3): %.3f s; floor %.1f ns/step x 3.6e6 = %.3f s; ratio %.2f\n" \
  "$best" "$floor_ns" "$floor_s" "$(echo "$best / $floor_s" | bc -l)"

echo
"$simulate" --config "$config" --duration 10 --torque-sine 5,0.5 --csv "$work/sweep.csv" \
  --sweep mechanism.spring_stiffness=100:400:25 --sweep initial_state.q1=0.1:1.2:40 2>"$work/err"
echo "sweep, 1000 cases x 10 s at 1 kHz, $(nproc) cores: $(tail -1 "$work/err")"
