"""kane_sim.BatchSimulator's throughput: mechanism-steps per second for n = 4096 mechanisms
(random rod masses and starts, effort mode, a torque per mechanism every 10 physics steps), on
the CPU's widest SIMD lanes with libm's sin/cos (every lane the single run's bits) and with the
vector sin/cos, on one thread and two, and on the drivers (simd off) for scale. Each figure the
best of three 2 s windows. Goal (issue: many mechanisms): >= 50 M mechanism-steps/s on two cores.
Usage: python3 bench/batch_simulator.py [N]"""
import sys
import time

import numpy as np

import kane_sim

n = int(sys.argv[1]) if len(sys.argv) > 1 else 4096
rng = np.random.default_rng(0)
params = {"mechanism.rod_mass": rng.uniform(0.8, 1.2, n),
          "initial_state.q1": rng.uniform(-1.0, 1.0, n)}
torques = rng.uniform(-2.0, 2.0, (64, n))


def rate(**settings):
    batch = kane_sim.BatchSimulator(n, params=params, **settings)
    best = 0.0
    for _ in range(3):
        steps, start = 0, time.perf_counter()
        while time.perf_counter() - start < 2.0:
            batch.step(torques[steps // 10 % 64], 10)
            steps += 10
        best = max(best, n * steps / (time.perf_counter() - start))
    return batch.path, best / 1e6


print("n = %d mechanisms, 10 physics steps per action" % n)
print("| path | threads | M mechanism-steps/s |")
print("|---|---|---|")
for settings in ({"simd": "off", "threads": 1}, {"threads": 1}, {"threads": 2},
                 {"vector_trig": True, "threads": 1}, {"vector_trig": True, "threads": 2},
                 {"simd": "off", "threads": 2}):
    path, m = rate(**settings)
    print("| %s | %d | %.1f |" % (path, settings["threads"], m))
