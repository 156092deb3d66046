#!/bin/bash
# The committed generated equations are what the derivation gives today: regenerate and compare
# (codegen/generate_equations.py --check), and make sure the comparison notices an edit.
# Usage: codegen_test.sh   (from anywhere; needs Debian's python3-sympy)
set -u
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
generator="$root/codegen/generate_equations.py"
header="$root/include/kane_sim/model/generated_equations.h"
failures=0

if /usr/bin/python3 "$generator" --check "$header"; then
  echo "ok   the committed header matches a fresh derivation"
else
  echo "FAIL the committed header differs from the derivation: run codegen/generate_equations.py"
  failures=$((failures + 1))
fi

edited=$(mktemp --suffix=.h)
trap 'rm -f "$edited"' EXIT
sed 's/const double t0 = L\*L;/const double t0 = L*L*1.0000001;/' "$header" > "$edited"
if cmp -s "$header" "$edited"; then
  echo "FAIL the edit did not apply (the header no longer has t0 = L*L): update this test"
  failures=$((failures + 1))
elif /usr/bin/python3 "$generator" --check "$edited" 2>/dev/null; then
  echo "FAIL --check accepted an edited header"
  failures=$((failures + 1))
else
  echo "ok   --check refuses an edited header"
fi
exit $((failures > 0))
