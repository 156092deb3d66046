#!/usr/bin/env bash
# Sweeps on a Dask cluster against the local sweep, on this machine: a 2000-case x 10 s sweep
# (2e7 physics steps, 2 N m at 0.5 Hz) by `rosrun kane_sim sweep` locally (--jobs 1 and 2) and on
# a scheduler at 127.0.0.1 with 1 and then 2 single-threaded workers (tasks of 64 cases), each
# the best of three whole processes (the client's start-up and connection included).
# Usage: bash bench/cluster_sweep.sh BUILD_DIR
# shellcheck source=common.sh
source "$(dirname "$0")/common.sh"
sweep="$build_dir/devel/lib/kane_sim/sweep"
plan=(--config "$config" --duration 10 --torque-sine 2,0.5
  --sweep mechanism.spring_stiffness=100:400:200 --sweep damping.slider4_joint=0:2:10)
pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done; rm -rf "$work"; }
trap cleanup EXIT
echo "| 2000 cases x 10 s | where | wall time [s] |"
echo "|---|---|---|"
for jobs in 1 2; do
  echo "| local | --jobs $jobs | $(best_of_three "$sweep" "${plan[@]}" --jobs "$jobs" --csv "$work/l.csv") |"
done
dask scheduler --host 127.0.0.1 --port 0 --scheduler-file "$work/s.json" --no-dashboard \
  >"$work/scheduler.log" 2>&1 &
pids+=($!)
for _ in $(seq 100); do [ -s "$work/s.json" ] && break; sleep 0.1; done
for n in 1 2; do
  dask worker --scheduler-file "$work/s.json" --nthreads 1 --no-nanny --no-dashboard \
    >"$work/worker$n.log" 2>&1 &
  pids+=($!)
  /usr/bin/python3 -c "
from distributed import Client
Client(scheduler_file='$work/s.json', timeout=30).wait_for_workers($n, timeout=60)"
  echo "| cluster | $n worker(s) | $(best_of_three "$sweep" "${plan[@]}" --scheduler "$work/s.json" --csv "$work/c.csv") |"
done
