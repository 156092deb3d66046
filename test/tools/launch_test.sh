#!/usr/bin/env bash
# The launch files as a user meets them, several launches on one master: a relaunch with
# another config takes the new values (clear_params); a wall-clock launch after a sim-time one
# stamps wall time (/use_sim_time set explicitly); a config file's publish_clock is honoured
# without launch arguments; every `rosrun kane_sim X` in README.md and doc/**/*.md resolves to
# exactly one executable; catkin_lint -W2 reports no warning or error.
# Usage: launch_test.sh BUILD_DIR
set -uo pipefail
build_dir=$(cd "$1" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
pkg=$(cd "$here/../.." && pwd)
set +u
# shellcheck disable=SC1091
source "$build_dir/devel/setup.bash"
set -u
export ROS_HOSTNAME=localhost
export PATH=/usr/bin:$PATH  # the ROS tools' Python is Debian's
port=$((20000 + RANDOM % 12000))
export ROS_MASTER_URI="http://localhost:$port"
work=$(mktemp -d)
passed=0; failed=0
check() {
  local name=$1; shift
  if "$@"; then echo "ok   $name"; passed=$((passed + 1)); else echo "FAIL $name"; failed=$((failed + 1)); fi
}
roscore -p "$port" >"$work/core.log" 2>&1 &
core=$!
cleanup() { [ -n "${launch:-}" ] && kill -INT "$launch" 2>/dev/null; kill -INT "$core" 2>/dev/null; wait 2>/dev/null; rm -rf "$work"; }
trap cleanup EXIT
for _ in $(seq 50); do rosparam list >/dev/null 2>&1 && break; sleep 0.2; done

start() {  # start ARGS...: sim.launch in the background, wait for mechanism_state
  roslaunch -p "$port" kane_sim sim.launch "$@" >"$work/launch.log" 2>&1 &
  launch=$!
  # A bound of 600 s, not an expectation: on one core beside a CPU hog rostopic alone took more
  # than the 3 s each try once had, and every try failed.
  local deadline=$((SECONDS + 600))
  while [ "$SECONDS" -lt "$deadline" ]; do
    timeout -k 5 60 rostopic echo -n 1 /mechanism_state/sim_time >/dev/null 2>&1 && return 0
    sleep 0.2
  done
  echo "     sim.launch $* published nothing:"; tail -5 "$work/launch.log"; return 1
}
stop() { kill -INT "$launch" 2>/dev/null; wait "$launch" 2>/dev/null; launch=""; }
# Every timeout kills what ignores its SIGTERM 5 s later (-k): rostopic on a starved machine (one
# core beside a CPU hog) once outlived `timeout 3` by 14 minutes.
# first field of a topic's message, as a number
field() { timeout -k 5 60 rostopic echo -n 1 "$1" 2>/dev/null | head -1 | tr -d '[]' | cut -d, -f"${2:-1}"; }
near() { /usr/bin/python3 -c "import sys; a,b,t=map(float,sys.argv[1:]); sys.exit(abs(a-b)>t)" "$@"; }

relaunch_takes_the_new_config() {
  start config:="$pkg/config/textbook.yaml" start_paused:=true || return 1
  local textbook; textbook=$(field /mechanism_state/u_dot 1)
  stop
  start start_paused:=true || return 1
  local fresh; fresh=$(field /mechanism_state/u_dot 1)
  local leftover=no
  rosparam get /kane_sim/mechanism/rod_inertia >/dev/null 2>&1 && leftover=yes
  stop
  echo "     u1' at the initial state: textbook.yaml $textbook, then mechanism.yaml $fresh; rod_inertia left over: $leftover"
  near "$textbook" -19.09 0.01 && near "$fresh" -17.66 0.01 && [ "$leftover" = no ]
}

wall_clock_after_sim_time() {
  start publish_clock:=true || return 1
  stop
  start || return 1
  local use_sim_time stamp now
  use_sim_time=$(rosparam get /use_sim_time)
  stamp=$(timeout -k 5 5 rostopic echo -n 1 /joint_states/header/stamp/secs 2>/dev/null | head -1)
  now=$(date +%s)
  stop
  echo "     /use_sim_time $use_sim_time, joint_states stamped $stamp s, wall clock $now s"
  [ "$use_sim_time" = false ] && near "$stamp" "$now" 10
}

config_publish_clock_is_honoured() {
  sed 's/publish_clock: false/publish_clock: true/' "$pkg/config/mechanism.yaml" >"$work/clock.yaml"
  start config:="$work/clock.yaml" || return 1
  local use_sim_time clock
  use_sim_time=$(rosparam get /use_sim_time)
  clock=$(timeout -k 5 5 rostopic echo -n 1 /clock/clock/secs 2>/dev/null | head -1)
  stop
  echo "     /use_sim_time $use_sim_time, /clock at $clock s"
  [ "$use_sim_time" = true ] && [ "${clock:-0}" -ge 1000000000 ]
}

doc_rosruns_resolve_once() {
  local ok=0 names pages
  pages=$(find "$pkg/README.md" "$pkg/doc" -name '*.md' | wc -l)
  [ "$pages" -gt 1 ] || { echo "     no README.md and doc/**/*.md under $pkg"; return 1; }
  names=$(find "$pkg/README.md" "$pkg/doc" -name '*.md' \
    -exec grep -ho 'rosrun kane_sim [A-Za-z_]*' {} + | awk '{print $3}' | sort -u)
  [ -n "$names" ] || { echo "     no rosrun in README.md or doc/"; return 1; }
  for exe in $names; do
    local found; found=$(rosrun --prefix echo kane_sim "$exe" </dev/null 2>&1)
    if [ "$(echo "$found" | wc -l)" -ne 1 ] || [ ! -x "$found" ]; then
      echo "     rosrun kane_sim $exe: $found"; ok=1
    fi
  done
  echo "     $(echo "$names" | wc -w) executables in $pages pages: $(echo $names)"
  return $ok
}

catkin_lint_clean() {
  catkin_lint -W2 "$pkg" >"$work/lint" 2>&1
  grep -E "(warning|error):" "$work/lint" && return 1
  echo "     $(grep -c 'notice:' "$work/lint") notices (README, Package checks), no warnings or errors"
}

# lockstep:=true controller:=true: the controller answers stamped, so lockstep never waits for its
# timeout. Waiting it out (1 s of wall time per published state, 0.01 s of sim time) would advance
# sim time at 0.01 s per second; answered, as fast as possible (real_time_factor 0), it goes far
# faster on any machine: more than 5 times that pace is asked, over the wall time measured
# around the two readings (rostopic's start-up counted in, so the pace is underestimated).
lockstep_runs_with_the_controller() {
  start lockstep:=true controller:=true real_time_factor:=0 || return 1
  [ "$(rosparam get /pd_controller/stamped)" = "true" ] || { echo "     controller not stamped"; return 1; }
  local a b t0 t1
  t0=$(date +%s.%N); a=$(field /mechanism_state/sim_time); sleep 2
  b=$(field /mechanism_state/sim_time); t1=$(date +%s.%N)
  stop
  local wall
  wall=$(/usr/bin/python3 -c "import sys; print(round(float(sys.argv[2]) - float(sys.argv[1]), 2))" "$t0" "$t1")
  /usr/bin/python3 -c "import sys; a, b, w = map(float, sys.argv[1:]); sys.exit(not (b - a) / w > 0.05)" \
    "${a:-nan}" "${b:-nan}" "$wall" ||
    { echo "     lockstep advanced only $a -> $b s of sim time in $wall s"; return 1; }
  echo "     lockstep: $a -> $b s of sim time in $wall s of wall time"
}

check "relaunch on the same master takes the new config" relaunch_takes_the_new_config
check "lockstep with the example controller runs at the controller's pace" lockstep_runs_with_the_controller
check "wall-clock launch after a sim-time launch stamps wall time" wall_clock_after_sim_time
check "the config file's publish_clock is honoured without launch arguments" config_publish_clock_is_honoured
check "every rosrun in README.md and doc/ resolves to one executable" doc_rosruns_resolve_once
check "catkin_lint -W2: no warnings or errors" catkin_lint_clean
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
