#!/usr/bin/python3
"""kane_sim against what users would use instead: SymPy's KanesMethod + SciPy.

Builds the textbook example's mechanism independently with sympy.physics.mechanics (KanesMethod),
lambdifies it and integrates 10 s of the default parameters (no torque):
  (a) fixed-step rk4 at dt = 1 ms (NumPy loop over the lambdified right-hand side),
  (b) an adaptive solver at rtol = atol = 1e-9 (SciPy RK45, Dormand-Prince like dopri5),
and runs `simulate` on the same cases. Reference: SciPy DOP853 at rtol = atol = 1e-12.
Then an accuracy table of `simulate` alone: rk4 at dt = 10, 1, 0.1 ms and dopri5 at
1e-6/1e-9/1e-12 - error at 10 s, energy drift over 60 s, cost.

Wall times: the integration only (SymPy's derivation and lambdify, and simulate's process
start, are excluded; simulate reports its own loop time on stderr).
Usage: bench/compare_sympy.py BUILD_DIR
"""
import os
import re
import subprocess
import sys
import tempfile
import time

import numpy as np
import scipy
import sympy as sp
import yaml
from scipy.integrate import solve_ivp

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "test", "tools"))
from sympy_model import sympy_model  # noqa: E402  (the independent SymPy derivation)

HERE = os.path.dirname(os.path.abspath(__file__))
CONFIG = os.path.join(HERE, "..", "config", "mechanism.yaml")


def rk4(rhs, x0, dt, duration):
    x = np.array(x0, dtype=float)
    for n in range(int(round(duration / dt))):
        t = n * dt
        k1 = rhs(t, x)
        k2 = rhs(t + dt / 2, x + dt / 2 * k1)
        k3 = rhs(t + dt / 2, x + dt / 2 * k2)
        k4 = rhs(t + dt, x + dt * k3)
        x = x + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return x


def simulate(build_dir, duration, physics_rate, integrator, tolerance=1e-9, output_rate=10):
    """Runs simulate with a temporary config; returns (rows, loop wall time [s])."""
    with open(CONFIG) as f:
        config = yaml.safe_load(f)
    config["simulation"].update(physics_rate=float(physics_rate), integrator=integrator,
                                absolute_tolerance=tolerance, relative_tolerance=tolerance)
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
        yaml.safe_dump(config, f)
        path = f.name
    try:
        run = subprocess.run([os.path.join(build_dir, "devel/lib/kane_sim/simulate"), "--config", path,
                              "--duration", str(duration), "--output-rate", str(output_rate)],
                             capture_output=True, text=True, check=True)
    finally:
        os.unlink(path)
    wall = float(re.search(r"wall time ([0-9.e+-]+) s", run.stderr).group(1))
    lines = run.stdout.strip().splitlines()
    header = lines[0].split(",")
    rows = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    return {name: rows[:, i] for i, name in enumerate(header)}, wall


def main(build_dir):
    with open(CONFIG) as f:
        config = yaml.safe_load(f)
    params, s0 = config["mechanism"], config["initial_state"]
    x0 = [s0["q1"], s0["q2"], s0["u1"], s0["u2"]]
    print("SymPy %s, SciPy %s, NumPy %s" % (sp.__version__, scipy.__version__, np.__version__))
    t0 = time.perf_counter()
    rhs = sympy_model(params, x0)
    print("SymPy KanesMethod derivation + lambdify: %.2f s (not counted below)" % (time.perf_counter() - t0))

    duration = 10.0
    reference = solve_ivp(rhs, (0, duration), x0, method="DOP853", rtol=1e-12, atol=1e-12).y[:, -1]

    # The two models agree on the equations themselves: compare u' along simulate's trajectory.
    rows, _ = simulate(build_dir, duration, 1000, "rk4")
    worst = max(np.max(np.abs(rhs(0, [rows["q1"][i], rows["q2"][i], rows["u1"][i], rows["u2"][i]])[2:]
                              - [rows["u1dot"][i], rows["u2dot"][i]]))
                for i in range(len(rows["t"])))
    print("max |u'(kane_sim) - u'(SymPy)| over 101 states of a 10 s run: %.2e" % worst)

    print("\n10 s simulated, default parameters, no torque; error vs DOP853 at 1e-12")
    print("| case | tool | wall time [s] | ratio | error q1 [rad] | error q2 [m] |")
    print("|---|---|---|---|---|---|")
    start = time.perf_counter()
    x_py = rk4(rhs, x0, 1e-3, duration)
    wall_py = time.perf_counter() - start
    rows, wall_ks = simulate(build_dir, duration, 1000, "rk4")
    for tool, wall, q1, q2 in (("SymPy + NumPy rk4", wall_py, x_py[0], x_py[1]),
                               ("kane_sim simulate rk4", wall_ks, rows["q1"][-1], rows["q2"][-1])):
        print("| (a) rk4, dt = 1 ms | %s | %.4f | %.0f | %.2e | %.2e |"
              % (tool, wall, wall / wall_ks, abs(q1 - reference[0]), abs(q2 - reference[1])))
    start = time.perf_counter()
    sol = solve_ivp(rhs, (0, duration), x0, method="RK45", rtol=1e-9, atol=1e-9)
    wall_py = time.perf_counter() - start
    rows, wall_ks = simulate(build_dir, duration, 1000, "dopri5", 1e-9)
    for tool, wall, q1, q2 in (("SymPy + SciPy RK45", wall_py, sol.y[0, -1], sol.y[1, -1]),
                               ("kane_sim simulate dopri5", wall_ks, rows["q1"][-1], rows["q2"][-1])):
        print("| (b) adaptive, tol 1e-9 | %s | %.4f | %.0f | %.2e | %.2e |"
              % (tool, wall, wall / wall_ks, abs(q1 - reference[0]), abs(q2 - reference[1])))

    print("\nAccuracy of simulate: error at 10 s (vs DOP853 1e-12), max |E - E0| over 60 s "
          "without torque, wall time of the 60 s run")
    print("| integrator | step / tolerance | error q1 [rad] | error q2 [m] | energy drift 60 s [J] | cost 60 s [ms] |")
    print("|---|---|---|---|---|---|")
    cases = [("rk4", 100, 1e-9, "dt = 10 ms"), ("rk4", 1000, 1e-9, "dt = 1 ms"),
             ("rk4", 10000, 1e-9, "dt = 0.1 ms"), ("dopri5", 1000, 1e-6, "tol 1e-6"),
             ("dopri5", 1000, 1e-9, "tol 1e-9"), ("dopri5", 1000, 1e-12, "tol 1e-12")]
    for integrator, rate, tol, label in cases:
        rows, _ = simulate(build_dir, duration, rate, integrator, tol)
        long_rows, wall = simulate(build_dir, 60.0, rate, integrator, tol)
        drift = np.max(np.abs(long_rows["total_energy"] - long_rows["total_energy"][0]))
        print("| %s | %s | %.2e | %.2e | %.2e | %.1f |"
              % (integrator, label, abs(rows["q1"][-1] - reference[0]), abs(rows["q2"][-1] - reference[1]),
                 drift, wall * 1e3))


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else os.environ.get("KANE_SIM_BUILD_DIR", ""))
