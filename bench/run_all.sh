#!/usr/bin/env bash
# One command for the whole benchmark suite (about 6 minutes): core throughput against the
# closed-form floor, kane_sim against MuJoCo (cost and agreement), the offline tool at length
# and a sweep, kane_sim against SymPy + SciPy with the accuracy table, and the live node.
# Installs what it needs (Debian packages), builds, and prints Markdown tables.
# Usage: bench/run_all.sh [NODE_SECONDS_PER_CASE (default 60)]
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh --tests
missing=()
for p in python3-scipy libmujoco-dev libsimbody-dev; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
bash scripts/build.sh
# shellcheck source=scripts/build_dir.sh
source scripts/build_dir.sh
build=$KANE_SIM_BUILD_DIR
export ROS_HOSTNAME=${ROS_HOSTNAME:-localhost}
set +u
# shellcheck disable=SC1091
source "$build/devel/setup.bash"
set -u
# Every figure below belongs to this machine: its CPU, the instruction sets the lanes may take,
# its cores (the speed issue: figures from an AVX-512 VM read as the user's AVX2 one's).
echo "## Machine"
echo "- CPU: $(grep -m1 '^model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//')"
echo "- cores this process may use: $(nproc); $(lscpu 2>/dev/null | grep -m1 '^Thread(s) per core' | sed 's/  */ /g')"
echo "- SIMD lanes this CPU runs: $(/usr/bin/python3 -c 'from kane_sim import _core; print(", ".join(a for a in ("avx512", "avx2", "sse2") if _core.lane_arch_available(a)))')"
echo "- $(uname -sr), $(gcc --version | head -1), $(date -u +%Y-%m-%d)"
echo
echo "## The speed goals: ratios within this run"
/usr/bin/python3 bench/speed_goals.py "$build"
echo
echo "## Core throughput (Google Benchmark)"
"$build/bench_bin/bench_core" --benchmark_min_time=1 --benchmark_repetitions=3 \
  --benchmark_report_aggregates_only=true 2>/dev/null
echo; echo "## Controller design: the exact Jacobian, linearization, equilibria, LQR"
"$build/bench_bin/bench_design" --benchmark_min_time=1 --benchmark_repetitions=3 \
  --benchmark_report_aggregates_only=true 2>/dev/null
echo; echo "## Against MuJoCo (RK4, dt = 1 ms) and Simbody, same mechanism and parameters"
"$build/bench_bin/bench_peers" --benchmark_min_time=1 --benchmark_repetitions=3 \
  --benchmark_report_aggregates_only=true 2>/dev/null
echo; echo "## simulate: 600 s and 3600 s simulated at 1 kHz, a 1000-case sweep"
bash bench/simulate_perf.sh "$build"
echo; echo "## Against SymPy + SciPy; accuracy"
/usr/bin/python3 bench/compare_sympy.py "$build"
echo; echo "## Live node"
/usr/bin/python3 bench/node_perf.py "$build" --seconds "${1:-60}"
echo; echo "## The Python module against simulate; rates"
/usr/bin/python3 bench/python_perf.py "$build"
echo; echo "## BatchSimulator (one and ten physics steps per call, rollout)"
/usr/bin/python3 bench/batch_simulator.py
echo; echo "## The estimator: an hour's readings offline, the observer node at 1 kHz"
/usr/bin/python3 bench/estimator_speed.py
