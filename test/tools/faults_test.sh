#!/usr/bin/env bash
# Faults, with real processes: SIGINT and SIGTERM end the node with exit 0 within 1 s (on a
# busy machine: within 5 times what a small roscpp node takes there and then); an
# interrupted demo recording leaves a complete bag (no reindex); when the master dies the node
# neither crashes nor spins a core, and when a master comes back on the same port the node
# notices (within ~1 s), registers its topics and services again and is reachable.
# Usage: faults_test.sh BUILD_DIR
set -uo pipefail
build_dir=$(cd "$1" && pwd)
work=$(mktemp -d)
set +u
# shellcheck disable=SC1091
source "$build_dir/devel/setup.bash"
set -u
export ROS_HOSTNAME=localhost
port=$((20000 + RANDOM % 12000))
export ROS_MASTER_URI="http://localhost:$port"
node_exe="$build_dir/devel/lib/kane_sim/kane_sim_node"
config="$(dirname "$0")/../../config/mechanism.yaml"
passed=0
failed=0
check() {  # check NAME COMMAND...
  local name=$1; shift
  if "$@"; then echo "ok   $name"; passed=$((passed + 1)); else echo "FAIL $name"; failed=$((failed + 1)); fi
}
core_pid=""
start_master() {
  # Waits are bounds, not expectations (600 s): each check returns as soon as it holds, and a busy
  # machine (one core beside a CPU hog) takes seconds to start a Python tool.
  local deadline=$((SECONDS + 600)) attempt=0
  while [ "$SECONDS" -lt "$deadline" ]; do
    # The master alone (rosmaster), not roscore: roscore (roslaunch) gives its master 10 s to
    # answer and then exits, and on one core beside a CPU hog the master's start took longer
    # (22 roscores in 600 s, none up). Started again whenever none is running.
    if [ -z "$core_pid" ] || ! kill -0 "$core_pid" 2>/dev/null; then
      attempt=$((attempt + 1))
      rosmaster --core -p "$port" -w 3 >"$work/roscore.$attempt.log" 2>&1 &
      core_pid=$!
    fi
    timeout -k 5 60 rostopic list >/dev/null 2>&1 && kill -0 "$core_pid" 2>/dev/null && return 0
    sleep 0.2
  done
  echo "     the master did not answer in 600 s ($attempt starts):"; tail -5 "$work/roscore.$attempt.log"
  return 1
}
# The master gone for good before anything starts another on its port (one that lingers would
# answer for the next). SIGTERM: a background job of this script ignores SIGINT.
stop_master() {
  kill -TERM "$core_pid" 2>/dev/null
  wait "$core_pid" 2>/dev/null
  core_pid=""
  pkill -f "rosmaster.*-p $port" 2>/dev/null
  local deadline=$((SECONDS + 120))
  while pgrep -f "rosmaster.*-p $port" >/dev/null && [ "$SECONDS" -lt "$deadline" ]; do sleep 0.2; done
  pkill -9 -f "rosmaster.*-p $port" 2>/dev/null
  return 0
}
cleanup() { stop_master; pkill -f "__name:=fault_(sim|reference)" 2>/dev/null; rm -rf "$work"; }
trap cleanup EXIT

start_node() {
  rosparam load "$config" /fault_sim
  "$node_exe" __name:=fault_sim >"$work/node.log" 2>&1 &
  node_pid=$!
  local deadline=$((SECONDS + 600))
  while [ "$SECONDS" -lt "$deadline" ]; do
    timeout -k 5 60 rostopic list 2>/dev/null | grep -q /mechanism_state && return 0
    sleep 0.2
  done
  return 1
}

# A node's registrations with the master (publications, subscriptions, services). roscpp
# unregisters each at shutdown, one call to the master each: on a busy machine, where the master
# (Python) answers slowly, a node's exit takes about that many of its answers.
registrations() { timeout -k 5 60 rosnode info -q "$1" 2>/dev/null | grep -c '^ \* '; }

# How long a small roscpp node (pd_controller: a subscriber, a publisher) takes from SIGNAL to
# its exit on this machine now, and its registrations ("SECONDS COUNT"): the yardstick for the
# sim's own exit.
reference_exit() {
  "$build_dir/devel/lib/kane_sim/pd_controller" __name:=fault_reference >/dev/null 2>&1 &
  local pid=$!
  local deadline=$((SECONDS + 600))
  while [ "$SECONDS" -lt "$deadline" ]; do
    timeout -k 5 60 rosnode list 2>/dev/null | grep -q fault_reference && break
    sleep 0.2
  done
  local count
  count=$(registrations /fault_reference)
  local start=$(date +%s.%N)
  kill -"$1" "$pid"
  wait "$pid"
  echo "$(echo "$(date +%s.%N) - $start" | bc) ${count:-1}"
}

# exits_quickly SIGNAL: the node exits with 0 within 1 s of the signal, or, on a machine so busy
# that this is not enough, within 5 times what a small roscpp node needs for the same, scaled by
# how many more registrations the sim has to undo (a bound relative to the machine's state in the
# same run, not an expectation of its speed; one core beside a CPU hog: 3.1 s against 0.27 s for
# the small node, 9.6 s against 0.43 s).
exits_quickly() {
  start_node || return 1
  sleep 1
  local own
  own=$(registrations /fault_sim)
  local start=$(date +%s.%N)
  kill -"$1" "$node_pid"
  wait "$node_pid"; local code=$?
  local took=$(echo "$(date +%s.%N) - $start" | bc)
  local reference reference_registrations
  read -r reference reference_registrations <<<"$(reference_exit "$1")"
  [ "${reference_registrations:-0}" -gt 0 ] || reference_registrations=1
  local ratio=$(echo "scale=3; r = ${own:-1} / $reference_registrations; if (r < 1) r = 1; r" | bc)
  local bound=$(echo "b = 5 * $reference * $ratio; if (b > 1.0) b else 1.0" | bc)
  echo "     SIG$1: exit code $code after $took s (a small roscpp node: $reference s for" \
    "$reference_registrations registrations, the sim has $own; bound $bound s)"
  [ "$code" -eq 0 ] && [ "$(echo "$took < $bound" | bc)" -eq 1 ]
}

recording_survives_sigint() {
  local bag="$work/interrupted.bag"
  roslaunch -p "$port" kane_sim demo.launch duration:=60 bag:="$bag" >"$work/demo.log" 2>&1 &
  local launch=$!
  # Recording under way (rosbag has opened its .active file and the sim publishes), then 2 s of it.
  local deadline=$((SECONDS + 600))
  while [ "$SECONDS" -lt "$deadline" ]; do
    [ -s "$bag.active" ] && timeout -k 5 60 rostopic echo -n 1 /mechanism_state/sim_time >/dev/null 2>&1 && break
    sleep 0.2
  done
  sleep 2
  kill -INT "$launch"
  wait "$launch"
  [ -f "$bag" ] && [ ! -e "$bag.active" ] && rosbag info "$bag" >"$work/info" 2>&1 &&
    grep -q "/mechanism_state" "$work/info" && echo "     $(grep -E '^duration|/mechanism_state' "$work/info" | tr -s ' ' | tr '\n' ' ')"
}

master_dies_and_returns() {
  start_node || return 1
  sleep 1
  stop_master
  local cpu0 cpu1
  cpu0=$(awk '{print $14 + $15}' "/proc/$node_pid/stat")
  sleep 3
  cpu1=$(awk '{print $14 + $15}' "/proc/$node_pid/stat")
  local cpu_pct=$(( (cpu1 - cpu0) * 100 / $(getconf CLK_TCK) / 3 ))
  echo "     master gone: node alive=$(kill -0 "$node_pid" 2>/dev/null && echo yes || echo no), CPU ${cpu_pct} % of one core"
  kill -0 "$node_pid" || return 1
  [ "$cpu_pct" -lt 50 ] || return 1
  start_master || return 1
  local seen=no deadline=$((SECONDS + 300))
  while [ "$SECONDS" -lt "$deadline" ]; do
    if timeout -k 5 60 rostopic echo -n 1 /mechanism_state/sim_time >/dev/null 2>&1; then seen=yes; break; fi
    sleep 1
  done
  local service=no
  timeout -k 5 60 rosservice call /fault_sim/step >/dev/null 2>&1 && service=yes
  echo "     master back: node alive=$(kill -0 "$node_pid" 2>/dev/null && echo yes || echo no), mechanism_state received again: $seen, step service answers: $service"
  kill -0 "$node_pid" && [ "$seen" = yes ] && [ "$service" = yes ]
  local alive=$?
  kill -INT "$node_pid"; wait "$node_pid"
  return $alive
}

start_master || { echo "FAIL the master did not start"; exit 1; }
check "SIGINT: exit 0 as soon as a small node's exit per registration allows (min 1 s)" exits_quickly INT
check "SIGTERM: exit 0 as soon as a small node's exit per registration allows (min 1 s)" exits_quickly TERM
stop_master
check "SIGINT during the demo recording: bag complete, no reindex" recording_survives_sigint
start_master
check "master dies and comes back" master_dies_and_returns
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
