"""The Python module against the offline tool, in one run on one machine (ratios, medians of
interleaved repetitions): Simulator.run of 10 s at 1 kHz against `simulate`'s own loop time for
the same case (its printed wall time: the loop, without start-up), Simulator.rates on 1e6 states,
and what a Python callable costs per step.
Bars (issue: the mechanism in Python): run within 1.3x of simulate's loop; rates >= 20 M/s.
Usage: python3 bench/python_perf.py BUILD_DIR [REPETITIONS]"""
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import kane_sim

build = sys.argv[1]
reps = int(sys.argv[2]) if len(sys.argv) > 2 else 7
config = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "config", "mechanism.yaml")
simulate = os.path.join(build, "devel", "lib", "kane_sim", "simulate")


def simulate_loop(output_rate, csv):
    err = subprocess.run([simulate, "--config", config, "--duration", "10", "--torque", "0.5",
                          "--output-rate", str(output_rate), "--csv", csv],
                         capture_output=True, text=True, check=True).stderr
    return float(re.search(r"wall time ([0-9.e+-]+) s", err).group(1))


def python_run(output_rate):
    sim = kane_sim.Simulator(config)
    start = time.perf_counter()
    sim.run(10.0, torque=0.5, output_rate=output_rate)
    return time.perf_counter() - start


print("| case (10 s at 1 kHz, rk4, torque 0.5 N m) | simulate loop | Simulator.run | ratio |")
print("|---|---|---|---|")
with tempfile.TemporaryDirectory() as tmp:
    csv = os.path.join(tmp, "run.csv")
    for rate in (1000, 100):
        cli, py = [], []
        for _ in range(reps):  # interleaved, so that the machine's load hits both alike
            cli.append(simulate_loop(rate, csv))
            py.append(python_run(rate))
        c, p = statistics.median(cli), statistics.median(py)
        print("| outputs at %d Hz (CSV / NumPy arrays of 43 columns) | %.1f ms | %.1f ms | %.2f |"
              % (rate, 1e3 * c, 1e3 * p, p / c))

sim = kane_sim.Simulator(config)
start = time.perf_counter()
sim.run(2.0, torque=lambda t, x: 0.5, output_rate=100)
per_call = (time.perf_counter() - start) / 2000
python_run(100)
start = time.perf_counter()
for _ in range(3):
    python_run(100)
per_step = (time.perf_counter() - start) / 30000
print()
print("torque as a Python callable: %.1f us per step (%.1f us without)"
      % (1e6 * per_call, 1e6 * per_step))

rng = np.random.default_rng(1)
states = np.column_stack([rng.uniform(-3, 3, 10 ** 6), rng.uniform(0.9, 1.5, 10 ** 6),
                          rng.uniform(-5, 5, 10 ** 6), rng.uniform(-2, 2, 10 ** 6)])
sim.rates(states, 0.5)  # warm: pages, threads
times = []
for _ in range(reps):
    start = time.perf_counter()
    sim.rates(states, 0.5)
    times.append(time.perf_counter() - start)
print("rates on 1e6 states (%d threads): median %.1f ms = %.1f M states/s (best %.1f M/s)"
      % (os.cpu_count(), 1e3 * statistics.median(times), 1e6 / statistics.median(times) / 1e6,
         1e6 / min(times) / 1e6))
