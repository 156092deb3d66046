#!/usr/bin/python3
"""Command flood: three publishers each sending torque_command at 10 kHz for SECONDS, against
the node at physics 1 kHz / publish 100 Hz. Reports the node's physics rate and lateness
during the flood, its CPU use, and its RSS sampled every 5 s (flat = the subscriber queue
stays bounded: roscpp drops beyond the queue of 10).
Usage: bench/flood.py BUILD_DIR [--seconds 60] [--rate 10000] [--publishers 3]
"""
import argparse
import os
import sys

from node_perf import Master, cpu_model, run_case


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("build_dir", nargs="?", default=os.environ.get("KANE_SIM_BUILD_DIR", ""))
    parser.add_argument("--seconds", type=float, default=60.0)
    parser.add_argument("--rate", type=float, default=10000.0, help="[Hz] per publisher")
    parser.add_argument("--publishers", type=int, default=3)
    args = parser.parse_args()
    lib = os.path.join(args.build_dir, "devel/lib/kane_sim")
    flood = [[os.path.join(args.build_dir, "bench_bin", "torque_flood"), str(args.rate), str(args.seconds + 5), str(v)]
             for v in (1.0, -2.0, 3.0)[: args.publishers]]
    with Master("kane_sim_flood") as master:
        r = run_case(os.path.join(lib, "kane_sim_node"), master.env, "flood",
                     {"simulation/physics_rate": 1000.0, "simulation/publish_rate": 100.0},
                     args.seconds, load_commands=flood)
    if r is None:
        print("no diagnostics received")
        return 1
    samples = r["rss_samples"]
    print("CPU: %s, %d cores" % (cpu_model(), os.cpu_count()))
    print("Flood: %d publishers x %.0f Hz for %.0f s" % (args.publishers, args.rate, args.seconds))
    print("| commands received [1/s] | physics rate [Hz] | ticks on time | lateness p50 / p99 (median window) / max [us] "
          "| node CPU [% of one core] | RSS first / max / last [MiB] |")
    print("|---|---|---|---|---|---|")
    print("| %.0f | %.1f | %.3f %% | %.0f / %.0f / %.0f | %.1f | %.1f / %.1f / %.1f |"
          % (r["commands"], r["rate"], r["on_time"], r["p50"], r["p99"], r["max"], r["cpu"], samples[0],
             max(samples), samples[-1]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
