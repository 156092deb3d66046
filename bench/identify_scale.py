#!/usr/bin/python3
"""identify on an hour at 1 kHz: a rig of the family (test/python/identify/rigs.py, a biased
multisine, 1 kHz sensors with noise, encoder counts and latency) recorded for DURATION s into a
bag cut to /joint_states, then `identify BAG -o FITTED.yaml` as a user runs it. Prints the wall
time, the peak memory (the tool's, from wait4's rusage), the progress lines it printed on stderr
with their times, and the errors against the rig's truth.

Usage: /usr/bin/python3 bench/identify_scale.py [--duration 3600] [--rate 1000] [--seed 7]
                                                [--workdir /tmp/kane_sim_identify_scale]
(after sourcing the build's devel/setup.bash, KANE_SIM_BUILD_DIR the build folder; the bag is
made once per workdir and reused: an hour at 1 kHz is 612 MB and takes ~4 minutes)
"""
import argparse
import os
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "test",
                                "python", "identify"))
import rigs  # noqa: E402
import kane_sim  # noqa: E402


def make_bag(rig, path):
    import rosbag
    import rospy
    from sensor_msgs.msg import JointState
    data = rigs.record(rig)
    names = kane_sim._core.joint_names()
    with rosbag.Bag(path + ".part", "w") as bag:
        for k in range(len(data["t"])):
            msg = JointState()
            stamp = rospy.Time.from_sec(1e9 + data["t"][k])
            msg.header.stamp = stamp
            msg.name = [names[0], names[3]]
            msg.position = [data["q1"][k], data["q2"][k]]
            msg.velocity = [data["u1"][k], data["u2"][k]]
            msg.effort = [data["applied_torque"][k], 0.0]
            bag.write("/joint_states", msg, stamp)
    os.replace(path + ".part", path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--duration", type=float, default=3600.0)
    parser.add_argument("--rate", type=float, default=1000.0)
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--workdir", default="/tmp/kane_sim_identify_scale")
    parser.add_argument("--make-bag", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    os.makedirs(args.workdir, exist_ok=True)
    rig = rigs.draw(args.seed, regime="multisine_bias", duration=args.duration)
    rig.sensors["sensors.rate"] = args.rate
    bag = os.path.join(args.workdir, "rig_%d_%g_%g.bag" % (args.seed, args.duration, args.rate))
    if args.make_bag:
        make_bag(rig, bag)
        return
    if not os.path.exists(bag):
        # In a process of its own: the recording's gigabytes stay out of this one, whose
        # resident pages a forked child counts as its own until it execs (wait4's peak).
        start = time.monotonic()
        subprocess.run([sys.executable] + sys.argv + ["--make-bag"], check=True)
        print("made %s (%.0f MB) in %.0f s" % (bag, os.path.getsize(bag) / 1e6,
                                               time.monotonic() - start), flush=True)
    fitted = os.path.join(args.workdir, "fitted.yaml")
    start = time.monotonic()
    tool = os.path.join(os.environ["KANE_SIM_BUILD_DIR"], "devel", "lib", "kane_sim", "identify") \
        if "KANE_SIM_BUILD_DIR" in os.environ else "identify"
    proc = subprocess.Popen([tool, bag, "-o", fitted],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    lines = []
    for line in proc.stderr:
        lines.append("%7.1f s  %s" % (time.monotonic() - start, line.rstrip()))
        print(lines[-1], flush=True)
    out = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.monotonic() - start
    code = os.waitstatus_to_exitcode(status)
    print(out)
    print("%s: exit %d, %.1f s wall, peak memory %.0f MB (%s, %g s at %g Hz, %d messages)"
          % (rig, code, wall, usage.ru_maxrss / 1024, os.path.basename(bag), args.duration,
             args.rate, int(args.duration * args.rate)))
    if code == 0:
        fit = kane_sim.Config(fitted)
        truth = rig.config()
        for name in rigs.MASSES + rigs.STIFFNESS + rigs.DAMPERS:
            if truth[name]:
                print("  %-28s truth %-10.5g fitted %-10.5g error %+.3g %%"
                      % (name, truth[name], fit[name], 100 * (fit[name] / truth[name] - 1)))


if __name__ == "__main__":
    main()
