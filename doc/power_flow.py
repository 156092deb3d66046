#!/usr/bin/python3
"""Regenerates doc/power_flow.png: the power of each load and their sum dT/dt over a run of the
default mechanism with the crank and slider 4 damped (c_O 0.5 N m s/rad, c_C 2 N s/m), 15 N m
for 3 s and then none. Usage (after sourcing the devel space):
    python3 doc/power_flow.py [OUT.png]     (default: doc/power_flow.png)
"""
import os
import sys

import kane_sim

HERE = os.path.dirname(os.path.abspath(__file__))


def main(out):
    config = kane_sim.Config()  # config/mechanism.yaml
    config["damping.crank_joint"] = 0.5
    config["damping.slider4_joint"] = 2.0
    run = kane_sim.Simulator(config).run(
        6.0, torque=kane_sim.TorqueProfile.step(3.0, 15.0, 0.0), output_rate=200)
    kane_sim.plot_result(run, out, title="15 N m for 3 s, then none; crank and slider 4 damped")
    print("power flow ->", out)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "power_flow.png"))
