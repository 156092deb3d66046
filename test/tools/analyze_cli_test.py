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

    def variant(*replacements):
        text = open(CONFIG).read()
        for old, new in replacements:
            assert old in text, old
            text = text.replace(old, new, 1)  # the first: damping.* before friction.*
        f = tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False)
        f.write(text)
        f.close()
        return f.name

    # Overdamped modes: zeta per mode, against the decoupled closed forms (2.578, 3.953).
    path = variant(("crank_joint: 0.0", "crank_joint: 10.0"), ("slider4_joint: 0.0", "slider4_joint: 100.0"))
    r = run(exe, "--config", path, "--json")
    os.unlink(path)
    zeta = json.loads(r.stdout)["damping_ratios"]
    want = [10.0 / (2 * math.sqrt(4 * g * L * (m + M1 + M2) * (2 * inertia + 2 * m * L * L))),
            100.0 / (2 * math.sqrt(k * M2))]
    check(all(abs(z - w) < 1e-7 * w for z, w in zip(zeta, want)),
          "overdamped damping ratios %s = closed forms %s" % (zeta, want))

    # Gravity 0: valid JSON whatever is undefined (null, with a note), exit 0, the crank neutral.
    path = variant(("gravity: 9.81", "gravity: 0.0"))
    r = run(exe, "--config", path, "--json")
    try:
        a = json.loads(r.stdout)
        ok = True
    except ValueError:
        a, ok = {}, False
    check(ok and r.returncode == 0, "gravity 0: --json is valid JSON, exit 0 (%d)" % r.returncode)
    check(ok and "nan" not in r.stdout and "inf" not in r.stdout, "no nan/inf tokens in the JSON")
    check(ok and a["neutral"] == [True, False] and a["damping_ratios"][0] is None
          and a["natural_frequencies_hz"][0] == 0 and any("neutral" in n for n in a["notes"]),
          "gravity 0: the crank's mode is neutral (frequency 0, ratio null, a note)")
    r = run(exe, "--config", path)
    check("neutral" in r.stdout and "Hz (" in r.stdout, "gravity 0: text names the neutral mode")
    r = run(exe, "--config", path, "--torque", "1")
    os.unlink(path)
    check(r.returncode == 3 and "mechanism.gravity 0" in r.stderr,
          "gravity 0 under a torque: no equilibrium, naming mechanism.gravity (%s)" % r.stderr.strip())

    # No --config: the package's default, said in one line.
    r = run(exe, "--json")
    check(r.returncode == 0 and "using the package's default" in r.stderr
          and json.loads(r.stdout)["natural_frequencies_hz"] == f,
          "no --config: the default config, said on stderr (%s)" % r.stderr.strip())

    print("%d passed, %d failed" % (0 if failures else 1, 1 if failures else 0))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
