#!/usr/bin/env bash
# plot_bag makes a 1200x1050 PNG from a small bag and from a CSV of `simulate` (with the power
# panel), the reaction forces with --reactions, and fails clearly on a file without data.  Usage: plot_bag_test.sh BUILD_DIR
set -euo pipefail
build_dir=$(cd "$1" && pwd)
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
set +u
# shellcheck disable=SC1091
source "$build_dir/devel/setup.bash"
set -u
simulate="$build_dir/devel/lib/kane_sim/simulate"
"$simulate" --config "$here/../../config/mechanism.yaml" --duration 2 --torque-sine 5,1 \
  --bag "$work/run.bag" --csv "$work/run.csv" 2>/dev/null

failures=0
for input in run.bag run.csv; do
  /usr/bin/python3 "$here/../../scripts/plot_bag" "$work/$input" -o "$work/$input.png"
  size=$(/usr/bin/python3 -c "import matplotlib.image as m, sys; i = m.imread(sys.argv[1]); print('%dx%d' % (i.shape[1], i.shape[0]))" "$work/$input.png")
  if [ "$size" = "1200x1050" ]; then echo "ok   $input -> $size PNG"; else echo "FAIL $input -> $size"; failures=$((failures + 1)); fi
done
echo "t,q1" > "$work/empty.csv"
if /usr/bin/python3 "$here/../../scripts/plot_bag" "$work/empty.csv" -o "$work/empty.png" 2>"$work/err"; then
  echo "FAIL a CSV without the columns was accepted"; failures=$((failures + 1))
elif grep -q "cannot read" "$work/err"; then echo "ok   bad CSV refused: $(cat "$work/err")"
else echo "FAIL unclear error: $(cat "$work/err")"; failures=$((failures + 1)); fi
# A device or a pipe is refused at once (read as a bag it never ended, growing without bound).
for tool in plot_bag bag_summary; do
  if timeout -k 5 20 /usr/bin/python3 "$here/../../scripts/$tool" /dev/zero 2>"$work/err" >/dev/null; then
    echo "FAIL $tool accepted /dev/zero"; failures=$((failures + 1))
  elif grep -q "not a regular file" "$work/err"; then echo "ok   $tool /dev/zero refused: $(cat "$work/err")"
  else echo "FAIL $tool /dev/zero: $(cat "$work/err")"; failures=$((failures + 1)); fi
done

# Sensors on: the readings are drawn over q1 (at their arrival), another run beside with
# --compare; a --compare that cannot be read is refused naming it.
/usr/bin/python3 - "$here/../../config" "$work/sensors.yaml" <<'PY'
import sys, yaml
base = yaml.safe_load(open(sys.argv[1] + "/mechanism.yaml"))
base["sensors"].update(yaml.safe_load(open(sys.argv[1] + "/sensors.yaml"))["sensors"])
yaml.safe_dump(base, open(sys.argv[2], "w"))
PY
"$simulate" --config "$work/sensors.yaml" --duration 2 --torque-sine 5,1 --bag "$work/sensors.bag" 2>/dev/null
out=$(/usr/bin/python3 "$here/../../scripts/plot_bag" "$work/sensors.bag" --compare "$work/run.csv" -o "$work/sensors.png")
if echo "$out" | grep -q "200 sensor readings, compared with"; then echo "ok   sensors + compare: $out"
else echo "FAIL sensors + compare: $out"; failures=$((failures + 1)); fi
if /usr/bin/python3 "$here/../../scripts/plot_bag" "$work/run.bag" --compare "$work/nothing.bag" -o "$work/x.png" 2>"$work/err"; then
  echo "FAIL a missing --compare was accepted"; failures=$((failures + 1))
elif grep -q "cannot read --compare" "$work/err"; then echo "ok   missing --compare refused"
else echo "FAIL unclear error: $(cat "$work/err")"; failures=$((failures + 1)); fi

# The reaction forces over the crank angle, from the bag and from the CSV; a CSV of an older
# simulate without those columns is refused naming them.
for input in run.bag run.csv; do
  out=$(/usr/bin/python3 "$here/../../scripts/plot_bag" "$work/$input" --reactions -o "$work/r_$input.png")
  if echo "$out" | grep -q "reaction forces ->"; then echo "ok   --reactions $input"
  else echo "FAIL --reactions $input: $out"; failures=$((failures + 1)); fi
done
cut -d, -f1-22 "$work/run.csv" > "$work/old.csv"
if /usr/bin/python3 "$here/../../scripts/plot_bag" "$work/old.csv" --reactions -o "$work/o.png" 2>"$work/err"; then
  echo "FAIL --reactions without the columns was accepted"; failures=$((failures + 1))
elif grep -q "no reaction forces" "$work/err"; then echo "ok   --reactions on an old CSV refused"
else echo "FAIL unclear error: $(cat "$work/err")"; failures=$((failures + 1)); fi
# The old CSV still plots (without the power panel).
if /usr/bin/python3 "$here/../../scripts/plot_bag" "$work/old.csv" -o "$work/o.png" >/dev/null; then
  echo "ok   a CSV without the power columns plots"
else echo "FAIL a CSV without the power columns"; failures=$((failures + 1)); fi

total=9
if [ "$failures" -eq 0 ]; then echo "$total passed, 0 failed"; else echo "$((total - failures)) passed, $failures failed"; exit 1; fi
