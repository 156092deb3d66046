#!/usr/bin/python3
"""Soak: the node under a sine torque for a long time, watching for NaN, energy balance and
memory.
  phase 1: /clock mode at real_time_factor 20, until SIM_HOURS of sim time;
  phase 2: wall-clock mode at physics 1 kHz for WALL_MINUTES.
The torque 5 sin(2 pi 0.2 t) N m is commanded from here at ~200 Hz wall from the latest sim
time (10 Hz in sim time in phase 1). Phase 1 is not run at real_time_factor 0: a commander
that is not synchronised with sim time would then hold each command for seconds of sim time,
which can pump the crank over the top and spin it beyond what rk4 at 1 kHz resolves. Reports NaN count, the spread of E - W over the
run (E - W is constant for a correct simulation with a torque held between commands), and
the node's RSS sampled every 5 s.
Usage: bench/soak.py BUILD_DIR [--sim-hours 1] [--wall-minutes 10] [--integrator rk4|dopri5]
"""
import argparse
import math
import os
import subprocess
import sys
import time

import rospy
from std_msgs.msg import Float64

from node_perf import Master, cpu_model, rss_mib

sys.path.insert(0, os.path.join(os.environ.get("KANE_SIM_BUILD_DIR", ""),
                                "devel", "lib", "python3", "dist-packages"))
from kane_sim.msg import MechanismState  # noqa: E402

CONFIG = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "config", "mechanism.yaml")


def phase(master, exe, name, settings, done, limit_s):
    ns = "/soak_" + name
    subprocess.run(["rosparam", "load", CONFIG, ns], env=master.env, check=True)
    for key, value in settings.items():
        subprocess.run(["rosparam", "set", ns + "/" + key, str(value)], env=master.env, check=True)
    stats = {"n": 0, "nan": 0, "lo": math.inf, "hi": -math.inf, "t": 0.0, "max_u1": 0.0}

    def on_state(m):
        stats["n"] += 1
        values = list(m.q) + list(m.u) + [m.total_energy, m.motor_work]
        if not all(math.isfinite(v) for v in values):
            stats["nan"] += 1
            return
        balance = m.total_energy - m.motor_work
        stats["lo"], stats["hi"] = min(stats["lo"], balance), max(stats["hi"], balance)
        stats["t"] = m.sim_time
        stats["max_u1"] = max(stats["max_u1"], abs(m.u[0]))

    sub = rospy.Subscriber("/mechanism_state", MechanismState, on_state, queue_size=100)
    pub = rospy.Publisher("/torque_command", Float64, queue_size=10)
    node = subprocess.Popen([exe, "__name:=" + ns[1:]], env=master.env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    rss, start, last_sample = [], time.monotonic(), time.monotonic()
    try:
        time.sleep(2.0)  # start-up
        while not done(stats) and time.monotonic() - start < limit_s:
            pub.publish(Float64(5.0 * math.sin(2 * math.pi * 0.2 * stats["t"])))
            now = time.monotonic()
            if now - last_sample >= 5.0:
                rss.append(rss_mib(node.pid))
                last_sample = now
            time.sleep(0.005)
        rss.append(rss_mib(node.pid))
    finally:
        node.terminate()
        node.wait(timeout=10)
        sub.unregister()
    wall = time.monotonic() - start
    print("| %s | %.0f s sim in %.0f s wall | %d | %d | %.3g | %.1f | %.1f / %.1f / %.1f |"
          % (name, stats["t"], wall, stats["n"], stats["nan"], stats["hi"] - stats["lo"],
             stats["max_u1"], rss[0], max(rss), rss[-1]))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build_dir", nargs="?", default=os.environ.get("KANE_SIM_BUILD_DIR", ""))
    parser.add_argument("--sim-hours", type=float, default=1.0)
    parser.add_argument("--wall-minutes", type=float, default=10.0)
    parser.add_argument("--integrator", default="rk4", help="rk4 | dopri5 (simulation/integrator)")
    args = parser.parse_args()
    exe = os.path.join(args.build_dir, "devel/lib/kane_sim/kane_sim_node")
    with Master("kane_sim_soak") as master:
        print("CPU: %s, %d cores" % (cpu_model(), os.cpu_count()))
        print("| phase | duration | states received | non-finite | spread of E - W [J] | max |u1| [rad/s] "
              "| RSS first / max / last [MiB] |")
        print("|---|---|---|---|---|---|---|")
        if args.sim_hours > 0:
            phase(master, exe, "fast_1h_sim_" + args.integrator,
                  {"simulation/publish_clock": True, "simulation/real_time_factor": 20.0, "command/timeout": 0.0,
                   "simulation/integrator": args.integrator},
                  lambda s: s["t"] >= args.sim_hours * 3600, limit_s=args.sim_hours * 3600)
        if args.wall_minutes > 0:
            phase(master, exe, "real_time_1kHz",
                  {"simulation/physics_rate": 1000.0, "simulation/integrator": args.integrator},
                  lambda s: False, limit_s=args.wall_minutes * 60)
    return 0


if __name__ == "__main__":
    sys.exit(main())
