#!/usr/bin/env bash
# rviz smoke test under Xvfb: write a bag offline with `simulate --bag`, replay it (looping)
# through launch/view_bag.launch into rviz with config/kane_sim.rviz, take a screenshot, and
# check that the mechanism (RobotModel and markers) is drawn inside the 3D view and that neither
# rviz nor tf complained about old or repeated data. Then the same for the live sim launched in a
# namespace with rviz and the crank's interactive marker (sim.launch ns:=robot_a
# frame_prefix:=robot_a rviz:=true interactive_marker:=true): the marker's ring must be drawn too.
# Usage: rviz_smoke_test.sh BUILD_DIR   (the screenshot is kept in BUILD_DIR/test_artifacts/)
set -euo pipefail
build_dir=$(cd "$1" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
artifacts="$build_dir/test_artifacts"
mkdir -p "$artifacts"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

set +u
# shellcheck disable=SC1091
source "$build_dir/devel/setup.bash"
set -u
export ROS_HOSTNAME=localhost
# Our own master, clear of any other run, and below the kernel's ephemeral ports (32768 and up,
# where an outgoing connection can hold a port: a master once found 35942 taken).
port=$((20000 + RANDOM % 12000))
export ROS_MASTER_URI="http://localhost:$port"

# 4 s of a driven crank: the 16 s of replay below loops it several times.
rosrun kane_sim simulate --config "$here/../../config/mechanism.yaml" --duration 4 \
  --torque-sine 12,0.5 --bag "$work/run.bag" 2>/dev/null

export KANE_SIM_CHECK_SCREENSHOT="$here/check_screenshot.py"
# wait_until_drawn PROBE PID [CHECK_FLAGS...]: inside xvfb-run, screenshots the display once a
# second until check_screenshot.py sees the mechanism (rviz and the launch take 5-15 s to come up
# on a busy 2-core machine; on one core beside a CPU hog and the browser test it took more than
# 75 s), for at most 600 s: a bound, not an expectation; PROBE holds the last shot. Returns 2 at
# once when the launch PID has exited (rviz is a required node: it died).
wait_until_drawn() {
  local probe=$1 pid=$2; shift 2
  local start=$SECONDS
  while [ $((SECONDS - start)) -lt 600 ]; do
    sleep 1
    if ! kill -0 "$pid" 2>/dev/null; then
      echo "     the launch exited after $((SECONDS - start)) s, nothing drawn"
      return 2
    fi
    import -window root "$probe" 2>/dev/null || continue
    if /usr/bin/python3 "$KANE_SIM_CHECK_SCREENSHOT" "$probe" "$@" >/dev/null 2>&1; then
      echo "     drawn after $((SECONDS - start)) s"
      return 0
    fi
  done
  echo "     not drawn within 600 s"
  return 1
}

# launch_until_drawn LOG PROBE "ROSLAUNCH ARGS" [CHECK_FLAGS...]: inside xvfb-run, starts the
# launch (its output appended to LOG) and waits until it draws; sets $launch. Debian's rviz now
# and then dies as it starts, before its first frame, right after rospack's "no such package
# media_export" (exit -11, or -6 with "free(): invalid next size"; in 2 of 2 clean-clone CI runs
# on the 2-core VM, 2026-11-28, on the first of the test's three starts): such a start is tried
# again, twice at most, and said in LOG. Not drawn in time is not retried.
launch_until_drawn() {
  local log=$1 probe=$2 args=$3; shift 3
  local attempt status
  for attempt in 1 2 3; do
    roslaunch $args >> "$log" 2>&1 &
    launch=$!
    status=0
    wait_until_drawn "$probe" "$launch" "$@" || status=$?
    [ "$status" -eq 2 ] || return "$status"
    wait "$launch" || true
    echo "rviz_smoke_test: the launch died before drawing (start $attempt); starting it again" | tee -a "$log"
  done
  return 2
}

# replay_shots BAG NAME LOG GAP COUNT: replays BAG through view_bag.launch into rviz under Xvfb and
# takes COUNT screenshots GAP s apart from the second pass on, as $work/NAME_{1..COUNT}.png.
# loop_bag restamps each pass after the one before (/clock never goes back), so rviz keeps its
# tf buffer and every shot, also one right after a loop, shows the mechanism (a loop that rewound
# /clock left the RobotModel white for 1-2 s).
replay_shots() {
  rm -f "$work/$2"_*.png
  : > "$3"
  xvfb-run -a -s "-screen 0 1280x800x24" bash -c "
    $(declare -f wait_until_drawn launch_until_drawn)
    launch_until_drawn '$3' '$work/$2_probe.png' '-p $port kane_sim view_bag.launch bag:=$1'
    for i in \$(seq $5); do import -window root '$work/$2'_\$i.png; sleep $4; done
    kill -INT \$launch
    wait \$launch || true
  "
}

shot="$artifacts/rviz_smoke.png"
log="$artifacts/rviz_smoke.log"
rm -f "$shot"
# 5 shots 1.1 s apart span more than one 4 s pass: at least one lands just after a loop.
replay_shots "$work/run.bag" shot "$log" 1.1 5

failures=0
shown=0
taken=0
for candidate in "$work"/shot_*.png; do
  [ -s "$candidate" ] || continue
  taken=$((taken + 1))
  cp "$candidate" "$shot"
  if /usr/bin/python3 "$here/check_screenshot.py" "$candidate"; then
    shown=$((shown + 1))
  else
    cp "$candidate" "$artifacts/rviz_smoke_not_drawn.png"
  fi
done
if [ "$taken" -eq 0 ]; then
  echo "FAIL: no screenshot taken"; failures=$((failures + 1))
elif [ "$shown" -ne "$taken" ]; then
  echo "FAIL: the mechanism is drawn in $shown of $taken screenshots across the loops (kept: rviz_smoke_not_drawn.png)"
  failures=$((failures + 1))
fi
for pattern in "too old" TF_OLD_DATA TF_REPEATED_DATA "Could not load"; do
  if grep -q "$pattern" "$log"; then
    echo "FAIL: rviz or tf reported '$pattern':"; grep -m3 "$pattern" "$log"
    failures=$((failures + 1))
  fi
done
grep -q "RViz is ready\|rviz" "$log" || true
echo "screenshot: $shot, log: $log"

# Fast motion replayed at full rate: the crank driven round by 30 +- 15 N m (never near zero, so
# the arrow is long in every shot). The markers are
# in their links' frames, frame-locked, so rviz places them with the links' own transforms: the
# torque arrow must touch rod 1 in every screenshot taken.
rosrun kane_sim simulate --config "$here/../../config/mechanism.yaml" --duration 4 \
  --torque-sine 15,1.5,30 --bag "$work/fast.bag" 2>/dev/null
fast_shot="$artifacts/rviz_fast.png"
replay_shots "$work/fast.bag" fast "$artifacts/rviz_fast.log" 0.6 8
attached=0
for candidate in "$work"/fast_*.png; do
  [ -s "$candidate" ] || continue
  cp "$candidate" "$fast_shot"
  # A shot right after a loop rewinds /clock may show nothing (see above): skip those; every
  # shot that shows the mechanism with the arrow must have it on the rod.
  if /usr/bin/python3 "$here/check_screenshot.py" "$candidate" >/dev/null; then
    verdict=0
    /usr/bin/python3 "$here/check_screenshot.py" "$candidate" --attached || verdict=$?
    if [ "$verdict" -eq 0 ]; then
      attached=$((attached + 1))
    elif [ "$verdict" -ne 3 ]; then  # 3: the arrow too short or cut off to judge
      echo "FAIL: in the fast replay the torque arrow is off rod 1 ($candidate)"
      cp "$candidate" "$artifacts/rviz_fast_detached.png"
      failures=$((failures + 1))
    fi
  fi
done
[ "$attached" -ge 1 ] || { echo "FAIL: no screenshot of the fast replay shows the mechanism with its arrow"; failures=$((failures + 1)); }
echo "fast replay: $attached screenshots with the arrow on rod 1 ($fast_shot)"

# The live sim in a namespace with its own frame prefix, rviz started by sim.launch in that
# namespace: the config's relative topics (robot_description, markers, the interactive marker's
# update topic) must resolve there, and the marker must find the prefixed mechanism frame.
ns_shot="$artifacts/rviz_namespace.png"
ns_log="$artifacts/rviz_namespace.log"
rm -f "$ns_shot"
: > "$ns_log"
xvfb-run -a -s "-screen 0 1280x800x24" bash -c "
  $(declare -f wait_until_drawn launch_until_drawn)
  launch_until_drawn '$ns_log' '$ns_shot' '-p $port kane_sim sim.launch ns:=robot_a frame_prefix:=robot_a rviz:=true interactive_marker:=true' --setpoint
  sleep 1  # rviz's warnings about the marker, if any, come with its first frames
  import -window root '$ns_shot'
  kill -INT \$launch
  wait \$launch || true
"
if [ ! -s "$ns_shot" ]; then
  echo "FAIL: no screenshot of the namespaced sim"; failures=$((failures + 1))
elif ! /usr/bin/python3 "$here/check_screenshot.py" "$ns_shot" --setpoint; then
  echo "FAIL: sim.launch ns:=robot_a rviz:=true interactive_marker:=true does not show the mechanism and its marker"
  failures=$((failures + 1))
fi
if grep -q "Marker is fully transparent\|No transform" "$ns_log"; then
  echo "FAIL: rviz warned in the namespace:"; grep -m3 "transparent\|No transform" "$ns_log"
  failures=$((failures + 1))
fi
echo "namespaced screenshot: $ns_shot, log: $ns_log"
if [ "$failures" -eq 0 ]; then
  echo "1 passed, 0 failed"
else
  echo "0 passed, 1 failed"
  exit 1
fi
