# What every whole-process benchmark starts with (sourced): the build folder (the first argument
# or KANE_SIM_BUILD_DIR), the package's config, simulate, a scratch folder removed on exit, now,
# best_of_three.
set -euo pipefail
build_dir=$(cd "${1:-$KANE_SIM_BUILD_DIR}" && pwd)
config="$(dirname "$0")/../config/mechanism.yaml"
simulate="$build_dir/devel/lib/kane_sim/simulate"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
now() { date +%s.%N; }
best_of_three() {  # prints the best wall time [s] of three runs of "$@"
  local best="" start end t
  for _ in 1 2 3; do
    start=$(now)
    "$@" >/dev/null 2>&1
    end=$(now)
    t=$(echo "$end - $start" | bc)
    if [ -z "$best" ] || [ "$(echo "$t < $best" | bc)" = 1 ]; then best=$t; fi
  done
  echo "$best"
}
