# What every whole-process benchmark starts with (sourced): the build folder (the first argument
# or KANE_SIM_BUILD_DIR), the package's config, simulate, a scratch folder removed on exit, now.
set -euo pipefail
build_dir=$(cd "${1:-$KANE_SIM_BUILD_DIR}" && pwd)
config="$(dirname "$0")/../config/mechanism.yaml"
simulate="$build_dir/devel/lib/kane_sim/simulate"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
now() { date +%s.%N; }
