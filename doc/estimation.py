#!/usr/bin/python3
"""Regenerates doc/estimation.png: the estimator (kane_sim.Estimator, the observer's filter) on
the simulator with config/sensors.yaml's sensors as the rig: the crank's true speed, its
velocity readings, a finite difference of its angle readings and the estimate; the spring's
force (a virtual sensor: nothing measures it) true and estimated; and the alarm when the spring
is weakened by 30 % at t = 6 s while the estimator keeps the healthy model.
Usage: python3 doc/estimation.py   (with the devel space sourced; needs python3-matplotlib)
"""
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import yaml  # noqa: E402

import kane_sim  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
CONFIG = os.path.join(HERE, "..", "config")


def rig():
    with open(os.path.join(CONFIG, "mechanism.yaml")) as f:
        config = yaml.safe_load(f)
    with open(os.path.join(CONFIG, "sensors.yaml")) as f:
        config["sensors"].update(yaml.safe_load(f)["sensors"])
    config["sensors"]["command_latency"] = 0.0  # the torque below is the effort at each sample
    return config


def main():
    config = rig()
    sim = kane_sim.Simulator(config)
    torque = lambda t, x: 6.0 * math.sin(2 * math.pi * 0.6 * t) + 3.0 * math.sin(7.0 * t)  # noqa
    first = sim.run(6.0, torque=torque, output_rate=1000)
    sim["mechanism.spring_stiffness"] = 140.0  # the fault: the spring 30 % weaker
    second = sim.run(4.0, torque=torque, output_rate=1000)
    truth = {k: np.concatenate([first[k], second[k][1:]]) for k in ("t", "u1", "spring_force")}
    readings = {k: np.concatenate([first.sensors[k], second.sensors[k]])
                for k in ("t", "sample_t", "position", "velocity")}
    effort = np.array([torque(t, None) for t in readings["sample_t"]])
    rows, summary = kane_sim.Estimator(config).run(
        readings["t"], readings["position"][:, 0], readings["position"][:, 3], effort,
        readings["velocity"][:, 0], readings["velocity"][:, 3])
    t0 = readings["t"][0]
    t = rows["t"] + t0
    fd = np.diff(readings["position"][:, 0]) / np.diff(readings["t"])

    fig, axes = plt.subplots(3, 1, figsize=(8, 7.5), sharex=True)
    axes[0].plot(readings["t"][1:], fd, color="0.75", lw=0.8, label="finite difference of q1 readings")
    axes[0].plot(readings["t"], readings["velocity"][:, 0], ".", color="0.45", ms=2,
                 label="velocity readings")
    axes[0].plot(truth["t"], truth["u1"], "k", lw=1.2, label="true u1")
    axes[0].plot(t, rows["u1"], "C0", lw=1.0, label="estimate")
    axes[0].set_ylabel("u1 [rad/s]")
    axes[0].set_ylim(np.min(truth["u1"]) - 1, np.max(truth["u1"]) + 1)
    axes[0].legend(fontsize=7, loc="upper right", ncol=2)
    axes[1].plot(truth["t"], truth["spring_force"], "k", lw=1.2, label="true (nothing measures it)")
    axes[1].plot(t, rows["spring_force"], "C1", lw=1.0, label="virtual sensor (estimate)")
    axes[1].set_ylabel("spring force [N]")
    axes[1].legend(fontsize=7, loc="upper right")
    axes[2].step(t, rows["alarm"], "C3", where="post")
    axes[2].axvline(6.0, color="0.3", ls="--", lw=1)
    axes[2].text(6.05, 1.5, "spring -30 % (the model keeps k)", fontsize=8)
    axes[2].set_yticks([0, 1, 2])
    axes[2].set_yticklabels(["OK", "WARN", "ERROR"])
    axes[2].set_xlabel("t [s]")
    axes[2].set_ylabel("alarm")
    flagged = t[np.argmax((rows["alarm"] == 2) & (t > 6.0))]
    fig.suptitle("The observer on a rig with config/sensors.yaml's sensors (100 Hz): the fault "
                 "flagged %.2f s after it" % (flagged - 6.0), fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(HERE, "estimation.png"), dpi=110)
    settled = (t > 1.0) & (t < 6.0)
    u1_true = np.interp(t, truth["t"], truth["u1"])
    print("u1 RMS error %.4f rad/s (velocity readings' sigma 0.02); spring force RMS %.3f N; "
          "flagged %.3f s after the fault" % (
              np.sqrt(np.mean((rows["u1"][settled] - u1_true[settled]) ** 2)),
              np.sqrt(np.mean((rows["spring_force"][settled]
                               - np.interp(t, truth["t"], truth["spring_force"])[settled]) ** 2)),
              flagged - 6.0))


if __name__ == "__main__":
    main()
