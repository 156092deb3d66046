#!/bin/bash
# The committed generated files are what the derivation and the parameter table give today:
# regenerate and compare (codegen/generate_equations.py --check: the equations, their Jacobian,
# MechanismParameters and the schema's rows), and make sure the comparison notices an edit of each kind. One
# derivation checks them all (SymPy's derivation is the test's whole cost).
# Usage: codegen_test.sh   (from anywhere; needs Debian's python3-sympy and python3-yaml)
set -u
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
generator="$root/codegen/generate_equations.py"
header="$root/include/kane_sim/model/generated_equations.h"
jacobian="$root/include/kane_sim/model/generated_jacobian.h"
struct="$root/include/kane_sim/model/mechanism_parameters.h"
rows="$root/src/config/mechanism_parameter_rows.cpp"
failures=0

edited=$(mktemp -d)
out=$(mktemp)
trap 'rm -rf "$edited" "$out"' EXIT
# One edit in each generated file, under its own name (--check compares a file with the generated
# file of its name).
sed 's/const Real t0 = L\*L;/const Real t0 = L*L*1.0000001;/' "$header" > "$edited/generated_equations.h"
sed 's|jacobian.d\[1\]\[1\] = -j38\*k;|jacobian.d[1][1] = -j38*k*1.0000001;|' "$jacobian" > "$edited/generated_jacobian.h"
sed 's/double velocity_scale = 0.01;/double velocity_scale = 0.02;/' "$struct" > "$edited/mechanism_parameters.h"
sed 's/physical("friction_velocity_scale", 1e-06, 1.0)/physical("friction_velocity_scale", 1e-06, 2.0)/' \
  "$rows" > "$edited/mechanism_parameter_rows.cpp"
for f in "$header" "$jacobian" "$struct" "$rows"; do
  if cmp -s "$f" "$edited/$(basename "$f")"; then
    echo "FAIL the edit of $(basename "$f") did not apply: update this test"
    exit 1
  fi
done
/usr/bin/python3 "$generator" --check "$header" "$jacobian" "$struct" "$rows" "$edited"/* >"$out" 2>&1
status=$?
cat "$out"
for f in "$header" "$jacobian" "$struct" "$rows"; do
  if grep -q "^$f matches the derivation" "$out"; then
    echo "ok   the committed $(basename "$f") matches a fresh derivation"
  else
    echo "FAIL the committed $(basename "$f") differs: run /usr/bin/python3 codegen/generate_equations.py"
    failures=$((failures + 1))
  fi
  if grep -q "^$edited/$(basename "$f") differs from a fresh derivation" "$out" && [ "$status" -ne 0 ]; then
    echo "ok   --check refuses an edited $(basename "$f") (exit $status)"
  else
    echo "FAIL --check accepted an edited $(basename "$f")"
    failures=$((failures + 1))
  fi
done
exit $((failures > 0))
