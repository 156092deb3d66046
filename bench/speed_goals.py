"""The speed goals in one table, with the machine: the rk4 step against the hand-written floor,
friction's cost (every damper and Coulomb friction on) against the plain step under the same
drive (swung: moving, most friction forces saturated; held: at rest, none), `simulate` 3600 s
against the floor, and a 4096-mechanism batch's two threads against one at each SIMD width this
CPU runs (KANE_SIM_SIMD_MAX caps it as a narrower CPU would). Ratios within one run are the
stable figures on a shared machine; each is the median (bench_core, 5 repetitions) or the best
(simulate: 5 processes, each beside the floor measured just before it; the batch: twenty 0.1 s
windows taken in turn) of its run.
Usage: /usr/bin/python3 bench/speed_goals.py BUILD_DIR"""
import json
import os
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from batch_simulator import Case, machine, measure  # noqa: E402

from kane_sim import _core  # noqa: E402

CONFIG = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "config",
                      "mechanism.yaml")


def core_medians(build):
    """bench_core's medians [ns] of the plain rk4 step, the every-load step and the floor."""
    out = subprocess.run(
        [os.path.join(build, "bench_bin", "bench_core"),
         "--benchmark_filter=Rk4Step/generated|Floor", "--benchmark_repetitions=5",
         "--benchmark_min_time=0.5", "--benchmark_format=json"],
        capture_output=True, text=True, check=True, timeout=600).stdout
    medians = {b["run_name"]: b["real_time"] for b in json.loads(out)["benchmarks"]
               if b.get("aggregate_name") == "median"}
    return (medians["BM_Rk4Step/generated"], medians["BM_Rk4Step/generated_every_load"],
            medians["BM_Rk4Step/generated_swung"],
            medians["BM_Rk4Step/generated_every_load_swung"],
            medians["BM_ClosedFormRk4StepFloor"],
            medians["BM_ClosedFormRk4StepFloorDeterministicTrig"])


def floor_now(build):
    """bench_core's floor [ns], measured for 0.3 s: the yardstick beside one simulate process."""
    out = subprocess.run(
        [os.path.join(build, "bench_bin", "bench_core"),
         "--benchmark_filter=BM_ClosedFormRk4StepFloor$", "--benchmark_min_time=0.3",
         "--benchmark_format=json"], capture_output=True, text=True, check=True,
        timeout=600).stdout
    return json.loads(out)["benchmarks"][0]["real_time"]


def simulate_ratios(build, runs=5):
    """[(simulate's seconds, the floor's ns)] for `runs` whole `simulate` processes of 3600 s at
    1 kHz (CSV at 1 Hz), each measured right after the floor: on a shared VM a neighbour moves
    both by up to 40 % from one second to the next, and a pair taken together shares it."""
    simulate = os.path.join(build, "devel", "lib", "kane_sim", "simulate")
    pairs = []
    with tempfile.TemporaryDirectory() as work:
        for _ in range(runs):
            floor = floor_now(build)
            start = time.perf_counter()
            subprocess.run([simulate, "--config", CONFIG, "--duration", "3600", "--torque", "2",
                            "--output-rate", "1", "--csv", os.path.join(work, "long.csv")],
                           check=True, capture_output=True, timeout=600)
            pairs.append((time.perf_counter() - start, floor))
    return pairs


def thread_ratios(n=4096):
    """{width: (M mechanism-steps/s on 1 thread, on 2)} at ten physics steps a call."""
    out = {}
    for arch in ("avx512", "avx2", "sse2"):
        if not _core.lane_arch_available(arch):
            continue
        one, two = Case(n, 10, simd=arch, threads=1), Case(n, 10, simd=arch, threads=2)
        measure([one, two])
        out[arch] = (one.rate(), two.rate())
    return out


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    build = sys.argv[1]
    print("machine: %s" % machine())
    plain, every_load, swung, every_load_swung, floor, floor_same_trig = core_medians(build)
    pairs = sorted(simulate_ratios(build), key=lambda p: p[0] / (p[1] * 3.6e-3))
    print("| figure | measured | ratio | goal |")
    print("|---|---|---|---|")
    print("| rk4 step, plain / closed-form floor (bench_core) | %.1f / %.1f ns | %.2fx | <= 1.2x |"
          % (plain, floor, plain / floor))
    print("| rk4 step, plain / the floor with the simulator's sin and cos | %.1f / %.1f ns | "
          "%.2fx | (the math's share: %.2fx) |"
          % (plain, floor_same_trig, plain / floor_same_trig, floor_same_trig / floor))
    print("| rk4 step with every damper and friction / plain, the crank swung at 1 Hz | "
          "%.1f / %.1f ns | %.2fx | <= 1.5x |" % (every_load_swung, swung, every_load_swung / swung))
    print("| the same, held at rest (every tanh in its smooth part) | %.1f / %.1f ns | %.2fx | "
          "(the tanh's latency) |" % (every_load, plain, every_load / plain))
    ratios = [seconds / (ns * 3.6e-3) for seconds, ns in pairs]
    best = pairs[0]
    print("| simulate 3600 s / floor x 3.6e6 steps (best of %d pairs; median %.2fx) | %.2f / %.2f s "
          "| %.2fx | <= 1.3x |" % (len(pairs), ratios[len(ratios) // 2], best[0],
                                  best[1] * 3.6e-3, ratios[0]))
    for arch, (one, two) in thread_ratios().items():
        print("| BatchSimulator 4096, %s lanes, 2 threads / 1 | %.1f / %.1f M steps/s | %.2fx "
              "| >= 1.85x |" % (arch, two, one, two / one))


if __name__ == "__main__":
    main()
