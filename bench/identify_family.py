#!/usr/bin/python3
"""Identification over a family of rigs it was not tuned on (test/python/identify/rigs.py):
random masses, k, dampers, friction and rod inertia, six motion regimes, random sensors, recorded
mid-run. Prints per rig what identify() decided, then the distribution: per parameter class the
median and worst relative error of what it told (not kept, not marked), also without the
parameters it named as told poorly, the coverage (share of told (rig, parameter) pairs within 3
of their reported sigma), a fresh torque (10 s of another multisine): how the fitted config
follows the rig's fresh recording (rigs.fresh_recording_error) and how it predicts the truth
restarted from the truth's states every 2 s (rigs.fresh_torque_error), against the sensors'
noise; refusals with their reasons, the wall time and peak memory.

--closed-loop: the rigs run under a controller instead (rigs.CLOSED_LOOP in turn: the PD
controller in lockstep with its commands logged, a position and a velocity servo driven by
setpoint steps with the setpoints logged; sensors at 100, 200 and 500 Hz with 2 ms of latency
jitter), fitted over a base that knows the rig's command settings (mode, gains, limit) and no
physics; the fresh recording is another setpoint sequence under the same controller.

Usage: /usr/bin/python3 bench/identify_family.py [--rigs N] [--first SEED] [--duration S]
[--closed-loop] (after sourcing the build's devel/setup.bash; N = 30, SEED = 100, the regimes in
turn; S = 0: each rig's own 20 to 120 s)
"""
import argparse
import os
import resource
import sys
import time

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "test",
                                "python", "identify"))
import rigs  # noqa: E402
from machine import machine  # noqa: E402
import kane_sim  # noqa: E402
from kane_sim import identify as ki  # noqa: E402


def _case(seed, k, args):
    """(rig, its recording, the base config, the fresh recording to follow or None)."""
    if not args.closed_loop:
        rig = rigs.draw(seed, regime=rigs.REGIMES[k % len(rigs.REGIMES)],
                        duration=args.duration or None)
        return rig, rigs.record(rig), None, None
    rig = rigs.draw_closed_loop(seed, rigs.CLOSED_LOOP[k % len(rigs.CLOSED_LOOP)],
                                duration=args.duration or None)
    base = kane_sim.Config().with_values(
        {name: value for name, value in rig.truth.items() if name.startswith("command.")})
    return rig, rigs.record_closed(rig), base, rigs.record_closed(rig, seed=1)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rigs", type=int, default=30)
    parser.add_argument("--first", type=int, default=100)
    parser.add_argument("--duration", type=float, default=0.0)
    parser.add_argument("--closed-loop", action="store_true")
    args = parser.parse_args()
    errors = {label: [] for label in rigs.CLASSES}
    well_told = {label: [] for label in rigs.CLASSES}  # not named as told poorly
    z_all, refused, walls, fresh_ratio, followed = [], [], [], [], []
    for k in range(args.rigs):
        seed = args.first + k
        rig, data, base, fresh_data = _case(seed, k, args)
        start = time.monotonic()
        try:
            fit = ki.identify(data, base, holdout=0)
        except ValueError as e:
            walls.append(time.monotonic() - start)
            refused.append((rig, "error: " + str(e)[:160]))
            print("%-44s refused before fitting: %s" % (rig, str(e)[:120]), flush=True)
            continue
        walls.append(time.monotonic() - start)
        if fit.refusal:
            refused.append((rig, fit.refusal[:160]))
            print("%-44s REFUSED (%.1f s): %s" % (rig, walls[-1], fit.refusal[:110]), flush=True)
            continue
        rows = rigs.score(rig, fit)
        fresh, noise = rigs.fresh_torque_error(rig, fit)
        fresh_ratio.append(max(fresh[0] / noise[0], fresh[1] / noise[1]))
        followed.append(max(rigs.fresh_recording_error(rig, fit, data=fresh_data)))
        worst = {}
        for name, row in rows.items():
            if not row["told"] or name == "torque_offset":
                continue
            label = rigs.parameter_class(name)
            if row["truth"] != 0:
                errors.setdefault(label, []).append(abs(row["error"]))
                if name not in fit.poorly_told:
                    well_told.setdefault(label, []).append(abs(row["error"]))
                worst[label] = max(worst.get(label, 0.0), abs(row["error"]))
            z_all.append(row["z"])
        print("%-44s ok (%.1f s): worst %s; z max %.2g; fresh recording followed to %.2g, "
              "predicted from the truth's states to %.2g x noise" % (
                  rig, walls[-1],
                  ", ".join("%s %.2g %%" % (k2, 100 * v) for k2, v in worst.items()),
                  max([r["z"] for r in rows.values() if r["told"]] or [0]), followed[-1],
                  fresh_ratio[-1]), flush=True)
    print("\nper class (told parameters whose truth is not 0): median / worst relative error")
    for label, values in errors.items():
        if values:
            print("  %-10s %4d  median %.3g %%  worst %.3g %%"
                  % (label, len(values), 100 * np.median(values), 100 * np.max(values)))
    print("the same, without those the fit named as told poorly (its error above 5 %)")
    for label, values in well_told.items():
        if values:
            print("  %-10s %4d  median %.3g %%  worst %.3g %%"
                  % (label, len(values), 100 * np.median(values), 100 * np.max(values)))
    z = np.array(z_all)
    if len(z):
        print("coverage: %.1f %% of %d told (rig, parameter) pairs within 3 sigma (median z %.2g)"
              % (100 * np.mean(z <= 3), len(z), np.median(z)))
    fresh = ("another setpoint sequence under the same controller" if args.closed_loop else
             "10 s of another multisine")
    for what, ratios in (("fresh recording (%s, the rig's sensors; the fitted config follows it "
                          "as the fit follows its data: start states, drift and lag free)" % fresh,
                          followed),
                         ("fresh torque (10 s of another multisine, the fitted config restarted "
                          "from the true rig's state every 2 s)", fresh_ratio)):
        if ratios:
            f = np.array(ratios)
            print("%s: RMS error / sensor noise median %.2g, worst %.2g; within 3x the noise: "
                  "%d of %d" % (what, np.median(f), np.max(f), np.sum(f <= 3), len(f)))
    print("refused: %d of %d rigs" % (len(refused), args.rigs))
    for rig, why in refused:
        print("  %s: %s" % (rig, why))
    print("machine:", machine())
    print("wall time per fit: median %.1f s, worst %.1f s; peak memory %.0f MB"
          % (np.median(walls), np.max(walls),
             resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024))


if __name__ == "__main__":
    main()
