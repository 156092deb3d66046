"""The machine a figure was measured on, as the benches print it: CPU model, widest instruction
set (AVX-512, AVX2 or SSE2), the cores this process may use, the platform."""
import os
import platform


def machine():
    model = flags = "?"
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name") and model == "?":
                model = line.split(":", 1)[1].strip()
            if line.startswith("flags") and flags == "?":
                have = line.split(":", 1)[1].split()
                flags = "AVX-512" if "avx512f" in have else "AVX2" if "avx2" in have else "SSE2"
    return "%s, %s, %d cores, %s" % (model, flags, len(os.sched_getaffinity(0)),
                                     platform.platform())
