#!/usr/bin/env bash
# Every executable as a user first meets it: `--help` prints its usage and exits 0 without
# contacting a master (ros::init under a taken name would kill the running node); a namespace
# or node name ROS refuses ("robot-a") exits 1 naming it instead of aborting; teleop_key with a
# closed stdin says so and exits 1 instead of reading its master socket as the keyboard forever.
# Usage: node_cli_test.sh BUILD_DIR
set -uo pipefail
build_dir=$(cd "$1" && pwd)
set +u
# shellcheck disable=SC1091
source "$build_dir/devel/setup.bash"
set -u
export ROS_HOSTNAME=localhost
# No master listens here: anything that tried to reach one would hang until the timeout.
export ROS_MASTER_URI="http://localhost:$((20000 + RANDOM % 12000))"
bin="$build_dir/devel/lib/kane_sim"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
passed=0
failed=0
check() {  # check NAME COMMAND...
  local name=$1; shift
  if "$@"; then echo "ok   $name"; passed=$((passed + 1)); else echo "FAIL $name"; failed=$((failed + 1)); fi
}

helps() {  # helps EXE: --help and -h print a usage and exit 0 at once, without a master
  local flag
  for flag in --help -h; do
    timeout -k 5 5 "$bin/$1" "$flag" >"$work/out" 2>"$work/err" </dev/null
    local code=$?
    [ "$code" -eq 0 ] || { echo "     $1 $flag: exit $code"; cat "$work/err"; return 1; }
    grep -qi "usage" "$work/out" || { echo "     $1 $flag: no usage"; cat "$work/out"; return 1; }
  done
}
for exe in kane_sim_node pd_controller tracking_controller observer crank_marker teleop_key simulate analyze design config_info; do
  check "$exe --help" helps "$exe"
done

# The parameter table doc/reference/parameters.md holds (test_parameter_schema compares the two),
# and a stray argument refused as a usage error.
parameter_table() {
  "$bin/config_info" parameters >"$work/out" 2>"$work/err" || { cat "$work/err"; return 1; }
  head -1 "$work/out" | grep -q "^| key | symbol | unit | default | rule |" &&
    grep -q "^| mechanism.rod_mass | m | kg | required | > 0 |" "$work/out" || { cat "$work/out"; return 1; }
  "$bin/config_info" parameters rod_mas >"$work/out" 2>"$work/err"
  local code=$?
  [ "$code" -eq 2 ] && grep -q "'rod_mas' is not a config key; did you mean mechanism.rod_mass" "$work/err" ||
    { echo "     exit $code"; cat "$work/err"; return 1; }
  "$bin/config_info" parameters a b >"$work/out" 2>"$work/err"
  code=$?
  [ "$code" -eq 2 ] && grep -q "parameters takes at most one argument" "$work/err" ||
    { echo "     exit $code"; cat "$work/err"; return 1; }
  # One parameter, and every one for a terminal: "field: value" lines, no Markdown.
  "$bin/config_info" parameters mechanism.spring_stiffness >"$work/out" 2>"$work/err" &&
    head -1 "$work/out" | grep -qx "mechanism.spring_stiffness" &&
    grep -qx "  unit: N/m" "$work/out" && grep -q "^  reconfigure: spring_stiffness" "$work/out" ||
    { echo "     KEY:"; cat "$work/out" "$work/err"; return 1; }
  "$bin/config_info" parameters --text >"$work/out" 2>"$work/err" &&
    grep -qx "mechanism.rod_mass" "$work/out" && ! grep -q "^| " "$work/out" ||
    { echo "     --text:"; head "$work/out"; return 1; }
}
check "config_info parameters prints the table, one KEY or --text; a wrong key or stray arguments are usage errors" parameter_table

# The output table doc/reference/outputs.md holds (test_simulator compares the two): a load's
# power row names its CSV column, Python key and message field; an argument is a usage error.
output_table() {
  "$bin/config_info" outputs >"$work/out" 2>"$work/err" || { cat "$work/err"; return 1; }
  grep -qF '| `power_spring_damper` | power | `Result.powers["spring_damper"]` | `load_powers[7]` |' "$work/out" ||
    { head -3 "$work/out"; return 1; }
  "$bin/config_info" outputs --text >"$work/out" 2>"$work/err"
  local code=$?
  [ "$code" -eq 2 ] && grep -q "outputs takes no argument" "$work/err" ||
    { echo "     exit $code"; cat "$work/err"; return 1; }
  # A table that cannot be written (full disk) is an error, not a silent success.
  "$bin/config_info" outputs >/dev/full 2>"$work/err"
  code=$?
  [ "$code" -eq 4 ] && grep -q "could not write the output" "$work/err" ||
    { echo "     /dev/full: exit $code"; cat "$work/err"; return 1; }
}
check "config_info outputs prints the output table; an argument is a usage error; a write error exits 4" output_table

# loop_bag refuses what it cannot play before it contacts a master (no master runs here).
loop_bag_refusals() {
  "$bin/simulate" --duration 0.1 --bag "$work/run.bag" 2>/dev/null || return 1
  local args expected
  while IFS='|' read -r args expected; do
    # shellcheck disable=SC2086
    timeout -k 5 10 /usr/bin/python3 "$(rospack find kane_sim)/scripts/loop_bag" $args >"$work/out" 2>"$work/err"
    local code=$?
    [ "$code" -eq 1 ] && grep -q -- "$expected" "$work/err" ||
      { echo "     loop_bag $args: exit $code"; cat "$work/err"; return 1; }
  done <<EOF_CASES
$work/run.bag --rate 0|--rate must be in (0, 1e6), got 0.0
$work/run.bag --rate nan|--rate must be in (0, 1e6), got nan
$work/run.bag --delay -5|--delay must be in
$work/run.bag --passes -1|--passes must be >= 0
/nonexistent.bag|cannot read /nonexistent.bag
$work|cannot read
EOF_CASES
}
check "loop_bag refuses bad rates, delays, passes and files by name" loop_bag_refusals

sim_time_line() {  # config_info use_sim_time prints a whole line
  local config
  config=$(rospack find kane_sim)/config/mechanism.yaml
  "$bin/config_info" use_sim_time "$config" >"$work/out" 2>"$work/err" || { cat "$work/err"; return 1; }
  [ "$(cat "$work/out")" = false ] && [ "$(tail -c 1 "$work/out" | od -An -c | tr -d ' ')" = '\n' ] ||
    { od -c "$work/out"; return 1; }
}
check "config_info use_sim_time ends its line" sim_time_line

refuses_name() {  # refuses_name EXE ARG TEXT: exit 1 with TEXT on stderr, no abort
  timeout -k 5 5 "$bin/$1" "$2" >"$work/out" 2>"$work/err" </dev/null
  local code=$?
  [ "$code" -eq 1 ] && grep -q "$3" "$work/err" || { echo "     $1 $2: exit $code"; cat "$work/err"; return 1; }
}
for exe in kane_sim_node pd_controller tracking_controller observer crank_marker teleop_key; do
  check "$exe __ns:=robot-a exits 1 naming it" refuses_name "$exe" "__ns:=robot-a" "robot-a"
  check "$exe __name:=k-s exits 1 naming it" refuses_name "$exe" "__name:=k-s" "k-s"
done
env_namespace() {
  ROS_NAMESPACE=robot-a timeout -k 5 5 "$bin/kane_sim_node" >"$work/out" 2>"$work/err" </dev/null
  local code=$?
  [ "$code" -eq 1 ] && grep -q "robot-a" "$work/err" || { echo "     exit $code"; cat "$work/err"; return 1; }
}
check "ROS_NAMESPACE=robot-a exits 1 naming it" env_namespace

closed_stdin() {
  timeout -k 5 5 "$bin/teleop_key" <&- >"$work/out" 2>"$work/err"
  local code=$?
  [ "$code" -eq 1 ] && grep -q "stdin is closed" "$work/err" || { echo "     exit $code"; cat "$work/err"; return 1; }
}
check "teleop_key <&- exits 1: stdin is closed" closed_stdin

# What `rosrun kane_sim <TAB>` offers, found the way rosbash's completion finds it: every
# executable file under the package folder and its catkin libexec folder (hidden folders
# skipped). Only the user's tools, each once; node_tests stays because rostest starts it by type
# from the package. (It listed 61: test and benchmark binaries, install_deps.sh, sanitize.sh,
# the .cfg, and source copies of the Python tools beside their devel relays.)
tab_completion() {
  local pkg libexec
  pkg=$(rospack find kane_sim) || return 1
  libexec=$(catkin_find --first-only --without-underlays --libexec kane_sim 2>/dev/null)
  find -L "$pkg" $libexec -type f -perm /111 ! -regex ".*/[.][^./].*" -printf '%f\n' | sort >"$work/tab"
  printf '%s\n' analyze bag_summary config_info crank_marker demo_supervisor design identify kane_sim_node \
    lockstep_controller loop_bag node_tests observer pd_controller plot_bag simulate sweep teleop_key \
    tracking_controller web |
    sort >"$work/want"
  diff "$work/want" "$work/tab" >"$work/diff" || { echo "     expected < > offered:"; sed 's/^/     /' "$work/diff"; return 1; }
}
check "rosrun kane_sim <TAB> offers the user's tools, each once" tab_completion

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
