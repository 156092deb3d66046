#!/usr/bin/python3
"""The estimator's speed (bench/run_all.sh runs it): an hour of 200 Hz readings replayed through
kane_sim.Estimator.run (observer --bag's loop, the bag reading aside), and the observer node's
CPU beside kane_sim_node with 1 kHz sensor readings (from /proc, over the node's own run).
Prints a Markdown table; the machine is run_all.sh's header.
Usage: bench/estimator_speed.py [NODE_SECONDS (default 20)]
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
    config = rig(200.0)
    sim = kane_sim.Simulator(config)
    torque = lambda t, x: 6.0 * math.sin(2 * math.pi * 0.6 * t) + 3.0 * math.sin(7.0 * t)  # noqa
    r = sim.run(3600.0, torque=torque, output_rate=1, states_only=True)
    s = r.sensors
    effort = 6.0 * np.sin(2 * np.pi * 0.6 * s["sample_t"]) + 3.0 * np.sin(7.0 * s["sample_t"])
    start = time.perf_counter()
    rows, summary = kane_sim.Estimator(config).run(s["t"], s["position"][:, 0],
                                                   s["position"][:, 3], effort,
                                                   s["velocity"][:, 0], s["velocity"][:, 3])
    seconds = time.perf_counter() - start
    return len(s["t"]), seconds, summary["alarm"]["level"]


def cpu_seconds(pid):
    with open("/proc/%d/stat" % pid) as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def node_cpu(seconds):
    config = rig(1000.0)
    config["simulation"]["publish_rate"] = 100.0
    with tempfile.NamedTemporaryFile("w", suffix=".yaml", delete=False) as f:
        yaml.safe_dump(config, f)
    env = dict(os.environ, ROS_HOSTNAME=os.environ.get("ROS_HOSTNAME", "localhost"))
    port = "11391"
    env["ROS_MASTER_URI"] = "http://localhost:%s" % port
    procs = [subprocess.Popen(["roscore", "-p", port], env=env, stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL)]
    time.sleep(3)
    subprocess.run(["rosparam", "load", f.name, "/kane_sim"], env=env, check=True)
    procs.append(subprocess.Popen(["rosrun", "kane_sim", "kane_sim_node"], env=env,
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
    observer = subprocess.Popen(["rosrun", "kane_sim", "observer", "_config:=" + f.name], env=env,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    procs.append(observer)
    # The transport's floor: topic_tools' relay takes the same messages without reading them
    # (and republishes to no one). Without topic_tools, no floor.
    relay = subprocess.Popen(["rosrun", "topic_tools", "relay", "/joint_states", "/relayed"],
                             env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    procs.append(relay)
    time.sleep(4)
    hz = subprocess.run(["timeout", "4", "rostopic", "hz", "/joint_states"], env=env,
                        capture_output=True, text=True).stdout
    rates = [float(l.split(":")[1]) for l in hz.splitlines() if "average rate" in l]
    if not rates or rates[-1] < 900:
        raise RuntimeError("joint_states at %s Hz, not 1 kHz: %s" % (rates, hz[-300:]))
    pid = int(subprocess.check_output(["pgrep", "-n", "-f", "lib/kane_sim/observer"]).split()[0])
    relay_pid = subprocess.run(["pgrep", "-n", "-f", "topic_tools/relay"], capture_output=True,
                               text=True).stdout.split()
    relay_pid = int(relay_pid[0]) if relay_pid else None
    before = cpu_seconds(pid)
    relay_before = cpu_seconds(relay_pid) if relay_pid else 0.0
    time.sleep(seconds)
    used = cpu_seconds(pid) - before
    relay_used = cpu_seconds(relay_pid) - relay_before if relay_pid else float("nan")
    for p in reversed(procs):
        p.terminate()
    for p in procs:
        p.wait(timeout=20)
    return used / seconds, relay_used / seconds


def main():
    n, seconds, level = replay_hour()
    print("| figure | value |")
    print("|---|---|")
    print("| an hour of 200 Hz readings (%d) through the estimator | %.1f s (%.2f µs per "
          "reading; alarm %s) |" % (n, seconds, 1e6 * seconds / n, level))
    share, floor = node_cpu(float(sys.argv[1]) if len(sys.argv) > 1 else 20.0)
    print("| observer node beside kane_sim_node, 1 kHz readings | %.1f %% of a core |" %
          (100 * share))
    print("| the transport's floor: topic_tools relay on the same topic, same run | %.1f %% of a "
          "core |" % (100 * floor))


if __name__ == "__main__":
    main()
