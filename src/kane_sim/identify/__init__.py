"""Fit the twin to the rig: the mechanism's parameters from recorded motion.

Kane's equations F*_r + F_r = 0 are linear in the masses, the rod inertia, the spring's stiffness
(and preload), the dampers and a torque offset, so a recorded motion (q, u, the delivered torque)
gives a linear least-squares problem Y theta = -y0. The regressor is the model's own (the C++
loads list through kane_sim._core.identification_rows: no second derivation); this module reads
the data, estimates the rates, solves, judges what the motion can tell, writes the fitted config
and validates it by simulation.

    fit = kane_sim.identify("rig.bag", "base.yaml")
    print(fit.report())
    fit.config.yaml()       # base.yaml with the estimates written in

The rates u' are not measured: they come from zero-phase Savitzky-Golay differentiation of the
recorded positions (scipy.signal.savgol_filter, cubic, its window from `bandwidth`); the torque
goes through the same filter, so both sides of the equations see the same smoothing.

The package does one job per module: data (reading), rates, least_squares, refinement,
validation, report, excitation; identify() below runs them in order.
"""
import math
import time

import numpy as np

from kane_sim import _core
from kane_sim.core import Config
from kane_sim.identify.data import (  # noqa: F401  (the public names, as before the split)
    MAX_FILE_BYTES, MAX_MAGNITUDE, MIN_SAMPLES, Motion, load_motion)
from kane_sim.identify.rates import (  # noqa: F401  (the public names, as before the split)
    DEFAULT_BANDWIDTH, NOISE_FREE_ROUGHNESS, Prepared, estimate_rates, noise_free)
from kane_sim.identify.least_squares import (  # noqa: F401  (the public names, as before the split)
    DEFAULT_METHOD, ENERGY_WINDOW, ENERGY_WINDOW_RECORDED, METHODS, QUADRATURE_TOLERANCE,
    _dissipative, _estimate, _friction, _rest_length, _rms, _system, _usable, fitted_config, parameters)
from kane_sim.identify.refinement import (  # noqa: F401  (the public names, as before the split)
    BIAS_KNOT_SPACING, CONVERGED_NOISE_FACTOR, MAX_LAG, SEGMENT_SECONDS, _refine,
    refine_segments, simulate_motion)
from kane_sim.identify.validation import (  # noqa: F401  (the public names, as before the split)
    _config_warnings, _holdout, validation)
from kane_sim.identify.report import (  # noqa: F401  (the public names, as before the split)
    Identification)
from kane_sim.identify.excitation import (  # noqa: F401  (the public names, as before the split)
    EXCITATION_DESIGN_HORIZON, excitation, pd_controller_base)

__all__ = ["Motion", "Identification", "identify", "load_motion", "excitation", "simulate_motion"]


# The least squares' samples at most (an hour at 1 kHz: every 6th), see identify().
MAX_LEAST_SQUARES_SAMPLES = 600000


def identify(data, config=None, params=None, method=DEFAULT_METHOD, bandwidth="auto",
             holdout=0.25, topic=None, validate=True, refine="auto", progress=None):
    """Identifies `params` (default: every parameter identifiable by default, parameters()) from
    `data` (a bag, a CSV, arrays or a Motion) over the base `config` (a Config, path or dict: its
    L, g, rod shape and initial state are taken as measured, its other values as the starting
    point and the fallback). method: "energy" (the work-energy form over 1 s windows: no
    accelerations) or "equations" (Kane's equations at every sample, u' from the filter).
    bandwidth: the derivative filter's [Hz], None (the data as recorded) or "auto" (None on
    noise-free data, DEFAULT_BANDWIDTH otherwise). refine: after the least squares, fit the
    re-simulated positions to the recorded ones (output error, _refine); "auto" does on measured
    (filtered) data, where the least squares is biased by the noise in its regressor. progress:
    a callable given a line of text at each stage (the CLI prints them on stderr). Returns an
    Identification. The stages: the names checked, the data read, the least squares, the output
    error, then the result judged (its held-out check, its validation, its refusal)."""
    base = Config(config)
    names = _parameter_names(base, params, method, holdout, refine)
    say = progress or (lambda text: None)
    motion, rated, prepared, notes = _read(data, topic, base, bandwidth, say)
    result = Identification()
    result.names, result.method, result.bandwidth = names, method, prepared.bandwidth
    result.notes = notes
    result.base_values = {n: _core.identification_base_value(base._core, n) for n in names}
    say("least squares: %d samples, %d parameters (%s form)" % (len(prepared), len(names), method))
    fit = _least_squares(base, names, prepared, method)
    if refine is True or (refine == "auto" and prepared.bandwidth is not None):
        _output_error(result, base, fit, motion, rated, progress)
    _record(result, base, fit, motion, prepared)
    if holdout > 0:
        say("held-out check: the least squares on the first %.0f %%" % (100 * (1 - holdout)))
        result.holdout = _holdout(base, names, prepared, method, holdout)
    if validate:
        say("validation: re-simulating the recorded torque with the fitted and the base config")
        result.validation = validation(motion, base, result.config,
                                       result.estimates.get("torque_offset", 0.0), bandwidth,
                                       start=(rated.t[0], rated.states[0]))
        result.warnings += _replay_warnings(result.validation)
    result.refusal = _refusal(result)
    return result


def _parameter_names(base, params, method, holdout, refine):
    """The names to identify (params, or every one identifiable by default), each known and none
    twice, with identify()'s other arguments checked, before any data is read."""
    if isinstance(params, str):  # "a,b" as the command line's --params
        params = [p.strip() for p in params.split(",") if p.strip()]
    names = list(params) if params is not None else \
        [p["name"] for p in _core.identifiable_parameters() if p["by_default"]]
    for name in names:
        if not isinstance(name, str):
            raise TypeError("params: names must be strings, got %r" % (name,))
    if not names:
        raise ValueError("params: name at least one parameter (kane_sim.identify.parameters())")
    _core.identification_base_value(base._core, names[0])  # an unknown name fails here, named
    # The regressor's own checks of the names (each known, none twice), before the data is read:
    # built on no samples.
    _core.identification_energy(base._core, names, np.zeros((0, 4)), np.zeros(0))
    if method not in METHODS:
        raise ValueError("method must be one of %s, got %r" % (", ".join(METHODS), method))
    if not (isinstance(holdout, (int, float)) and 0 <= holdout < 0.9):
        raise ValueError("holdout must be a fraction in [0, 0.9), got %r" % (holdout,))
    if refine not in ("auto", True, False):
        raise ValueError("refine must be 'auto', True or False, got %r" % (refine,))
    return names


def _read(data, topic, base, bandwidth, say):
    """(motion, its rates, the samples the least squares takes, notes): the data read (with its
    logged commands), its rates estimated, the samples where the sliders touch left out, and
    refused when nothing can be identified from it."""
    clock = time.monotonic()
    motion = load_motion(data, topic, base)
    say("read %d samples, %.4g s at %.4g Hz (%.1f s)" % (len(motion), motion.t[-1] - motion.t[0],
                                                         motion.rate, time.monotonic() - clock))
    rated = estimate_rates(motion, bandwidth)
    prepared = rated.select(_usable(base, rated.states))
    # An hour at 1 kHz: the least squares (and its held-out check) take every k-th filtered
    # sample, at most MAX_LEAST_SQUARES_SAMPLES (the filter's band, a few Hz, is far below
    # their rate; the energy windows' quadrature stays exact to 1e-8 of the work).
    stride = int(math.ceil(len(prepared) / MAX_LEAST_SQUARES_SAMPLES))
    notes = list(motion.notes)
    if stride > 1:
        prepared = prepared.select(slice(None, None, stride))
        notes.append("the least squares took one filtered sample in %d (%d of %d: at most %d)"
                     % (stride, len(prepared), len(rated), MAX_LEAST_SQUARES_SAMPLES))
    if len(prepared) < MIN_SAMPLES:
        raise ValueError("data (%s): %d usable samples (the sliders touch in the rest): too few"
                         % (motion.source, len(prepared)))
    if np.ptp(prepared.states[:, 0]) < 1e-6 and np.ptp(prepared.states[:, 1]) < 1e-9:
        raise ValueError("data (%s): no motion (q1 and q2 constant): nothing can be identified"
                         % motion.source)
    if not np.any(motion.torque):
        raise ValueError("data (%s): the torque is 0 throughout (a bag's effort of the crank "
                         "joint; a driver that publishes no effort gives zeros): without the "
                         "driving torque the motion fixes the parameters only up to a common "
                         "scale" % motion.source)
    return motion, rated, prepared, notes


class _Fit:
    """The estimate as it goes through the stages: theta, cov, what the least squares kept at
    the base (kept, and why: messages), what moves with a kept value (entangled), what its
    quadrature check kept (quadrature), the condition number, the residual RMS and the rows."""

    def __init__(self, names, theta, cov, kept, messages, cond, rms, entangled, quadrature,
                 rows):
        self.names, self.theta, self.cov, self.kept = names, theta, cov, kept
        self.messages, self.cond, self.rms, self.entangled = messages, cond, rms, entangled
        self.quadrature, self.rows = quadrature, rows


def _least_squares(base, names, prepared, method):
    y, b, groups, check = _system(base, names, prepared, method)
    theta, cov, kept, messages, cond, rms, entangled, quadrature = _estimate(
        base, names, y, b, groups, prepared.states, check, _rms(prepared.torque))
    theta, cov = _rest_length(names, theta, cov)
    return _Fit(names, theta, cov, kept, messages, cond, rms, entangled, quadrature, len(b))


def _refinement_start(base, fit):
    """The output error's first guess from the least squares' values. Its dissipative values are
    noisy: a negative one starts at 0. Friction's is the least reliable (a rig's came out 100
    times the truth, a config rk4 could not run): it starts at the base's value. A mass or
    stiffness the least squares put at or a little below 0 (within UNPHYSICAL_SIGMAS of its
    error: a poorly excited coordinate, a base slightly off) starts at the base's value, and
    the refinement, which keeps it positive, decides; further below is a flipped torque or wrong
    units, refused now by name (fitted_config), before the re-simulations would fail on it with
    a message about the integrator."""
    theta = fit.theta.copy()
    sigma = np.sqrt(np.maximum(np.diag(fit.cov), 0.0))
    for i, name in enumerate(fit.names):
        if name in fit.kept:
            continue
        if _friction(name):
            theta[i] = _core.identification_base_value(base._core, name)
        elif _dissipative(name) and theta[i] < 0:
            theta[i] = 0.0
        elif name != "torque_offset" and name != "spring_rest_length" and theta[i] <= 0 \
                and theta[i] > -UNPHYSICAL_SIGMAS * sigma[i]:
            theta[i] = _core.identification_base_value(base._core, name)
    fitted_config(base, dict(zip(fit.names, theta)), dict(zip(fit.names, sigma)))
    return theta


def _output_error(result, base, fit, motion, rated, progress):
    """The output-error stage (refine_segments) from the least squares' values, updating `fit`
    and result.refined. What the quadrature check kept, it fits again from the base's value: an
    effect within the energy windows' integration error can still move the positions far beyond
    their noise (a servo rig's crank friction, 0.043 N m kept at 0, re-simulated a fresh torque
    53 times the noise off)."""
    names = fit.names
    start = _refinement_start(base, fit)
    if len(fit.kept) >= len(names):
        fit.theta = start
        return
    refit = [n for n in fit.quadrature if n in fit.kept]
    fixed = [n for n in fit.kept if n not in refit]
    ls_cov = fit.cov
    fit.theta, fit.cov, result.refined = refine_segments(base, names, start, fixed, motion,
                                                         rated, progress=progress)
    if motion.servo is not None and "torque_offset" in names:
        # The servo's law made the torque in the replays: the offset is the least squares'
        # alone, with its error.
        i = names.index("torque_offset")
        fit.cov[i, :], fit.cov[:, i] = 0.0, 0.0
        fit.cov[i, i], fit.theta[i] = ls_cov[i, i], start[i]
    result.refined["least_squares"] = dict(zip(names, start))
    result.refined["refit"] = refit
    fit.kept = [n for n in fit.kept if n not in refit]
    fit.messages = [m for m in fit.messages if not any(m.startswith(n + " ") or
                                                       m.startswith(n + ":") for n in refit)]
    fit.entangled = [n for n in fit.entangled if any(
        m.startswith(k + " (kept at") and n in m for k in fit.kept for m in fit.messages)]


def _record(result, base, fit, motion, prepared):
    """The fit's numbers, what it kept and why, the fitted config and the warnings, in
    `result`."""
    result.warnings = base.warnings + _config_warnings(base, motion)
    physics_rate = base["simulation.physics_rate"]
    if prepared.bandwidth is None and not result.refined and motion.rate < 0.999 * physics_rate:
        result.warnings.append(
            "the data is noise-free but sampled at %.4g Hz, below the physics rate (%.4g Hz): "
            "the torque between its samples is not in it, and the errors above count how well "
            "the equations close, not that (a 100 Hz simulate CSV of an --excite run gave the "
            "crank damper 23 %% off at 3.8 of its errors): record at the physics rate for errors "
            "that hold" % (motion.rate, physics_rate))
    result.samples, result.rows = len(prepared), fit.rows
    result.condition_number, result.residual_rms = fit.cond, fit.rms
    result.kept, result.unidentifiable, result.entangled = fit.kept, fit.messages, fit.entangled
    for i, n in enumerate(fit.names):
        result.estimates[n] = float(fit.theta[i])
        result.std_errors[n] = float(math.sqrt(max(fit.cov[i, i], 0.0)))
    result.config, result.clipped = fitted_config(base, result.estimates, result.std_errors)


def _replay_warnings(v):
    """What the whole-run replay says when the fitted model parts from the recording by more
    than half its span: said, not refused (a recording made under a controller can part
    whatever the parameters: PD-controlled live-node recordings replayed with their true
    parameters 5.6-11.9 rad RMS off against a 2.7 rad span)."""
    if not v or "error" in v.get("fitted", {}):
        return ["the fitted model cannot be re-simulated with the recorded torque: "
                + v["fitted"]["error"]] if v else []
    out = []
    for k, unit in (("q1", "rad"), ("q2", "m")):
        rms, span = v["fitted"][k + "_rms"], v[k + "_span"]
        if not rms <= 0.5 * span:
            out.append("re-simulated open loop from the first sample with the recorded torque, "
                       "the fitted model parts from the recorded %s by %.4g %s RMS (its span: "
                       "%.4g): expected of a recording made under a controller (its torque "
                       "answers the motion); of an open-loop recording, it says the model does "
                       "not describe the data" % (k, rms, unit, span))
    return out


# How far from the base's value (a factor, either way) a mass or k may be estimated.
OFF_SCALE = 30.0
# On noise-free data, how far (a share of the span) the fitted model may replay the recording:
# simulate's CSV at 100 Hz of an --excite run replays 2.6 % off (the torque between its samples
# is not the profile's), the same with the torque 50 ms late 9.5 %.
NOISE_FREE_REPLAY_SHARE = 0.05
# How far the servo law's torque in the replays may lie from the recorded effort (medians, a
# share of the effort's) before the config's servo is refused as not the rig's.
SERVO_EFFORT_SHARE = 0.03
# How far (times their noise) a fit that passed by the torque-sampling floor may leave the
# positions before it is refused as resting on a torque the recording does not hold: the
# open-loop family's PRBS rig at 200 Hz is fitted to 6.8 times slider 4's noise; PD loops
# without their logged commands to 290 (100 Hz, lockstep) and 320 (the live node).
TORQUE_FLOOR_FACTOR = 10.0
# How far below 0 (in its standard errors) a least-squares mass or stiffness may come out and
# still be left to the refinement: beyond, the data's torque has the wrong sign or units.
UNPHYSICAL_SIGMAS = 5.0


def _lag_at_bound(refined):
    """Whether the output error's fitted lag ran into its bound (MAX_LAG either way)."""
    return abs(refined.get("lag", 0.0)) >= 0.99 * MAX_LAG


def _refusal(result):
    """Why the fit must not be written, or None: the first of the causes below that holds, each
    naming what is most likely wrong (a fit that does not converge first)."""
    for cause in (_servo_not_the_rigs, _not_converged, _torque_between_samples_guessed,
                  _lag_at_its_bound, _off_scale, _noise_free_replay_off,
                  _no_better_than_the_base):
        reason = cause(result)
        if reason:
            return reason
    return None


def _servo_not_the_rigs(result):
    """A servo replayed with its law (logged setpoints) whose torque is not the recorded effort:
    the config's gains or torque limit, or the setpoints, are not the rig's, and a fit through
    that law can follow the positions to the noise with every mass twice the truth (a base with
    kp and kd twice the rig's). With the rig's own gains the law gives the effort to a median
    0.1-0.6 % of its size over four family rigs; 10 % off in the gains, 8.5-10 %."""
    r = result.refined
    if not (r and r.get("servo_effort")):
        return None
    mismatch, effort = r["servo_effort"]
    if not mismatch > SERVO_EFFORT_SHARE * effort:
        return None
    return ("the servo's law with the config's gains gives a torque a median %.3g N m from the "
            "recorded effort (whose median is %.3g N m): the config's command section (its "
            "mode, gains and torque_limit) is not the rig's servo, or the logged setpoints are "
            "not the ones it followed; the estimates describe no model of this data"
            % (mismatch, effort))


def _not_converged(result):
    """The output-error fit left the positions further from the recording than
    CONVERGED_NOISE_FACTOR times their noise: its numbers, and their standard errors, then
    describe no model of this data."""
    r = result.refined
    if not r or r["converged"]:
        return None
    stopped = r["evaluations"] >= r["evaluation_limit"]
    causes = ["the fit stopped at its limit of %d evaluations" % r["evaluation_limit"]] \
        if stopped else []
    if _lag_at_bound(r):
        causes.insert(0, "a torque later than a sensor's latency (the positions' lag ran "
                      "into the fit's bound: %.3g ms, the bound %g ms either way)"
                      % (1e3 * r["lag"], 1e3 * MAX_LAG))
    if r.get("stalled"):
        causes.append("the fit stopped getting closer after %d evaluations (a local "
                      "minimum: a base far from the rig)" % r["evaluations"])
    fitted = set(result.names) - set(result.kept)
    if "mechanism.rod_inertia" not in fitted:
        causes.append("a parameter not fitted that matters (the rod's inertia: add "
                      "mechanism.rod_inertia to the parameters)")
    causes += ["a mechanism the base does not describe (its measured rod_half_length L "
               "and gravity g, which are not fitted)",
               "a torque that is not the one delivered (its sign, units, a lag)",
               "too little excitation for the parameters asked"]
    return ("the output-error fit left the positions at %.3g rad and %.3g m RMS from the "
            "recording, more than %g times their noise (%.3g rad, %.3g m): the estimates "
            "and their errors describe no model of this data. Most likely: %s"
            % (r["position_rms"] + (CONVERGED_NOISE_FACTOR,) + r["noise"]
               + ("; or ".join(causes),)))


def _torque_between_samples_guessed(result):
    """The fit passed only because the torque between samples is a guess (the torque-sampling
    floor): it left the positions more than TORQUE_FLOOR_FACTOR times their noise from the
    recording in a coordinate whose floor is over 3 times the noise. Its error model (the noise
    alone) does not hold there, and neither do its numbers (a 100 Hz PD loop's masses came out
    18-22 % off at 3.4-3.8 of their errors, fitted to 290 times slider 4's noise; a live one
    with the torque saturating was "fitted" to 1.56 rad RMS on a 7 rad span). A PRBS rig at 200
    Hz, fitted to 6.8 times the noise under a floor of 14, is not refused."""
    r = result.refined
    if not r:
        return None
    floor = r.get("torque_sampling", (0.0, 0.0))
    for k in (0, 1):
        misfit = r["position_rms"][k] / r["noise"][k]
        if misfit > TORQUE_FLOOR_FACTOR and floor[k] > CONVERGED_NOISE_FACTOR * r["noise"][k]:
            return ("the recorded torque steps between its samples at instants the recording "
                    "does not hold: the fit follows the positions only to %.0f times their "
                    "noise (%s %.3g %s), and that guess alone leaves them up to %.3g %s from any "
                    "model's, so the estimates rest on a torque the recording does not have. "
                    "Record the node's ~input_log with the readings (rosbag record -a: its "
                    "commands give the torque between samples), pass the commands you sent "
                    "(command_t and command columns), or record the effort at the physics rate"
                    % (misfit, ("q1", "q2")[k], r["position_rms"][k], ("rad", "m")[k],
                       floor[k], ("rad", "m")[k]))
    return None


def _lag_at_its_bound(result):
    """The lag ran into its bound: the torque and the positions are further apart in time than
    a sensor's latency (a 50 ms late effort was fitted at -25 ms to 2.3 times the noise, masses
    8-14 % off)."""
    r = result.refined
    if not (r and _lag_at_bound(r)):
        return None
    return ("the positions' lag behind the torque ran into the fit's bound (%.3g ms, the "
            "bound %g ms either way): the torque is not the one delivered when its sample "
            "says (an effort read late, stamps from another clock); the estimates describe "
            "no model of this data" % (1e3 * r["lag"], 1e3 * MAX_LAG))


def _off_scale(result):
    """A mass, the rod's inertia or k more than OFF_SCALE times from the base's (either way): no
    rig's rough values are that far off; a torque in the wrong units is (x1000 gave masses of
    1282 kg for 1.3). An estimate that far off but zero within its error is not a unit's doing:
    the motion did not tell it (a crank that barely moves leaves the rod's inertia at 0 +- its
    size)."""
    config_names = set(_core.Config.names())  # not torque_offset, spring_rest_length
    untold = []
    for name in result.names:
        if name not in config_names or name in result.kept or \
                _core.Config.role(name) not in ("inertial", "stiffness"):
            continue
        base, value = result.base_values[name], result.estimates[name]
        sigma = result.std_errors.get(name, 0.0)
        if base > 0 and not (base / OFF_SCALE <= value <= base * OFF_SCALE):
            if abs(value) <= 3.0 * sigma:
                untold.append("%s %.3g +- %.2g" % (name, value, sigma))
                continue
            return ("%s estimated %.6g, %.3g times the base's %.6g: the torque's units (N m), "
                    "or the positions' (rad, m), are not the model's, or the base is not this "
                    "mechanism" % (name, value, value / base, base))
    if untold:
        return ("the motion did not excite %s (each zero within its error, far from the base's "
                "value): drive the rig harder or longer (rosrun kane_sim identify --excite writes "
                "a torque that excites every parameter), or leave them out of --params to keep "
                "the base's" % ", ".join(untold))
    return None


def _noise_free_replay_off(result):
    """Noise-free data (a simulation's output), fitted without the output-error stage: the
    fitted model must replay it to NOISE_FREE_REPLAY_SHARE of its span (a 50 ms lag in the
    torque left 0.097 rad and was written)."""
    v = result.validation
    if not (v and result.bandwidth is None and "error" not in v.get("fitted", {})):
        return None
    for k, unit in (("q1", "rad"), ("q2", "m")):
        rms, span = v["fitted"][k + "_rms"], v[k + "_span"]
        if not rms <= NOISE_FREE_REPLAY_SHARE * span:
            return ("the data is noise-free, yet the fitted model replays its %s %.4g %s RMS "
                    "off (%.2g %% of its span): a torque that is not the one delivered "
                    "(sign, units, a lag), or a mechanism the base does not describe (its "
                    "L and g)" % (k, rms, unit, 100 * rms / span))
    return None


def _no_better_than_the_base(result):
    """The fitted parameters follow the recording no better than the base's: judged through the
    output error's segments when it ran (a whole-recording replay of full turns diverges for
    any parameters: a rig fitted to 1.5 times its noise, masses within 0.02 %, replayed no
    better than the base over 20 s), else by the whole-run replay."""
    r, v = result.refined, result.validation
    if r and "base_position_rms" in r:
        if all(not r["position_rms"][k] < r["base_position_rms"][k] for k in (0, 1)):
            return ("the base's parameters follow the recording's segments as well as the "
                    "fitted ones (q1 %.4g rad against %.4g, q2 %.4g m against %.4g): the data "
                    "cannot tell this model's parameters (too little excitation)"
                    % (r["position_rms"][0], r["base_position_rms"][0], r["position_rms"][1],
                       r["base_position_rms"][1]))
        return None
    if v and "error" not in v.get("fitted", {}) and "error" not in v.get("base", {}):
        # A base that cannot follow at all (NaN) leaves nothing to compare with: not a pass.
        worse = [k for k in ("q1", "q2") if not v["fitted"][k + "_rms"] < v["base"][k + "_rms"]
                 and np.isfinite(v["base"][k + "_rms"])]
        if len(worse) == 2:
            return ("re-simulated with the recorded torque, the fitted model follows the "
                    "recording no better than the base (q1 %.4g rad against %.4g, q2 %.4g m "
                    "against %.4g): the data cannot tell this model's parameters (too little "
                    "excitation), or the base does not describe the mechanism"
                    % (v["fitted"]["q1_rms"], v["base"]["q1_rms"], v["fitted"]["q2_rms"],
                       v["base"]["q2_rms"]))
    return None
