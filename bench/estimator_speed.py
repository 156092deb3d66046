#!/usr/bin/python3
"""The estimator's speed (bench/run_all.sh runs it): an hour of 200 Hz readings replayed through
kane_sim.Estimator.run (observer --bag's loop, the bag reading aside), and the observer node's
CPU beside kane_sim_node with 1 kHz sensor readings (from /proc, over the node's own run),
with the tracking controller's and topic_tools relay's in the same run.
Prints a Markdown table; the machine is run_all.sh's header.
Usage: bench/estimator_speed.py [WINDOW_SECONDS (default 15; three windows)]
"""
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
import yaml

import kane_sim
import kane_sim.identify

HERE = os.path.dirname(os.path.abspath(__file__))
CONFIG_DIR = os.path.join(HERE, "..", "config")


def rig(rate):
    with open(os.path.join(CONFIG_DIR, "mechanism.yaml")) as f:
        config = yaml.safe_load(f)
    with open(os.path.join(CONFIG_DIR, "sensors.yaml")) as f:
        config["sensors"].update(yaml.safe_load(f)["sensors"])
    config["sensors"]["rate"] = rate
    config["sensors"]["command_latency"] = 0.0
    return config


def replay_hour():
    """An hour of 200 Hz readings through the estimator: its seconds, plain and with an
    uncertainty: section on every parameter identify fits (the consider filter's cost)."""
    config = rig(200.0)
    sim = kane_sim.Simulator(config)
    torque = lambda t, x: 6.0 * math.sin(2 * math.pi * 0.6 * t) + 3.0 * math.sin(7.0 * t)  # noqa
    r = sim.run(3600.0, torque=torque, output_rate=1, states_only=True)
    s = r.sensors
    effort = 6.0 * np.sin(2 * np.pi * 0.6 * s["sample_t"]) + 3.0 * np.sin(7.0 * s["sample_t"])
    loaded = kane_sim.Config(config)
    uncertain = loaded.with_values({
        "uncertainty." + p["name"]: 0.01 * max(abs(loaded[p["name"]]), 1.0)
        for p in kane_sim.identify.parameters() if "uncertainty." + p["name"] in
        kane_sim.Config.names()})
    timings = []
    for model in (loaded, uncertain):
        start = time.perf_counter()
        rows, summary = kane_sim.Estimator(model).run(s["t"], s["position"][:, 0],
                                                      s["position"][:, 3], effort,
                                                      s["velocity"][:, 0], s["velocity"][:, 3])
        timings.append((time.perf_counter() - start, summary["alarm"]["level"]))
    return len(s["t"]), timings


def cpu_seconds(pid):
    with open("/proc/%d/stat" % pid) as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def node_cpu(seconds, windows=3):
    """Each reader's share of a core over `windows` consecutive windows of `seconds`, beside
    kane_sim_node publishing joint_states at 1 kHz: {name: [share per window]}."""
    # The swing-up's rig (the plan is for its mechanism), free-running at 1 kHz readings.
    with open(os.path.join(CONFIG_DIR, "swing_up.yaml")) as f:
        config = yaml.safe_load(f)
    config["sensors"]["rate"] = 1000.0
    config["simulation"].update(lockstep=False, publish_clock=False, publish_rate=100.0)
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
        yaml.safe_dump(config, f)
    env = dict(os.environ, ROS_HOSTNAME=os.environ.get("ROS_HOSTNAME", "localhost"))
    port = "11391"
    env["ROS_MASTER_URI"] = "http://localhost:%s" % port
    procs = [subprocess.Popen(["roscore", "-p", port], env=env, stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL)]
    time.sleep(3)
    subprocess.run(["rosparam", "load", f.name, "/kane_sim"], env=env, check=True)
    readers = {
        "observer": ["rosrun", "kane_sim", "observer", "_config:=" + f.name],
        # The swing-up's tracking law answering every reading (its torque drives the sim;
        # on the wall clock the plan is soon over and its goal's LQR answers).
        "tracking_controller": ["rosrun", "kane_sim", "tracking_controller",
                                "_plan:=" + os.path.join(CONFIG_DIR, "swing_up_plan.csv"),
                                "_config:=" + f.name],
        # The transport's floor: topic_tools' relay takes the same messages without reading
        # them (and republishes to no one). Without topic_tools, no floor.
        "relay": ["rosrun", "topic_tools", "relay", "/joint_states", "/relayed"],
    }
    procs.append(subprocess.Popen(["rosrun", "kane_sim", "kane_sim_node"], env=env,
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
    for command in readers.values():
        procs.append(subprocess.Popen(command, env=env, stdout=subprocess.DEVNULL,
                                      stderr=subprocess.DEVNULL))
    time.sleep(4)
    hz = subprocess.run(["timeout", "4", "rostopic", "hz", "/joint_states"], env=env,
                        capture_output=True, text=True).stdout
    rates = [float(l.split(":")[1]) for l in hz.splitlines() if "average rate" in l]
    if not rates or rates[-1] < 900:
        raise RuntimeError("joint_states at %s Hz, not 1 kHz: %s" % (rates, hz[-300:]))
    patterns = {"observer": "lib/kane_sim/observer",
                "tracking_controller": "lib/kane_sim/tracking_controller",
                "relay": "topic_tools/relay"}
    pids = {}
    for name, pattern in patterns.items():
        found = subprocess.run(["pgrep", "-n", "-f", pattern], capture_output=True,
                               text=True).stdout.split()
        if found:
            pids[name] = int(found[0])
    shares = {name: [] for name in pids}
    for _ in range(windows):
        before = {name: cpu_seconds(pid) for name, pid in pids.items()}
        time.sleep(seconds)
        for name, pid in pids.items():
            shares[name].append((cpu_seconds(pid) - before[name]) / seconds)
    for p in reversed(procs):
        p.terminate()
    for p in procs:
        p.wait(timeout=20)
    return shares


def spread(shares):
    shares = sorted(100 * s for s in shares)
    return "%.1f %% of a core (median of %d windows; %.1f–%.1f)" % (
        shares[len(shares) // 2], len(shares), shares[0], shares[-1])


def main():
    n, timings = replay_hour()
    print("| figure | value |")
    print("|---|---|")
    for (seconds, level), what in zip(timings, ("", ", every fitted parameter uncertain")):
        print("| an hour of 200 Hz readings (%d) through the estimator%s | %.1f s (%.2f µs per "
              "reading; alarm %s) |" % (n, what, seconds, 1e6 * seconds / n, level))
    shares = node_cpu(float(sys.argv[1]) if len(sys.argv) > 1 else 15.0)
    print("| observer node beside kane_sim_node, 1 kHz readings | %s |" %
          spread(shares["observer"]))
    print("| tracking_controller answering the same readings | %s |" %
          spread(shares["tracking_controller"]))
    if "relay" in shares:
        print("| the transport's floor: topic_tools relay on the same topic, same run | %s |" %
              spread(shares["relay"]))


if __name__ == "__main__":
    main()
