"""How the fit holds: the torque on held-out data, and the fitted config re-simulated against
the recording; what of the base config the recording contradicts."""
import numpy as np

from kane_sim.identify.data import MIN_SAMPLES
from kane_sim.identify.least_squares import _estimate, _rms, _system
from kane_sim.identify.rates import estimate_rates
from kane_sim.identify.refinement import simulate_motion


def _config_warnings(base, motion):
    """What of the base config the written one keeps that the recording contradicts: the
    validation drives the recorded torque in effort mode, without a limit."""
    out = []
    peak = float(np.max(np.abs(motion.torque)))
    if peak > base["command.torque_limit"]:
        out.append("the recorded torque reaches %.4g N m, beyond the config's command.torque_limit "
                   "%.4g N m (kept in the written config: raise it to play the recording)"
                   % (peak, base["command.torque_limit"]))
    if base["command.mode"] != "effort":
        out.append("the config's command.mode is %s (kept in the written config); the fit and its "
                   "validation take the recorded effort as the torque delivered"
                   % base["command.mode"])
    return out


def _holdout(base, names, prepared, method, fraction):
    """Fit on the first (1 - fraction) of the samples; on the rest, the crank torque Kane's
    equations predict with that fit against the recorded one."""
    split = int(len(prepared) * (1 - fraction))
    if split < MIN_SAMPLES or len(prepared) - split < MIN_SAMPLES:
        return {"fraction": fraction, "skipped": "it holds %d samples and the rest %d (at least %d "
                "each)" % (len(prepared) - split, split, MIN_SAMPLES)}
    train = prepared.select(slice(0, split))
    test = prepared.select(slice(split, None))
    try:
        y, b, groups, check = _system(base, names, train, method)
        theta = _estimate(base, names, y, b, groups, train.states, check,
                          _rms(train.torque))[0]  # preload as k s0
    except ValueError as e:
        return {"fraction": fraction, "skipped": "the rest alone: %s" % e}
    y, b, _, _ = _system(base, names, test, "equations")
    # Row 0 of each sample: Y_1 theta + y0_1 = 0 with y0_1 holding the measured torque, so
    # Y_1 theta - b_1 is the measured torque minus the one the fit predicts.
    error = (y @ theta - b)[0::2]
    return {"fraction": fraction, "samples": len(test),
            "torque_rms_error": float(np.sqrt(np.mean(error ** 2))),
            "torque_rms": float(np.sqrt(np.mean(test.torque ** 2)))}


def validation(motion, base, fitted, torque_offset=0.0, bandwidth="auto", start=None):
    """RMS error of q1 and q2 when the recorded torque is re-simulated with the fitted config
    (and the fitted torque offset) and with the base config, over the whole recording, from
    `start` ((t, state), the filter's first; computed when not given)."""
    if start is None:
        prepared = estimate_rates(motion, bandwidth)
        start = (prepared.t[0], prepared.states[0])
    out = {"duration": float(motion.t[-1] - motion.t[0]),
           "recorded": {"t": motion.t, "q": motion.q},
           "q1_span": float(np.ptp(motion.q[:, 0])), "q2_span": float(np.ptp(motion.q[:, 1]))}
    for label, config, offset in (("fitted", fitted, torque_offset), ("base", base, 0.0)):
        try:
            t, q = simulate_motion(config, motion, offset, start=start)
        except (RuntimeError, ValueError) as e:
            out[label] = {"q1_rms": float("nan"), "q2_rms": float("nan"), "error": str(e)}
            continue
        recorded = np.column_stack([np.interp(t, motion.t, motion.q[:, k]) for k in (0, 1)])
        err = q - recorded
        out[label] = {"q1_rms": float(np.sqrt(np.mean(err[:, 0] ** 2))),
                      "q2_rms": float(np.sqrt(np.mean(err[:, 1] ** 2))), "t": t, "q": q}
    return out
