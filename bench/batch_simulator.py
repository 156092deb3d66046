"""kane_sim.BatchSimulator's throughput: mechanism-steps per second (random rod masses and
starts, effort mode, a torque per mechanism every call), at 10 physics steps per call and at one
(a learning loop's step), on the CPU's widest SIMD lanes with libm's sin/cos (every lane the
single run's bits) and with the vector sin/cos, on one thread and two, and on the drivers (simd
off) for scale; the fixed cost of a call (n = 64, one step); rollout (T = 100 actions at
once); and building 10^5 and 10^6 mechanisms with distinct rod masses and k. Each figure the
best of twenty 0.1 s windows taken in turn across the rows; the machine printed first; a call's
fixed cost fitted from one and ten steps a call.
Usage: /usr/bin/python3 bench/batch_simulator.py [N]   (N = 4096; KANE_SIM_BENCH_BUILDS=0 skips
the 10^5 and 10^6 builds, 1 keeps only 10^5)"""
import os
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


# Coulomb friction at every joint (the rigs learning code randomises have it): the deterministic
# tanh in every lane, skipped where a whole block is beyond its saturation.
FRICTION = {"friction.crank_joint": 0.02, "friction.coupler_joint": 0.02,
            "friction.slider3_joint": 0.3, "friction.slider4_joint": 0.3}


class Case:
    """One row: a batch of n random mechanisms stepped `steps_per_call` physics steps a call
    (with friction: every joint's, and torques of +-12 N m that keep the crank moving)."""

    def __init__(self, n, steps_per_call, friction=False, **settings):
        rng = np.random.default_rng(0)
        params = {"mechanism.rod_mass": rng.uniform(0.8, 1.2, n),
                  "initial_state.q1": rng.uniform(-1.0, 1.0, n)}
        if friction:
            params.update(FRICTION)
        self.friction = friction
        self.torques = rng.uniform(-12.0, 12.0, (64, n)) if friction \
            else rng.uniform(-2.0, 2.0, (64, n))
        self.batch = kane_sim.BatchSimulator(n, params=params, **settings)
        self.n, self.steps, self.settings = n, steps_per_call, settings
        self.best_call = float("inf")  # seconds a call, the best window's
        self.calls = 0

    def window(self, seconds=0.1):
        calls, start = 0, time.perf_counter()
        while time.perf_counter() - start < seconds:
            self.batch.step(self.torques[self.calls % 64], self.steps)
            self.calls += 1
            calls += 1
        self.best_call = min(self.best_call, (time.perf_counter() - start) / calls)

    def rate(self):  # M mechanism-steps a second
        return self.n * self.steps / self.best_call / 1e6


def measure(cases, rounds=20):
    """Windows of 0.1 s taken in turn, case after case, `rounds` times; each case keeps its
    best: a shared machine's slow moments land on every case alike, and the best is the
    machine's own speed."""
    for _ in range(rounds):
        for case in cases:
            case.window()


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
    cases = [Case(n, 10, simd="off", threads=1),
             Case(n, 10, threads=1), Case(n, 10, threads=2),
             Case(n, 1, threads=1), Case(n, 1, threads=2),
             Case(n, 10, vector_trig=True, threads=1), Case(n, 10, vector_trig=True, threads=2),
             Case(64, 1, threads=1), Case(256, 1, threads=1),
             Case(n, 10, threads=1, friction=True), Case(n, 10, simd="off", threads=1,
                                                         friction=True)]
    measure(cases)
    print("| n | path | threads | physics steps per call | M mechanism-steps/s | us per call |")
    print("|---|---|---|---|---|---|")
    for c in cases:
        print("| %d | %s%s | %d | %d | %.1f | %.1f |"
              % (c.n, c.batch.path, ", every joint's friction" if c.friction else "",
                 c.settings["threads"], c.steps, c.rate(), c.best_call * 1e6))
    # A call's fixed cost, from one and ten steps a call (the same batch, interleaved windows):
    # call(s) = fixed + s * step.
    for one, ten in ((cases[3], cases[1]), (cases[4], cases[2])):
        step = (ten.best_call - one.best_call) / 9
        fixed = one.best_call - step
        print("n = %d, %d thread(s): a call's fixed cost %.1f us (%.1f ns a mechanism), a "
              "physics step %.1f ns a mechanism" % (n, one.settings["threads"], fixed * 1e6,
                                                    fixed / n * 1e9, step / n * 1e9))
    print("two threads / one: %.2fx at ten steps a call, %.2fx at one"
          % (cases[2].rate() / cases[1].rate(), cases[4].rate() / cases[3].rate()))
    print("rollout, T = 100, one physics step each, 2 threads: %.1f M mechanism-steps/s"
          % rollout_rate(n, threads=2))
    for size in (10 ** 5, 10 ** 6)[:int(os.environ.get("KANE_SIM_BENCH_BUILDS", "2"))]:
        seconds, per = build_randomised(size)
        print("domain randomisation, %d mechanisms with distinct rod masses and k: built in "
              "%.2f s, %.0f bytes a mechanism (peak memory growth)" % (size, seconds, per))


if __name__ == "__main__":
    main()
