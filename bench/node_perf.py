#!/usr/bin/python3
"""Live node performance: runs kane_sim_node under its own master for each case and reports
achieved rates, tick lateness, overruns, CPU use and RSS, and the free-running real-time factor.

Lateness and overruns come from the node's own /diagnostics (1 s windows, steady clock);
CPU is (utime + stime) from /proc/PID/stat over the measured window, RSS from /proc/PID/status.
Usage: bench/node_perf.py BUILD_DIR [--seconds 60]
"""
import argparse
import os
import random
import subprocess
import sys
import time

import rospy
from diagnostic_msgs.msg import DiagnosticArray

HERE = os.path.dirname(os.path.abspath(__file__))
CONFIG = os.path.join(HERE, "..", "config", "mechanism.yaml")
CLOCK_TICKS = os.sysconf("SC_CLK_TCK")


def cpu_seconds(pid):
    with open("/proc/%d/stat" % pid) as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / CLOCK_TICKS  # utime, stime


def rss_mib(pid):
    with open("/proc/%d/status" % pid) as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def run_case(exe, env, name, settings, seconds, load_commands=(), sample_every=5.0):
    """Runs the node in namespace /perf_NAME with `settings` over config/mechanism.yaml, starts
    `load_commands` once it is up, and measures for `seconds`. The node's topics are global
    (its node name, not its namespace, is /perf_NAME)."""
    ns = "/perf_" + name
    subprocess.run(["rosparam", "load", CONFIG, ns], env=env, check=True)
    for key, value in settings.items():
        subprocess.run(["rosparam", "set", ns + "/" + key, str(value)], env=env, check=True)
    windows = []

    def on_diagnostics(msg):
        for status in msg.status:
            if ns in status.name:
                windows.append({v.key: float(v.value) for v in status.values})

    sub = rospy.Subscriber("/diagnostics", DiagnosticArray, on_diagnostics, queue_size=100)
    node = subprocess.Popen([exe, "__name:=" + ns[1:]], env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    load = []
    rss_samples = []
    try:
        time.sleep(3.0)  # start-up, first windows discarded
        load = [subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                for cmd in load_commands]
        windows.clear()
        cpu0, wall0 = cpu_seconds(node.pid), time.monotonic()
        while time.monotonic() - wall0 < seconds:
            rss_samples.append(rss_mib(node.pid))
            time.sleep(min(sample_every, max(0.0, seconds - (time.monotonic() - wall0))))
        cpu1, wall1 = cpu_seconds(node.pid), time.monotonic()
        rss = rss_mib(node.pid)
        rss_samples.append(rss)
    finally:
        for process in load:
            process.terminate()
            process.wait(timeout=10)
        node.terminate()
        node.wait(timeout=10)
        sub.unregister()
    if not windows:
        return None
    ticks = sum(w["ticks"] for w in windows)
    overruns = sum(w["overruns"] for w in windows)
    p50 = sorted(w["tick lateness p50 [us]"] for w in windows)[len(windows) // 2]
    return {
        "rate": ticks / sum(1.0 for _ in windows),  # ticks per 1 s window
        "on_time": 100.0 * (1 - overruns / ticks) if ticks else float("nan"),
        "p50": p50,
        "p99": sorted(w["tick lateness p99 [us]"] for w in windows)[len(windows) // 2],
        "p99_worst": max(w["tick lateness p99 [us]"] for w in windows),
        "max": max(w["tick lateness max [us]"] for w in windows),
        "overruns": int(overruns),
        "ticks": int(ticks),
        "cpu": 100.0 * (cpu1 - cpu0) / (wall1 - wall0),
        "rss": rss,
        "rss_samples": rss_samples,
        "rtf": sorted(w["real-time factor achieved"] for w in windows)[len(windows) // 2],
        "windows": len(windows),
        "commands": sorted(w.get("torque commands received [1/s]", 0.0) for w in windows)[len(windows) // 2],
    }


class Master:
    """roscore on a free port for the duration of a `with` block; sets this process up as a node."""

    def __init__(self, node_name):
        self.port = random.randint(20000, 40000)
        self.env = dict(os.environ, ROS_MASTER_URI="http://localhost:%d" % self.port,
                        ROS_HOSTNAME=os.environ.get("ROS_HOSTNAME", "localhost"))
        self.node_name = node_name

    def __enter__(self):
        os.environ.update(self.env)
        self.core = subprocess.Popen(["roscore", "-p", str(self.port)], env=self.env,
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        time.sleep(3.0)
        rospy.init_node(self.node_name, anonymous=True, disable_signals=True)
        return self

    def __exit__(self, *exc):
        rospy.signal_shutdown("done")
        self.core.terminate()
        self.core.wait(timeout=10)


def cpu_model():
    with open("/proc/cpuinfo") as f:
        return next((l.split(":", 1)[1].strip() for l in f if l.startswith("model name")), "?")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build_dir", nargs="?", default=os.environ.get("KANE_SIM_BUILD_DIR", ""))
    parser.add_argument("--seconds", type=float, default=60.0, help="measured window per case")
    parser.add_argument("--cases", default="all",
                        help="comma-separated case names (1kHz_100Hz, 1kHz_1kHz, 5kHz_100Hz, "
                             "hogs_normal, hogs_realtime, free) or all")
    args = parser.parse_args()
    exe = os.path.join(args.build_dir, "devel/lib/kane_sim/kane_sim_node")
    with Master("kane_sim_node_perf") as master:
        env = master.env
        print("CPU: %s, %d cores; %g s measured per case" % (cpu_model(), os.cpu_count(), args.seconds))
        print("| case | achieved physics rate [Hz] | ticks on time | lateness p50 / p99 [us] (median 1 s window) "
              "| p99 worst window / max [us] | overruns (> 1 period late) | CPU [% of one core] | RSS [MiB] |")
        print("|---|---|---|---|---|---|---|---|")
        cases = [
            ("1kHz_100Hz", "physics 1 kHz / publish 100 Hz", {"simulation/physics_rate": 1000.0, "simulation/publish_rate": 100.0}),
            ("1kHz_1kHz", "physics 1 kHz / publish 1 kHz", {"simulation/physics_rate": 1000.0, "simulation/publish_rate": 1000.0}),
            ("5kHz_100Hz", "physics 5 kHz / publish 100 Hz", {"simulation/physics_rate": 5000.0, "simulation/publish_rate": 100.0}),
        ]
        # Under load: two processes spinning on the 2 cores beside the 1 kHz loop, measured side by
        # side with simulation.realtime_priority off and at 80 (SCHED_FIFO, memory locked).
        hogs = [["/usr/bin/python3", "-c", "while True: pass"]] * 2
        cases += [
            ("hogs_normal", "1 kHz / 100 Hz, two CPU hogs, realtime_priority 0",
             {"simulation/physics_rate": 1000.0, "simulation/publish_rate": 100.0}, hogs),
            ("hogs_realtime", "1 kHz / 100 Hz, two CPU hogs, realtime_priority 80",
             {"simulation/physics_rate": 1000.0, "simulation/publish_rate": 100.0,
              "simulation/realtime_priority": 80}, hogs),
        ]
        wanted = None if args.cases == "all" else set(args.cases.split(","))
        for case in cases:
            name, label, settings = case[:3]
            if wanted is not None and name not in wanted:
                continue
            r = run_case(exe, env, name, settings, args.seconds, case[3] if len(case) > 3 else ())
            if r is None:
                print("| %s | no diagnostics received |" % label)
                continue
            print("| %s | %.1f | %.3f %% | %.0f / %.0f | %.0f / %.0f | %d of %d | %.2f | %.1f |"
                  % (label, r["rate"], r["on_time"], r["p50"], r["p99"], r["p99_worst"], r["max"],
                     r["overruns"], r["ticks"], r["cpu"], r["rss"]))
        free = None if wanted is not None and "free" not in wanted else run_case(exe, env, "free", {"simulation/publish_clock": True, "simulation/real_time_factor": 0.0,
                                           "command/timeout": 0.0}, min(args.seconds, 20.0))
        if free:
            print("\nFree-running (/clock mode, real_time_factor 0, publishing at 100 Hz sim time): "
                  "real-time factor %.0f (median of %d 1 s windows), %.0f physics steps/s, CPU %.0f %%"
                  % (free["rtf"], free["windows"], free["rate"], free["cpu"]))


if __name__ == "__main__":
    sys.exit(main())
