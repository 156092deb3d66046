#!/usr/bin/python3
"""Config fuzzer: mutations of config/mechanism.yaml fed to `simulate`, with a fixed seed.

Every case must end in one of the documented ways, never with a signal or a hang:
  exit 0 and a CSV whose every value is finite;
  exit 1 and a message naming a config key ("config key '...'");
  exit 3 and a refused-step message (a valid but violent config, e.g. gravity 1e300).
Mutations: values of every type and extreme (NaN, inf, 1e308, 1e-320, huge integers, strings,
lists, maps, null, booleans, binary), removed, duplicated and misplaced keys, deep nesting,
aliases, extra documents, complex keys and random bytes.

Usage: config_fuzz_test.py BUILD_DIR [CASES]
"""
import math
import os
import random
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
CONFIG = os.path.join(HERE, "..", "..", "config", "mechanism.yaml")
SEED = 20261122
OUTCOMES = {}  # exit code -> count, printed so that a fuzzer that only hits one path shows

VALUES = [".nan", ".inf", "-.inf", "1e308", "-1e308", "1e-320", "0", "-0.0", "1e-300", "-1",
          "99999999999999999999999", "0x10", "'text'", "[1, 2]", "{a: 1}", "~", "true", "''",
          "!!binary aGVsbG8=", "1e9", "1e-9", "3", "-3", "'1.0'", "0.001", "1000000", "1e300"]


def mutate(lines, rng):
    lines = list(lines)
    value_lines = [i for i, l in enumerate(lines) if l.startswith("  ") and ":" in l]
    kind = rng.randrange(10)
    if kind <= 3:  # a value replaced
        i = rng.choice(value_lines)
        key = lines[i].split(":")[0]
        lines[i] = "%s: %s" % (key, rng.choice(VALUES))
    elif kind == 4:  # a line removed
        del lines[rng.randrange(len(lines))]
    elif kind == 5:  # a line duplicated (duplicate key or section)
        i = rng.randrange(len(lines))
        lines.insert(i, lines[i])
    elif kind == 6:  # deep nesting in place of a value
        i = rng.choice(value_lines)
        depth = rng.choice([5, 50, 5000])
        lines[i] = lines[i].split(":")[0] + ": " + "[" * depth + "1" + "]" * depth
    elif kind == 7:  # anchors and aliases, or a second document
        if rng.random() < 0.5:
            lines.insert(0, "base: &b {rod_mass: 2.0}")
            i = rng.choice(value_lines) + 1
            lines[i] = lines[i].split(":")[0] + ": *b"
        else:
            lines += ["---"] + lines[: rng.randrange(len(lines))]
    elif kind == 8:  # a complex key or a misplaced section
        lines.insert(rng.randrange(len(lines)), rng.choice(["? [a, b]", ": 1", "mechanism: 5",
                                                            "  ? {x: 1}", "  : 2", "- item"]))
    else:  # random bytes somewhere
        i = rng.randrange(len(lines))
        junk = bytes(rng.randrange(256) for _ in range(rng.randrange(1, 8)))
        lines[i] = lines[i] + junk.decode("latin-1")
    return lines


def check(build_dir, text, case):
    path = os.path.join(build_dir, "fuzz_case.yaml")
    with open(path, "w", encoding="latin-1") as f:
        f.write(text)
    simulate = os.path.join(build_dir, "devel/lib/kane_sim/simulate")
    try:
        run = subprocess.run([simulate, "--config", path, "--duration", "0.05"],
                             capture_output=True, text=True, errors="replace", timeout=30)
    except subprocess.TimeoutExpired:
        return "hang (30 s)"
    err = run.stderr
    OUTCOMES[run.returncode] = OUTCOMES.get(run.returncode, 0) + 1
    if run.returncode == 0:
        rows = run.stdout.strip().splitlines()[1:]
        if not rows:
            return "exit 0 without rows"
        for row in rows:
            if not all(math.isfinite(float(v)) for v in row.split(",")):
                return "exit 0 with a non-finite value: " + row
        return None
    if run.returncode == 1:
        named = "config key '" in err or "config file: " in err  # a key, or the file itself
        return None if named else "exit 1 without naming a key or the file: " + err[-300:]
    if run.returncode == 3:
        return None if "step refused" in err else "exit 3 without a refusal: " + err[-300:]
    return "exit %d: %s" % (run.returncode, err[-300:])


def main():
    build_dir = sys.argv[1]
    cases = int(sys.argv[2]) if len(sys.argv) > 2 else 300
    with open(CONFIG) as f:
        base = f.read().splitlines()
    rng = random.Random(SEED)
    failures = []
    for case in range(cases):
        lines = base
        for _ in range(rng.choice([1, 1, 2, 3])):
            lines = mutate(lines, rng)
        text = "\n".join(lines) + "\n"
        problem = check(build_dir, text, case)
        if problem:
            failures.append((case, problem, text))
    for case, problem, text in failures[:5]:
        print("case %d: %s\n--- config ---\n%s" % (case, problem, text[:2000]))
    print("%d cases (seed %d), exit codes %s, %d failed" % (cases, SEED, sorted(OUTCOMES.items()),
                                                           len(failures)))
    # A fuzzer that never reaches the simulation (or never a refusal) tests little.
    if OUTCOMES.get(0, 0) < cases // 10 or OUTCOMES.get(1, 0) < cases // 10:
        failures.append((-1, "too few cases on one path: %s" % OUTCOMES, ""))
    print("%d passed, %d failed" % (cases - len(failures), len(failures)))
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
