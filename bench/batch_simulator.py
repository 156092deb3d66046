"""kane_sim.BatchSimulator's throughput: mechanism-steps per second (random rod masses and
starts, effort mode, a torque per mechanism every call), at 10 physics steps per call and at one
(a learning loop's step), on the CPU's widest SIMD lanes with libm's sin/cos (every lane the
single run's bits) and with the vector sin/cos, on one thread and two, and on the drivers (simd
off) for scale; the fixed cost of a call (n = 64, one step); rollout (T = 100 actions at
once); and building 10^5 and 10^6 mechanisms with distinct rod masses and k. Each figure the best of three 1 s windows; the machine printed first.
Usage: /usr/bin/python3 bench/batch_simulator.py [N]   (N = 4096)"""
import platform
import sys
import time

import numpy as np

import kane_sim
from kane_sim import _core


def machine():
    model = next((line.split(":", 1)[1].strip() for line in open("/proc/cpuinfo")
                  if line.startswith("model name")), platform.processor())
    arches = [a for a in ("avx512", "avx2", "sse2") if _core.lane_arch_available(a)]
    import os
    return "%s, %d cores, SIMD lanes: %s" % (model, len(os.sched_getaffinity(0)),
                                              ", ".join(arches))


def rate(n, steps_per_call, **settings):
    rng = np.random.default_rng(0)
    params = {"mechanism.rod_mass": rng.uniform(0.8, 1.2, n),
              "initial_state.q1": rng.uniform(-1.0, 1.0, n)}
    torques = rng.uniform(-2.0, 2.0, (64, n))
    batch = kane_sim.BatchSimulator(n, params=params, **settings)
    best, call = 0.0, 0.0
    for _ in range(3):
        calls, start = 0, time.perf_counter()
        while time.perf_counter() - start < 1.0:
            batch.step(torques[calls % 64], steps_per_call)
            calls += 1
        elapsed = time.perf_counter() - start
        if n * steps_per_call * calls / elapsed > best:
            best, call = n * steps_per_call * calls / elapsed, elapsed / calls
    return batch.path, best / 1e6, call * 1e6


def rollout_rate(n, horizon=100, **settings):
    batch = kane_sim.BatchSimulator(n, **settings)
    plan = np.random.default_rng(1).uniform(-2.0, 2.0, (n, horizon))
    best = 0.0
    for _ in range(3):
        start = time.perf_counter()
        batch.rollout(plan)
        best = max(best, n * horizon / (time.perf_counter() - start))
    return best / 1e6


def build_randomised(n):
    """Domain randomisation: n mechanisms with distinct rod masses and k, built (seconds, and the
    process's resident memory growth per mechanism)."""
    import gc
    import resource
    rng = np.random.default_rng(3)
    params = {"mechanism.rod_mass": rng.uniform(0.8, 1.2, n),
              "mechanism.spring_stiffness": rng.uniform(150.0, 250.0, n)}
    gc.collect()
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    start = time.perf_counter()
    batch = kane_sim.BatchSimulator(n, params=params, threads=2)
    elapsed = time.perf_counter() - start
    grown = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before
    batch.step(np.zeros(n), 1)
    return elapsed, grown * 1024.0 / n


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 4096
    print("machine: %s" % machine())
    print("| n | path | threads | physics steps per call | M mechanism-steps/s | us per call |")
    print("|---|---|---|---|---|---|")
    for size, steps, settings in (
            (n, 10, {"simd": "off", "threads": 1}),
            (n, 10, {"threads": 1}), (n, 10, {"threads": 2}),
            (n, 1, {"threads": 1}), (n, 1, {"threads": 2}),
            (n, 10, {"vector_trig": True, "threads": 1}),
            (n, 10, {"vector_trig": True, "threads": 2}),
            (64, 1, {"threads": 1})):
        path, m, call = rate(size, steps, **settings)
        print("| %d | %s | %d | %d | %.1f | %.1f |" % (size, path, settings["threads"], steps, m,
                                                        call))
    print("rollout, T = 100, one physics step each, 2 threads: %.1f M mechanism-steps/s"
          % rollout_rate(n, threads=2))
    for size in (10 ** 5, 10 ** 6):
        seconds, per = build_randomised(size)
        print("domain randomisation, %d mechanisms with distinct rod masses and k: built in "
              "%.2f s, %.0f bytes a mechanism (peak memory growth)" % (size, seconds, per))


if __name__ == "__main__":
    main()
