#!/bin/bash
# The committed generated equations are what the derivation gives today: regenerate and compare
# (codegen/generate_equations.py --check), and make sure the comparison notices an edit. One
# derivation checks both files (SymPy's derivation is the test's whole cost).
# Usage: codegen_test.sh   (from anywhere; needs Debian's python3-sympy)
set -u
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
generator="$root/codegen/generate_equations.py"
header="$root/include/kane_sim/model/generated_equations.h"
failures=0

edited=$(mktemp --suffix=.h)
out=$(mktemp)
trap 'rm -f "$edited" "$out"' EXIT
sed 's/const Real t0 = L\*L;/const Real t0 = L*L*1.0000001;/' "$header" > "$edited"
if cmp -s "$header" "$edited"; then
  echo "FAIL the edit did not apply (the header no longer has t0 = L*L): update this test"
  exit 1
fi
/usr/bin/python3 "$generator" --check "$header" "$edited" >"$out" 2>&1
status=$?
cat "$out"
if grep -q "^$header matches the derivation" "$out"; then
  echo "ok   the committed header matches a fresh derivation"
else
  echo "FAIL the committed header differs from the derivation: run codegen/generate_equations.py"
  failures=$((failures + 1))
fi
if grep -q "^$edited differs from a fresh derivation" "$out" && [ "$status" -ne 0 ]; then
  echo "ok   --check refuses an edited header (exit $status)"
else
  echo "FAIL --check accepted an edited header"
  failures=$((failures + 1))
fi
exit $((failures > 0))
