#!/usr/bin/python3
"""`observer --bag` as a user runs it: a rig recorded by `simulate --bag` with config/sensors.yaml's
sensors, replayed into a CSV; the same rows as kane_sim.Estimator (one filter, two doors); the
estimate against the truth the bag also holds; and every hostile input refused with its exit
code and its words, never a NaN written.
Usage: observer_cli_test.py BUILD_DIR
"""
import math
import os
import signal
import subprocess
import sys
import tempfile

import numpy as np
import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
CONFIG_DIR = os.path.join(HERE, "..", "..", "config")


def rig_config(path):
    """config/mechanism.yaml with config/sensors.yaml over it and a little crank friction."""
    with open(os.path.join(CONFIG_DIR, "mechanism.yaml")) as f:
        config = yaml.safe_load(f)
    with open(os.path.join(CONFIG_DIR, "sensors.yaml")) as f:
        config["sensors"].update(yaml.safe_load(f)["sensors"])
    config["friction"]["crank_joint"] = 0.2
    with open(path, "w") as f:
        yaml.safe_dump(config, f)


def main(build_dir):
    lib = os.path.join(build_dir, "devel", "lib", "kane_sim")
    observer, simulate = os.path.join(lib, "observer"), os.path.join(lib, "simulate")
    failures = []

    def check(ok, what):
        print(("ok   " if ok else "FAIL ") + what)
        if not ok:
            failures.append(what)

    def run(*args, timeout=120):
        return subprocess.run([observer, *args], capture_output=True, text=True, timeout=timeout)

    tmp = tempfile.mkdtemp(prefix="observer_cli_")
    config, bag, csv = (os.path.join(tmp, n) for n in ("rig.yaml", "rig.bag", "est.csv"))
    rig_config(config)
    truth_csv = os.path.join(tmp, "truth.csv")
    r = subprocess.run([simulate, "--config", config, "--duration", "10", "--torque-sine",
                        "8,0.5", "--bag", bag, "--csv", truth_csv, "--output-rate", "1000"],
                       capture_output=True, text=True, timeout=120)
    check(r.returncode == 0, "simulate --bag records the rig (%s)" % r.stderr.strip()[-200:])

    r = run("--bag", bag, "--config", config, "--csv", csv)
    check(r.returncode == 0, "observer --bag exits 0 (%d: %s)" % (r.returncode, r.stderr.strip()))
    check("1000 rows from 1000 readings of /joint_states (0 refused, 0 restarts)" in r.stderr,
          "stderr counts the rows: " + r.stderr.strip().splitlines()[-1][:120])
    check("alarm OK" in r.stderr, "the alarm is OK on a rig that is its model")
    rows = np.genfromtxt(csv, delimiter=",", names=True)
    names = rows.dtype.names
    for column in ("t", "q1", "q2", "u1", "u2", "sigma_u1", "bias_q1", "nis", "alarm",
                   "spring_force", "rail_force_slider3", "pin_o_x", "power_crank_friction",
                   "total_energy"):
        check(column in names, "column %s" % column)
    check(all(np.all(np.isfinite(rows[c])) for c in names), "every value finite")
    check(rows["t"][0] == 0.0 and np.all(np.diff(rows["t"]) > 0), "t from the first reading, rising")

    # Against the truth: simulate's CSV at every physics step, at each reading's stamp (sim time
    # from 1e9 s in the bag; the estimate is carried to the stamp).
    sys.path.insert(0, os.path.join(build_dir, "devel", "lib", "python3", "dist-packages"))
    from kane_sim import _bag
    stamps = _bag.read_joint_states(bag, "/joint_states", "crank_joint", "slider4_joint")["t"]
    truth = np.genfromtxt(truth_csv, delimiter=",", names=True)
    sim_t = rows["t"] + (stamps[0] - 1e9)
    settled = rows["t"] > 1.0
    u1_truth = np.interp(sim_t, truth["t"], truth["u1"])
    err = np.sqrt(np.mean((rows["u1"][settled] - u1_truth[settled]) ** 2))
    check(err < 0.02, "u1 RMS error %.4f rad/s against the truth (< 0.02, the velocity "
          "sensor's sigma)" % err)

    # One filter, two doors: kane_sim.Estimator gives the same rows, bit for bit.
    import kane_sim
    py_rows, summary = kane_sim.Estimator(config).run_bag(bag)
    same = all(np.array_equal(py_rows[c], rows[c]) for c in names)
    check(same and summary["rows"] == len(rows), "kane_sim.Estimator.run_bag = observer --bag")
    check(summary["alarm"]["level"] == "OK" and summary["alarm"]["suspects"] == [],
          "a rig that is its model: OK, no parameter suspected")

    # The model's uncertainty (as identify writes it) through both doors: the same rows, and a
    # filter that claims less.
    with open(config) as f:
        uncertain = yaml.safe_load(f)
    uncertain["uncertainty"] = {"mechanism.rod_mass": 0.02, "mechanism.spring_stiffness": 4.0,
                                "friction.crank_joint": 0.03}
    uncertain_config = os.path.join(tmp, "uncertain.yaml")
    uncertain_csv = os.path.join(tmp, "uncertain.csv")
    with open(uncertain_config, "w") as f:
        yaml.safe_dump(uncertain, f)
    r = run("--bag", bag, "--config", uncertain_config, "--csv", uncertain_csv)
    check(r.returncode == 0, "observer --bag with an uncertainty: section (%s)" % r.stderr[-200:])
    u_rows = np.genfromtxt(uncertain_csv, delimiter=",", names=True)
    py_u_rows, _ = kane_sim.Estimator(uncertain_config).run_bag(bag)
    check(all(np.array_equal(py_u_rows[c], u_rows[c]) for c in names),
          "with uncertainty: kane_sim.Estimator.run_bag = observer --bag")
    check(np.median(u_rows["sigma_u1"][settled]) > np.median(rows["sigma_u1"][settled]),
          "the uncertain model claims less: median sigma_u1 %.4g > %.4g" %
          (np.median(u_rows["sigma_u1"][settled]), np.median(rows["sigma_u1"][settled])))

    # Hostile inputs: each refused with its exit code, naming what is wrong.
    def refused(args, code, words, what):
        r = run(*args)
        check(r.returncode == code and words in r.stderr,
              "%s: exit %d naming %r (got %d: %s)" % (what, code, words, r.returncode,
                                                     r.stderr.strip()[-200:]))

    refused(["--bag", os.path.join(tmp, "none.bag"), "--config", config], 3, "none.bag",
            "a missing bag")
    refused(["--bag", "/dev/zero", "--config", config], 3, "/dev/zero", "/dev/zero as the bag")
    refused(["--bag", config, "--config", config], 3, "rig.yaml", "a YAML file as the bag")
    refused(["--bag", bag, "--config", config, "--topic", "joint_state"], 3, "joint_state",
            "a topic the bag lacks")
    refused(["--bag", bag, "--config", os.path.join(tmp, "nope.yaml")], 1, "nope.yaml",
            "a missing config")
    bad = os.path.join(tmp, "bad.yaml")
    with open(bad, "w") as f:
        f.write("mechanism: {rod_mass: .nan}\n")
    refused(["--bag", bag, "--config", bad], 1, "bad config", "a config with NaN")
    with open(config) as f:
        window = yaml.safe_load(f)
    window["estimator"]["alarm_window"] = -1
    with open(bad, "w") as f:
        yaml.safe_dump(window, f)
    refused(["--bag", bag, "--config", bad], 1, "estimator.alarm_window", "a negative window")
    refused(["--bag", bag, "--config", config, "--csv", "/nonexistent/dir/x.csv"], 4,
            "/nonexistent/dir/x.csv", "an unwritable CSV")
    refused(["--bag", bag, "--frobnicate"], 2, "frobnicate", "a typo in an option")
    refused(["--bag"], 2, "bag", "--bag without its value")
    refused(["--config", config], 2, "'--bag' is required", "an option without --bag (no node)")
    refused(["--bag", bag, "extra"], 2, "positional", "a stray word")
    size = os.path.getsize(bag)
    refused(["--bag", bag, "--config", config, "--csv", bag], 2, "is the --bag file",
            "--csv naming the bag")
    check(os.path.getsize(bag) == size, "the bag untouched")
    refused(["--bag", bag, "--config", config, "--csv", config], 2, "is the --config file",
            "--csv naming the config")

    # A bag of another robot, and readings with NaN and a stamp going back.
    import rosbag
    import rospy
    from sensor_msgs.msg import JointState
    other = os.path.join(tmp, "other.bag")
    with rosbag.Bag(other, "w") as b:
        for k in range(10):
            m = JointState(name=["shoulder", "elbow"], position=[0.1 * k, 0.2], effort=[0, 0])
            m.header.stamp = rospy.Time(1 + 0.01 * k)
            b.write("/joint_states", m, m.header.stamp)
    refused(["--bag", other, "--config", config], 3, "crank_joint", "another robot's bag")
    hostile = os.path.join(tmp, "hostile.bag")
    names4 = ["crank_joint", "coupler_joint", "slider3_joint", "slider4_joint"]
    with rosbag.Bag(hostile, "w") as b:
        for k in range(300):
            q1 = 0.52 if k != 100 else float("nan")
            effort = 0.0 if k != 150 else 1e300
            stamp = 1 + 0.01 * k if k != 200 else 2.5  # 0.5 s back: refused (within restart_gap)
            # Ten messages without velocities: read without them, the rest with.
            velocity = [] if 250 <= k < 260 else [0, 0, 0, 0]
            m = JointState(name=names4, position=[q1, -1.04, 0.866, 1.166],
                           velocity=velocity, effort=[effort, 0, 0, 0])
            m.header.stamp = rospy.Time(stamp)
            b.write("/joint_states", m, rospy.Time(1 + 0.01 * k))
            if k % 50 == 25:  # another publisher on the same topic: left out, counted, named
                g = JointState(name=["gripper"], position=[0.01], effort=[0.0])
                g.header.stamp = rospy.Time(1 + 0.01 * k + 0.005)
                b.write("/joint_states", g, g.header.stamp)
    r = run("--bag", hostile, "--config", config, "--csv", csv)
    rows = np.genfromtxt(csv, delimiter=",", names=True)
    check(r.returncode == 0 and "(6 messages skipped, 3 refused, 0 restarts, 10 without "
          "velocities)" in r.stderr and "has no joint 'crank_joint' (names: gripper)" in r.stderr,
          "another publisher's messages skipped and named, velocities per message (%s)"
          % r.stderr.strip()[-400:])
    _, hostile_summary = kane_sim.Estimator(config).run_bag(hostile)
    check(hostile_summary["skipped"] == 6 and hostile_summary["rows"] == len(rows),
          "kane_sim.Estimator.run_bag skips the same messages (%s)" % hostile_summary["skipped"])
    check(r.returncode == 0 and "297 rows from 300 readings" in r.stderr and
          "crank_joint's position = nan" in r.stderr and "goes back" in r.stderr and
          "effort = 1e+300 N m is beyond command.torque_limit" in r.stderr and
          all(np.all(np.isfinite(rows[c])) for c in rows.dtype.names),
          "NaN, 1e300 N m and a stamp going back: refused by name, 297 finite rows (%s)" %
          r.stderr.strip()[-300:])

    # Ctrl-C: a long recording stops with 130, the rows so far in place.
    long_bag = os.path.join(tmp, "long.bag")
    subprocess.run([simulate, "--config", config, "--duration", "600", "--torque-sine", "8,0.5",
                    "--bag", long_bag], capture_output=True, timeout=300)
    p = subprocess.Popen([observer, "--bag", long_bag, "--config", config, "--csv", csv],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    import time
    time.sleep(0.5)
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=60)
    check(p.returncode in (130, 0), "SIGINT stops it (exit %d)" % p.returncode)

    print("%d failures" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
