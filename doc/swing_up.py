#!/usr/bin/python3
"""Regenerates doc/swing_up.png: the shipped swing-up (config/swing_up.yaml, a 10 N m drive,
sensors) followed by the tracking controller (kane_sim.control.follow: the node's lockstep loop,
offline) against its plan (config/swing_up_plan.csv): the crank angle, slider 4 and the torque.
Usage: python3 doc/swing_up.py   (with the devel space sourced; needs python3-matplotlib)
"""
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import kane_sim.control  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CONFIG = os.path.join(HERE, "..", "config", "swing_up.yaml")
PLAN = os.path.join(HERE, "..", "config", "swing_up_plan.csv")


def main():
    run = kane_sim.control.follow(CONFIG, PLAN, duration=6.0)
    rows = [l for l in open(PLAN) if not l.startswith("#")][1:]
    plan = np.array([[float(v) for v in l.split(",")] for l in rows])
    t = run["t"]
    fig, axes = plt.subplots(3, 1, figsize=(8, 7), sharex=True)
    axes[0].plot(plan[:, 0], plan[:, 1], "k--", lw=1, label="plan")
    axes[0].plot(t, run["x"][:, 0], lw=1.2, label="followed (sensors, lockstep)")
    axes[0].axhline(math.pi, color="grey", lw=0.5)
    axes[0].set_ylabel("crank q1 [rad]")
    axes[0].legend(loc="lower right")
    axes[1].plot(plan[:, 0], plan[:, 2], "k--", lw=1)
    axes[1].plot(t, run["x"][:, 1], lw=1.2)
    axes[1].set_ylabel("slider 4 q2 [m]")
    axes[2].step(plan[:, 0], plan[:, 5], "k--", lw=1, where="post", label="plan's feedforward")
    axes[2].plot(t, run["torque"], lw=0.8, label="applied")
    axes[2].axhline(10, color="grey", lw=0.5)
    axes[2].axhline(-10, color="grey", lw=0.5)
    axes[2].set_ylabel("torque M_m [N m]")
    axes[2].set_xlabel("t [s]")
    axes[2].legend(loc="lower right")
    fig.suptitle("Swing-up: a 10 N m drive where gravity needs 22.6 N m; then the goal's LQR holds")
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "swing_up.png"), dpi=90)


if __name__ == "__main__":
    main()
