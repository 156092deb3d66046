#!/usr/bin/python3
"""Regenerates doc/linear_response.png: a damped free response from `simulate` against the
prediction of `analyze`'s linear model about the equilibrium of the same config,
x(t) = x_eq + expm(A t) (x(0) - x_eq).
Usage: doc/linear_response.py BUILD_DIR   (needs python3-scipy, python3-matplotlib)
"""
import csv
import io
import json
import os
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.linalg import expm  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def main(build_dir):
    exe = os.path.join(build_dir, "devel", "lib", "kane_sim")
    text = open(os.path.join(HERE, "..", "config", "mechanism.yaml")).read()
    # 0.2 rad from the hanging crank, slider 4 0.3 m below slider 3; light joint damping.
    text = text.replace("q1: 0.5235987755982988", "q1: 0.2").replace(
        "q2: 1.1660254037844386", "q2: %.16g" % (4 * 0.25 * np.cos(0.2) + 0.3))
    text = text.replace("crank_joint: 0.0 ", "crank_joint: 0.05").replace(
        "slider4_joint: 0.0 ", "slider4_joint: 0.4")
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
        f.write(text)
    analysis = json.loads(subprocess.run([os.path.join(exe, "analyze"), "--config", f.name,
                                          "--json"], check=True, capture_output=True,
                                         text=True).stdout)
    sim = subprocess.run([os.path.join(exe, "simulate"), "--config", f.name, "--duration", "6"],
                         check=True, capture_output=True, text=True).stdout
    os.unlink(f.name)
    rows = list(csv.DictReader(io.StringIO(sim)))
    t = np.array([float(r["t"]) for r in rows])
    x = np.array([[float(r[k]) for k in ("q1", "q2", "u1", "u2")] for r in rows])
    A = np.array(analysis["A"])
    eq = np.array([analysis["equilibrium"]["q1"], analysis["equilibrium"]["q2"], 0, 0])
    linear = np.array([eq + expm(A * ti) @ (x[0] - eq) for ti in t])
    fig, axes = plt.subplots(2, 1, figsize=(12, 7), dpi=100, sharex=True)
    for ax, i, label in ((axes[0], 0, "q1 [rad]"), (axes[1], 1, "q2 [m]")):
        ax.plot(t, x[:, i], label="simulate (nonlinear, rk4 1 kHz)")
        ax.plot(t, linear[:, i], "--", label="linear model from analyze")
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper right")
    axes[1].set_xlabel("t [s]")
    f_hz = ", ".join("%.4f Hz (zeta %.4f)" % (f, z) for f, z in
                     zip(analysis["natural_frequencies_hz"], analysis["damping_ratios"]))
    fig.suptitle("Free response from q1 = 0.2 rad against the linear prediction: modes " + f_hz)
    fig.tight_layout()
    out = os.path.join(HERE, "linear_response.png")
    fig.savefig(out)
    error = np.abs(x[:, :2] - linear[:, :2]).max(axis=0)
    print("wrote %s; max |nonlinear - linear|: q1 %.3g rad, q2 %.3g m" % (out, error[0], error[1]))


if __name__ == "__main__":
    main(sys.argv[1])
