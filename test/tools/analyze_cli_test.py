#!/usr/bin/python3
"""`analyze` as a user runs it: the JSON schema of the issue, the closed-form frequencies at zero
torque, the equilibrium under a torque, the error for an unholdable torque and a bad config.
Usage: analyze_cli_test.py BUILD_DIR
"""
import json
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
CONFIG = os.path.join(HERE, "..", "..", "config", "mechanism.yaml")


def run(exe, *args):
    return subprocess.run([exe, *args], capture_output=True, text=True, timeout=60)


def main(build_dir):
    exe = os.path.join(build_dir, "devel", "lib", "kane_sim", "analyze")
    failures = []

    def check(ok, what):
        print(("ok   " if ok else "FAIL ") + what)
        if not ok:
            failures.append(what)

    r = run(exe, "--config", CONFIG, "--json")
    check(r.returncode == 0, "--json exits 0 (%d: %s)" % (r.returncode, r.stderr.strip()))
    a = json.loads(r.stdout)
    for key in ("equilibrium", "A", "B", "eigenvalues", "natural_frequencies_hz", "damping_ratios"):
        check(key in a, "key %s present" % key)
    check(set(a["equilibrium"]) >= {"q1", "q2"}, "equilibrium has q1, q2")
    check(len(a["A"]) == 4 and all(len(row) == 4 for row in a["A"]), "A is 4x4")
    check(len(a["B"]) == 4, "B has 4 entries")
    check(all(len(e) == 2 for e in a["eigenvalues"]) and len(a["eigenvalues"]) == 4,
          "eigenvalues are 4 [re, im] pairs")
    f = a["natural_frequencies_hz"]
    check(f == sorted(f) and len(f) == 2, "frequencies ascending")
    check(len(a["damping_ratios"]) == len(f), "a damping ratio per frequency")
    # mechanism.yaml: m 1, L 0.25, M1 0.5, M2 0.8, k 200, g 9.81, I = m (2L)^2 / 12.
    m, L, M1, M2, k, g = 1.0, 0.25, 0.5, 0.8, 200.0, 9.81
    inertia = m * (2 * L) ** 2 / 12
    expected = sorted([math.sqrt(4 * g * L * (m + M1 + M2) / (2 * inertia + 2 * m * L * L)),
                       math.sqrt(k / M2)])
    for got, want in zip(f, expected):
        want /= 2 * math.pi
        check(abs(got - want) <= 1e-9 * want, "frequency %.12g Hz = closed form %.12g" % (got, want))
    # Rows of A in the state order (q1, q2, u1, u2): q' = u.
    check(a["A"][0][2] == 1.0 and a["A"][1][3] == 1.0, "A's first rows are q' = u")

    r = run(exe, "--config", CONFIG, "--torque", "10", "--json")
    q1 = json.loads(r.stdout)["equilibrium"]["q1"]
    want = math.asin(10 / (4 * g * L * (m + M1 + M2)))
    check(abs(q1 - want) < 1e-12, "equilibrium under 10 N m: q1 %.15g = asin(M/(4gL(m+M1+M2)))" % q1)

    r = run(exe, "--config", CONFIG, "--torque", "30")
    check(r.returncode == 3 and "beyond what gravity can hold: at most 22.563 N m" in r.stderr,
          "30 N m refused naming the limit (exit %d: %s)" % (r.returncode, r.stderr.strip()))

    r = run(exe, "--config", CONFIG)
    check(r.returncode == 0 and "Hz" in r.stdout and "Static equilibrium" in r.stdout,
          "text output by default")

    with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as bad:
        bad.write(open(CONFIG).read().replace("crank_joint: 0.0", "crank_joint: -2.0"))
    r = run(exe, "--config", bad.name)
    os.unlink(bad.name)
    check(r.returncode == 1 and "damping.crank_joint' must be >= 0, got -2" in r.stderr,
          "bad config exits 1 naming the key (%s)" % r.stderr.strip())

    print("%d passed, %d failed" % (0 if failures else 1, 1 if failures else 0))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
