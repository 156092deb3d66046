#!/usr/bin/python3
"""The mechanism in Python, end to end: a PD law written in Python swings the crank up to
q1 = 1 rad, the motion is animated (a GIF) and the reaction forces Kane's method brings into
evidence are plotted over one crank turn driven by the velocity servo.

    source <build>/devel/setup.bash
    python3 examples/python/crank_animation.py [OUT_DIR]    # OUT_DIR/crank.gif, swing_up.png,
                                                            # reactions_one_turn.png

Runs headless (the tests run it). In a notebook, the same calls with kane_sim.animate(r,
html=True) show the animation inline."""
import os
import sys

import numpy as np

import kane_sim

out_dir = sys.argv[1] if len(sys.argv) > 1 else "."
os.makedirs(out_dir, exist_ok=True)

# 1. A controller in Python: the torque from the state before every step (a Python call per
#    step: fine for a few seconds; use arrays or kane_sim.TorqueProfile for long runs).
sim = kane_sim.Simulator()  # the package's config/mechanism.yaml
r = sim.run(2.0, torque=lambda t, x: 400 * (1.0 - x[0]) - 30 * x[2], output_rate=100)
print("PD swing-up: q1 %.3f -> %.3f rad, peak torque %.1f N m"
      % (r.q[0, 0], r.q[-1, 0], np.abs(r.applied_torque).max()))
gif = os.path.join(out_dir, "crank.gif")
kane_sim.animate(r, save=gif, fps=20)
print("animation ->", gif)
kane_sim.plot_result(r, os.path.join(out_dir, "swing_up.png"), title="PD swing-up in Python")

# 2. One crank turn at one turn per second (the velocity servo), from q1 = 0: the pins' and
#    rails' forces over the turn.
cfg = kane_sim.Config()
cfg["command.mode"] = "velocity"
turn = kane_sim.Simulator(cfg)
L = cfg["mechanism.rod_half_length"]
rest = cfg["initial_state.q2"] - 4 * L * np.cos(cfg["initial_state.q1"])  # x_C - x_B, unstretched
turn.set_state([0.0, 4 * L + rest, 2 * np.pi, 0.0])  # q1 = 0, the spring at rest, 1 turn/s
reactions = turn.run(1.0, torque=2 * np.pi, output_rate=1000)
kane_sim.plot_result(reactions, os.path.join(out_dir, "reactions_one_turn.png"), kind="reactions",
                     title="Reaction forces over one crank turn (velocity servo, 1 turn/s)")
away = np.abs(np.cos(reactions["q1"])) > 0.1  # the toggle at q1 = 90, 270 deg aside
print("one turn: |pin O| up to %.0f N away from the toggle"
      % np.max(np.hypot(reactions["pin_o_x"], reactions["pin_o_y"])[away]))
