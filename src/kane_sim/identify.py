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
"""
import math
import os
from collections.abc import Mapping

import numpy as np

from kane_sim import _core, columns
from kane_sim.core import Config, Simulator

__all__ = ["Motion", "Identification", "identify", "load_motion", "excitation", "simulate_motion"]

# A file larger than this is refused before it is read (a 60 s, 1 kHz CSV of every column is
# ~60 MB; a bag of an hour's joint_states at 1 kHz ~400 MB).
MAX_FILE_BYTES = 2 << 30
# |value| beyond this in SI units is no rig's reading (1e308 would overflow the regressor).
MAX_MAGNITUDE = 1e6
MIN_SAMPLES = 50
DEFAULT_BANDWIDTH = 8.0  # [Hz] of the derivative filter: above the mechanism's modes (~1-4 Hz)


class Motion:
    """Recorded motion on a uniform time grid: t (N,), q (N, 2) = (q1, q2), u (N, 2) or None when
    the data has no velocities, torque (N,) the delivered M_m; notes: what was done to the data
    (resampling)."""

    def __init__(self, t, q, u, torque, source="arrays", notes=()):
        self.t, self.q, self.u, self.torque = t, q, u, torque
        self.source = source
        self.notes = list(notes)

    def __len__(self):
        return len(self.t)

    @property
    def rate(self):
        return (len(self.t) - 1) / (self.t[-1] - self.t[0])



def _dissipative(name):
    """A resistance's coefficient (a damper's, friction's): >= 0, 0 = off (the schema's role)."""
    return name in Config.names() and Config.role(name) == "dissipative"

def _check_file(path):
    if not os.path.exists(path):
        raise ValueError("data: %s does not exist" % path)
    if not os.path.isfile(path):
        raise ValueError("data: %s is not a regular file" % path)
    size = os.path.getsize(path)
    if size > MAX_FILE_BYTES:
        raise ValueError("data: %s is %d bytes, more than the %d this tool reads"
                         % (path, size, MAX_FILE_BYTES))
    if size == 0:
        raise ValueError("data: %s is empty" % path)


def _columns_from_mapping(data, source):
    data = columns.renamed_columns(dict(data))  # "torque" of an older CSV or script

    def column(name, required=True):
        if name not in data:
            if required:
                raise ValueError("data (%s) has no column '%s' (it needs t, q1, q2, applied_torque; u1 and "
                                 "u2 are used when present)" % (source, name))
            return None
        try:
            values = np.asarray(data[name], dtype=float)
        except (TypeError, ValueError):
            raise ValueError("data (%s): column '%s' is not numeric" % (source, name)) from None
        if values.ndim != 1:
            raise ValueError("data (%s): column '%s' must be one-dimensional, got shape %s"
                             % (source, name, values.shape))
        return values
    cols = {n: column(n) for n in ("t", "q1", "q2", "applied_torque")}
    u1, u2 = column("u1", False), column("u2", False)
    lengths = {n: len(v) for n, v in cols.items()}
    if u1 is not None and u2 is not None:
        cols["u1"], cols["u2"] = u1, u2
        lengths.update(u1=len(u1), u2=len(u2))
    if len(set(lengths.values())) != 1:
        raise ValueError("data (%s): columns of different lengths %s" % (source, lengths))
    return cols


def _read_csv(path):
    import csv
    try:
        with open(path, newline="") as f:
            header = next(csv.reader(f), None)
            has_rows = next(f, None) is not None
    except UnicodeDecodeError:
        raise ValueError("data: %s is neither a bag (.bag) nor a text CSV (it is binary)"
                         % path) from None
    if not header:
        raise ValueError("data: %s has no header line (simulate --csv writes one)" % path)
    if not has_rows:
        raise ValueError("data: %s has a header and no rows" % path)
    try:
        values = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    except ValueError as e:
        raise ValueError("data: %s: %s" % (path, e)) from None
    if values.shape[1] != len(header):
        raise ValueError("data: %s has %d columns in its header and %d in its rows"
                         % (path, len(header), values.shape[1]))
    return {name.strip(): values[:, i] for i, name in enumerate(header)}


def _read_bag(path, topic=None):
    try:
        import rosbag
    except ImportError:
        raise ValueError("data: reading %s needs rosbag (python3-rosbag)" % path) from None
    try:
        bag = rosbag.Bag(path)
    except Exception as e:  # rosbag raises its own ROSBagException, and others on garbage
        raise ValueError("data: %s is not a readable bag: %s" % (path, e)) from None
    with bag:
        types = bag.get_type_and_topic_info().topics
        states = sorted(t for t, info in types.items() if info.msg_type == "sensor_msgs/JointState")
        if topic is None:
            named = [t for t in states if t.rstrip("/").endswith("joint_states")]
            if not named:
                raise ValueError("data: %s has no joint_states topic (sensor_msgs/JointState topics: "
                                 "%s)" % (path, ", ".join(states) or "none"))
            if len(named) > 1:
                raise ValueError("data: %s has %d joint_states topics (%s): name one with topic= "
                                 "(identify --topic)" % (path, len(named), ", ".join(named)))
            topic = named[0]
        elif topic not in types:
            raise ValueError("data: %s has no topic %s (JointState topics: %s)"
                             % (path, topic, ", ".join(states) or "none"))
        elif topic not in states:
            raise ValueError("data: %s's topic %s is %s, not sensor_msgs/JointState (JointState "
                             "topics: %s)" % (path, topic, types[topic].msg_type,
                                              ", ".join(states) or "none"))
        names = _core.joint_names()
        crank, slider4 = names[0], names[3]
        rows, has_velocity = [], True
        for _, msg, stamp in bag.read_messages(topics=[topic]):
            where = {n: i for i, n in enumerate(msg.name)}
            for joint in (crank, slider4):
                if joint not in where:
                    raise ValueError("data: %s on %s has no joint '%s' (names: %s)"
                                     % (path, topic, joint, ", ".join(msg.name) or "none"))
            i, j = where[crank], where[slider4]
            if len(msg.effort) <= i:
                raise ValueError("data: %s on %s carries no effort for %s: identification needs the "
                                 "delivered torque" % (path, topic, crank))
            if len(msg.position) <= max(i, j):
                raise ValueError("data: %s on %s carries no positions" % (path, topic))
            has_velocity = has_velocity and len(msg.velocity) > max(i, j)
            t = msg.header.stamp.to_sec() or stamp.to_sec()
            u = (msg.velocity[i], msg.velocity[j]) if has_velocity else (0.0, 0.0)
            rows.append((t, msg.position[i], msg.position[j], u[0], u[1], msg.effort[i]))
    if not rows:
        raise ValueError("data: %s has no messages on %s" % (path, topic))
    a = np.array(rows, dtype=float)
    out = {"t": a[:, 0], "q1": a[:, 1], "q2": a[:, 2], "applied_torque": a[:, 5]}
    if has_velocity:
        out.update(u1=a[:, 3], u2=a[:, 4])
    return out, "%s %s" % (path, topic)


def load_motion(data, topic=None):
    """A Motion from a bag (joint_states: positions, velocities when present, effort = the
    delivered torque), a CSV of simulate's columns (t, q1, q2, u1, u2, torque), a mapping of
    arrays with those names (a kane_sim Result too) or a Motion. ValueError names what is wrong."""
    if isinstance(data, Motion):
        return data
    if isinstance(data, (str, os.PathLike)):
        path = os.fspath(data)
        _check_file(path)
        if path.endswith(".bag"):
            raw, source = _read_bag(path, topic)
        elif topic is not None:
            raise ValueError("data: topic %s is for a bag; %s is read as a CSV (a bag's name ends "
                             "in .bag)" % (topic, path))
        else:
            raw, source = _read_csv(path), path
    elif isinstance(data, Mapping):
        raw, source = data, "arrays"
    else:
        raise TypeError("data must be a bag or CSV path, a mapping of arrays or a Motion, got %s"
                        % type(data).__name__)
    cols = _columns_from_mapping(raw, source)
    return _uniform(cols, source)


def _uniform(cols, source):
    n = len(cols["t"])
    if n < MIN_SAMPLES:
        raise ValueError("data (%s): %d samples, too short to identify anything (at least %d)"
                         % (source, n, MIN_SAMPLES))
    for name, values in cols.items():
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            raise ValueError("data (%s): %s[%d] = %r is not finite (%d such rows)"
                             % (source, name, bad[0], values[bad[0]], bad.size))
        big = np.flatnonzero(np.abs(values) > MAX_MAGNITUDE)
        if big.size and name != "t":
            raise ValueError("data (%s): %s[%d] = %r is beyond any rig's reading (|x| > %g)"
                             % (source, name, big[0], values[big[0]], MAX_MAGNITUDE))
    t = cols["t"]
    dt = np.diff(t)
    bad = np.flatnonzero(dt <= 0)
    if bad.size:
        i = bad[0]
        what = "repeats" if dt[i] == 0 else "goes backward from %r" % t[i]
        raise ValueError("data (%s): time t[%d] = %r %s (%d such steps): stamps must increase"
                         % (source, i + 1, t[i + 1], what, bad.size))
    notes = []
    step = float(np.median(dt))
    if np.max(np.abs(dt - step)) > 1e-6 * step:
        # Jittered stamps (a reading stamped when it arrived) of a regular sampling: a line
        # fitted to the stamps is the sampling, when no stamp strays a third of a period from it.
        k = np.arange(n)
        slope, offset = np.polyfit(k, t - t[0], 1)
        stray = np.max(np.abs(t - t[0] - (offset + slope * k)))
        if stray < slope / 3:
            notes.append("stamps jitter up to %.3g ms about a regular %.4g s sampling: taken as "
                         "regular" % (1e3 * stray, slope))
            cols = dict(cols, t=t[0] + offset + slope * k)
        else:
            # Irregular sampling (a dropped message, a pause): linear interpolation onto the
            # median step.
            grid = t[0] + step * np.arange(int(math.floor((t[-1] - t[0]) / step + 1e-9)) + 1)
            notes.append("resampled %d irregular stamps (steps %.4g..%.4g s) onto a %.4g s grid"
                         % (n, dt.min(), dt.max(), step))
            cols = {key: (grid if key == "t" else np.interp(grid, t, v))
                    for key, v in cols.items()}
    q = np.column_stack([cols["q1"], cols["q2"]])
    u = np.column_stack([cols["u1"], cols["u2"]]) if "u1" in cols else None
    return Motion(cols["t"], q, u, cols["applied_torque"], source, notes)


def _window(rate, bandwidth, polyorder=3):
    """The Savitzky-Golay window (odd, in samples) whose -3 dB frequency is about `bandwidth`:
    f_c ~ (p + 1) / (3.2 N - 4.6) f_s (Schafer, 'What is a Savitzky-Golay filter?', 2011)."""
    n = int(round(((polyorder + 1) * rate / bandwidth + 4.6) / 3.2))
    n = max(n, polyorder + 2)
    return n + 1 if n % 2 == 0 else n


class Prepared:
    """The samples the regression sees: states (M, 4) = (q1, q2, u1, u2), u_dot (M, 2), torque
    (M,), t (M,), at the motion's indices `keep`; bandwidth: the derivative filter's [Hz], or
    None when the data is used as recorded (noise-free)."""

    def __init__(self, t, states, u_dot, torque, keep, bandwidth):
        self.t, self.states, self.u_dot, self.torque = t, states, u_dot, torque
        self.keep, self.bandwidth = keep, bandwidth

    def __len__(self):
        return len(self.t)

    def select(self, mask):
        return Prepared(self.t[mask], self.states[mask], self.u_dot[mask], self.torque[mask],
                        self.keep, self.bandwidth)


def _savgol(x, window, order, deriv, dt):
    from scipy.signal import savgol_filter
    return savgol_filter(x, window, order, deriv=deriv, delta=dt, axis=0, mode="interp")


# A 7-point quintic fit's RMS residual per unit of the positions' span (1 + span) below which
# data counts as noise-free. Measured: simulate's output 1e-11 at 1 kHz, 4e-7 at 100 Hz (the
# motion's own curvature between samples); sensors.yaml's sensors ~1e-3; a 20-bit encoder's
# rounding alone ~2e-7 (such a rig, noise-free otherwise, is taken as recorded).
NOISE_FREE_ROUGHNESS = 1e-5


def noise_free(motion):
    """True when the positions are smooth to rounding: a 7-point quintic fit leaves less than
    NOISE_FREE_ROUGHNESS (rad, m) per unit of their span (a simulation's output; a sensor's
    noise or a 12-bit encoder leaves far more)."""
    dt = 1.0 / motion.rate
    rough = motion.q - _savgol(motion.q, 7, 5, 0, dt)
    span = 1.0 + np.ptp(motion.q, axis=0)
    return bool(np.all(np.sqrt(np.mean(rough ** 2, axis=0)) < NOISE_FREE_ROUGHNESS * span))


def estimate_rates(motion, bandwidth="auto"):
    """The samples for the regression (a Prepared). bandwidth [Hz]: q, u, u' and the torque through
    one zero-phase Savitzky-Golay filter of the positions (cubic, -3 dB near `bandwidth`; the
    half-window at each end dropped). None, or "auto" on noise-free data: q, u and the torque as
    recorded (u from a 7-point quintic derivative when the data has none), u' from a 7-point
    quintic derivative of u. "auto" on measured data: DEFAULT_BANDWIDTH."""
    dt = 1.0 / motion.rate
    if isinstance(bandwidth, str):
        if bandwidth != "auto":
            raise ValueError("bandwidth must be a number of Hz, 'auto' or None, got %r" % bandwidth)
        bandwidth = None if noise_free(motion) else DEFAULT_BANDWIDTH
    if bandwidth is None:
        u = motion.u if motion.u is not None else _savgol(motion.q, 7, 5, 1, dt)
        u_dot = _savgol(u, 7, 5, 1, dt)
        keep = slice(3, len(motion) - 3)
        q, torque = motion.q, motion.torque
    else:
        if not (isinstance(bandwidth, (int, float)) and math.isfinite(bandwidth) and bandwidth > 0):
            raise ValueError("bandwidth must be a positive number of Hz, got %r" % (bandwidth,))
        if bandwidth >= motion.rate / 2:
            raise ValueError("bandwidth %.4g Hz is not below the data's Nyquist frequency %.4g Hz "
                             "(its stamps are %.4g s apart: time in seconds?)"
                             % (bandwidth, motion.rate / 2, 1.0 / motion.rate))
        window = _window(motion.rate, bandwidth)
        if len(motion) < 3 * window:
            lowest = 4 * motion.rate / max(3.2 * len(motion) / 3 - 4.6, 1e-300)
            raise ValueError("data (%s): %d samples at %.4g Hz: the %.3g Hz derivative filter's "
                             "window is longer than a third of them; give a bandwidth of at "
                             "least %.3g Hz, or record longer"
                             % (motion.source, len(motion), motion.rate, bandwidth, lowest))
        q, u, u_dot = (_savgol(motion.q, window, 3, d, dt) for d in (0, 1, 2))
        torque = _savgol(motion.torque, window, 3, 0, dt)
        keep = slice(window // 2, len(motion) - window // 2)
    c = np.ascontiguousarray
    return Prepared(c(motion.t[keep]), c(np.column_stack([q, u])[keep]), c(u_dot[keep]),
                    c(torque[keep]), keep, bandwidth)


def _effective_samples_factor(residual):
    """sqrt of the residual's integrated autocorrelation (filtered data's errors are correlated
    over the filter's window): the factor by which the i.i.d. standard errors understate."""
    r = residual - residual.mean()
    n = len(r)
    if n < 4 or not np.any(r):
        return 1.0
    spectrum = np.fft.rfft(r, 2 * n)
    acf = np.fft.irfft(spectrum * np.conj(spectrum))[:n] / np.dot(r, r)
    total = 1.0
    for k in range(1, n // 4):
        if acf[k] < 0.05:
            break
        total += 2 * acf[k]
    return math.sqrt(total)


class Identification:
    """What identify() found: `estimates` and `std_errors` by parameter name, the scaled
    regressor's `condition_number`, `unidentifiable` (messages naming what the motion could not
    tell apart; those parameters keep the base's values), `entangled` (estimates that move by more
    than 1 % when a kept value is off by its own size: named in `unidentifiable`), `config` (the
    base with the estimates written in; the torque offset is not a config value), `residual_rms`
    (N m, N), `samples`, `holdout` (cross-validation on the last part of the data: the fit of the
    rest predicting its torque; or why it was skipped), `notes`, `warnings` (the base config's
    unknown keys; what of it the recording contradicts)."""

    def __init__(self):
        self.names = []
        self.estimates = {}
        self.std_errors = {}
        self.base_values = {}
        self.kept = []
        self.unidentifiable = []
        self.entangled = []
        self.condition_number = float("nan")
        self.residual_rms = (float("nan"), float("nan"))
        self.samples = 0
        self.config = None
        self.holdout = None
        self.notes = []
        self.bandwidth = None
        self.method = DEFAULT_METHOD
        self.rows = 0
        self.clipped = []
        self.refined = None
        self.validation = None
        self.warnings = []

    def report(self):
        how = ("the work-energy form, %d windows" % self.rows if self.method == "energy"
               else "Kane's equations, %d rows" % self.rows)
        rates = ("data as recorded" if self.bandwidth is None
                 else "Savitzky-Golay %.3g Hz" % self.bandwidth)
        lines = ["identified by %s from %d samples (%s; %s); condition number %.3g"
                 % (how, self.samples, rates, ", ".join(self.notes) or "uniform stamps",
                    self.condition_number)]
        info = {p["name"]: p for p in _core.identifiable_parameters()}
        for name in self.names:
            unit = info[name]["unit"]
            if name in self.kept:
                lines.append("  %-28s %12.6g %-9s kept at the base's value (not identifiable)"
                             % (name, self.estimates[name], unit))
                continue
            value, err = self.estimates[name], self.std_errors[name]
            rel = " (%.2g %%)" % (100 * err / abs(value)) if value != 0 else ""
            bound = ", written as 0" if name in self.clipped else ""
            if name == "torque_offset":
                bound += ", not written (no config key: add it to the torque you command)"
            if name in self.entangled:
                bound += ", moves with a kept value (below)"
            lines.append("  %-28s %12.6g %-9s +- %.3g%s   base %.6g%s"
                         % (name, value, unit, err, rel, self.base_values[name], bound))
        for message in self.unidentifiable:
            lines.append("  not identifiable: " + message)
        for warning in self.warnings:
            lines.append("note: " + warning)
        if self.refined:
            lines.append("refined by output error (%d evaluations): positions fitted to %.3g rad, "
                         "%.3g m RMS (their noise %.3g rad, %.3g m)"
                         % ((self.refined["evaluations"],) + self.refined["position_rms"]
                            + self.refined["noise"]))
            knots, bias = self.refined.get("crank_bias", ([], []))
            if bias:
                lines.append("crank encoder drift (fitted beside them, a knot every %g s): %s rad"
                             % (BIAS_KNOT_SPACING, " ".join("%.3g" % b for b in bias)))
        if self.method == "energy":
            lines.append("residual RMS: %.4g J per window" % self.residual_rms)
        else:
            lines.append("residual RMS: %.4g N m (crank equation), %.4g N (slider equation)"
                         % self.residual_rms)
        if self.holdout and "skipped" in self.holdout:
            lines.append("held-out last %.2g %%: skipped (%s)" % (100 * self.holdout["fraction"],
                                                                self.holdout["skipped"]))
        elif self.holdout:
            lines.append("held-out last %.0f %% (fit on the rest): torque predicted to %.4g N m RMS "
                         "(recorded torque RMS %.4g N m)" % (100 * self.holdout["fraction"],
                                                              self.holdout["torque_rms_error"],
                                                              self.holdout["torque_rms"]))
        if self.validation:
            v = self.validation
            lines.append("re-simulated with the recorded torque over %.3g s: RMS error q1 %.4g rad, "
                         "q2 %.4g m (fitted); q1 %.4g rad, q2 %.4g m (base)"
                         % (v["duration"], v["fitted"]["q1_rms"], v["fitted"]["q2_rms"],
                            v["base"]["q1_rms"], v["base"]["q2_rms"]))
        return "\n".join(lines)


def _fit(y, b, weights):
    """theta of weighted least squares (rows weighted by `weights`) and its covariance."""
    yw, bw = y * weights[:, None], b * weights
    norms = np.linalg.norm(yw, axis=0)
    a = yw / norms
    theta_s, *_ = np.linalg.lstsq(a, bw, rcond=None)
    residual = bw - a @ theta_s
    dof = max(len(bw) - y.shape[1], 1)
    sigma2 = residual @ residual / dof
    inv = np.linalg.inv(a.T @ a)
    return theta_s / norms, sigma2 * inv / np.outer(norms, norms)


METHODS = ("energy", "equations")
DEFAULT_METHOD = "energy"
# [s] the work-energy form's windows: on filtered (measured) data long windows let the energy
# changes outgrow the noise at their ends; on data as recorded short ones keep Simpson's rule exact
# (measured: doc/guide/identification.md).
ENERGY_WINDOW = 1.0
ENERGY_WINDOW_RECORDED = 0.1
# An estimate that moves by more than this fraction of its value between Simpson's and the
# trapezoid rule is kept at the base's value and named (_estimate).
QUADRATURE_TOLERANCE = 0.1


def identify(data, config=None, params=None, method=DEFAULT_METHOD, bandwidth="auto",
             holdout=0.25, topic=None, validate=True, refine="auto"):
    """Identifies `params` (default: every parameter identifiable by default, parameters()) from
    `data` (a bag, a CSV, arrays or a Motion) over the base `config` (a Config, path or dict: its
    L, g, rod shape and initial state are taken as measured, its other values as the starting
    point and the fallback). method: "energy" (the work-energy form over 1 s windows: no
    accelerations) or "equations" (Kane's equations at every sample, u' from the filter).
    bandwidth: the derivative filter's [Hz], None (the data as recorded) or "auto" (None on
    noise-free data, DEFAULT_BANDWIDTH otherwise). refine: after the least squares, fit the
    re-simulated positions to the recorded ones (output error, _refine); "auto" does on measured
    (filtered) data, where the least squares is biased by the noise in its regressor. Returns an
    Identification."""
    base = Config(config)
    names = list(params) if params is not None else \
        [p["name"] for p in _core.identifiable_parameters() if p["by_default"]]
    for name in names:
        if not isinstance(name, str):
            raise TypeError("params: names must be strings, got %r" % (name,))
    if not names:
        raise ValueError("params: name at least one parameter (kane_sim.identify.parameters())")
    _core.identification_base_value(base._core, names[0])  # an unknown name fails here, named
    if method not in METHODS:
        raise ValueError("method must be one of %s, got %r" % (", ".join(METHODS), method))
    if not (isinstance(holdout, (int, float)) and 0 <= holdout < 0.9):
        raise ValueError("holdout must be a fraction in [0, 0.9), got %r" % (holdout,))
    if refine not in ("auto", True, False):
        raise ValueError("refine must be 'auto', True or False, got %r" % (refine,))
    motion = load_motion(data, topic)
    prepared = estimate_rates(motion, bandwidth)
    prepared = prepared.select(_usable(base, prepared.states))
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

    result = Identification()
    result.names, result.method, result.bandwidth = names, method, prepared.bandwidth
    result.notes = list(motion.notes)
    result.base_values = {n: _core.identification_base_value(base._core, n) for n in names}
    y, b, groups, check = _system(base, names, prepared, method)
    theta, cov, kept, messages, cond, rms, entangled = _estimate(
        base, names, y, b, groups, prepared.states, check, _rms(prepared.torque))
    theta, cov = _rest_length(names, theta, cov)
    if refine is True or (refine == "auto" and prepared.bandwidth is not None):
        # Unphysical least squares (a flipped torque, wrong units) is refused here, by name,
        # before the re-simulations would fail on it with a message about the integrator.
        fitted_config(base, dict(zip(names, theta)), dict(zip(names, np.sqrt(np.diag(cov)))))
        if len(kept) < len(names):
            ls_theta = dict(zip(names, theta))
            theta, cov, result.refined = _refine(base, names, theta, kept, motion,
                                                 estimate_rates(motion, bandwidth))
            result.refined["least_squares"] = ls_theta
    result.warnings = base.warnings + _config_warnings(base, motion)
    result.samples, result.rows = len(prepared), len(b)
    result.condition_number, result.residual_rms = cond, rms
    result.kept, result.unidentifiable, result.entangled = kept, messages, entangled
    for i, n in enumerate(names):
        result.estimates[n] = float(theta[i])
        result.std_errors[n] = float(math.sqrt(max(cov[i, i], 0.0)))
    result.config, result.clipped = fitted_config(base, result.estimates, result.std_errors)
    if holdout > 0:
        result.holdout = _holdout(base, names, prepared, method, holdout)
    if validate:
        result.validation = validation(motion, base, result.config,
                                       result.estimates.get("torque_offset", 0.0), bandwidth)
    return result


def _separation(base, q1, q2):
    """x_C - x_B [m] at each (q1, q2): the model's geometry (mechanismGeometry)."""
    points = _core.mechanism_points(base["mechanism.rod_half_length"], np.ascontiguousarray(q1),
                                    np.ascontiguousarray(q2))
    return points["C"][:, 0] - points["B"][:, 0]


def _usable(base, states):
    """Samples away from the sliders' contact (an unmeasured force acts there)."""
    keep = np.ones(len(states), dtype=bool)
    if base["contact.enabled"]:
        keep &= _separation(base, states[:, 0], states[:, 1]) > base["contact.gap"] + 2e-3
    return keep


def _system(base, names, prepared, method):
    """The least-squares system y theta = b, how many interleaved equations it holds (2: Kane's
    two equations per sample, N m and N; 1: one energy balance per window, J) and the check
    (y, b): the same energy rows with the trapezoid rule for their integrals (None for Kane's
    equations: they integrate nothing; see _estimate)."""
    if method == "equations":
        y, y0 = _core.identification_rows(base._core, names, prepared.states, prepared.u_dot,
                                          prepared.torque)
        y, b, groups, check = y.reshape(-1, len(names)), -y0.reshape(-1), 2, None
    else:
        (y, b), check = _energy_system(base, names, prepared)
        groups = 1
    if not np.all(np.isfinite(y)) or not np.all(np.isfinite(b)):
        raise ValueError("the regressor is not finite for this data: check its units and values")
    return y, b, groups, check


def _quadrature_weights(rule, intervals, step):
    if rule == "trapezoid":
        w = np.ones(intervals + 1)
        w[0] = w[-1] = 0.5
        return w * step
    w = np.full(intervals + 1, 2.0)  # Simpson's rule
    w[1::2] = 4.0
    w[0] = w[-1] = 1.0
    return w * step / 3.0


def _energy_system(base, names, prepared):
    """Kane's equations dotted with u and integrated over windows [a, b] of ENERGY_WINDOW:
    sum_j theta_j (E_j(b) - E_j(a) - int P_j dt) = int P0 dt - (E0(b) - E0(a)) + W_motor. The
    motor's work takes the torque as held from each sample to the next (the node's and
    simulate's commands are): W = sum tau_k (q1_k+1 - q1_k); the dampers' power by Simpson's rule.
    Windows overlap by half and end where samples are missing (contact). Returns (y, b) by
    Simpson's rule and (y, b) by the trapezoid rule, from one pass (the estimates' check)."""
    energy, power, e0, p0 = _core.identification_energy(
        base._core, names, prepared.states, np.zeros(len(prepared)))
    t, q1, torque = prepared.t, prepared.states[:, 0], prepared.torque
    step = np.median(np.diff(t))
    window = ENERGY_WINDOW_RECORDED if prepared.bandwidth is None else ENERGY_WINDOW
    m = max(1, int(round(window / step / 2)))  # 2m intervals a window (Simpson)
    if prepared.bandwidth is None:
        # As recorded (a simulation's own samples): the torque held from each sample to the next,
        # as the node and simulate hold commands, so the work is exact.
        motor = np.concatenate([[0.0], np.cumsum(torque[:-1] * np.diff(q1))])
    else:
        motor = None  # filtered: the torque is smooth; its power by Simpson's rule with the rest
    motor_power = torque * prepared.states[:, 2]
    weights = [_quadrature_weights(rule, 2 * m, step) for rule in ("simpson", "trapezoid")]
    rows, rhs = ([], []), ([], [])
    contiguous = np.diff(t) < 1.5 * step
    start = 0
    while start + 2 * m < len(t):
        end = start + 2 * m
        if not np.all(contiguous[start:end]):
            start += int(np.argmin(contiguous[start:end])) + 1
            continue
        span = slice(start, end + 1)
        for k, w in enumerate(weights):
            rows[k].append(energy[end] - energy[start] - w @ power[span])
            work = motor[end] - motor[start] if motor is not None else w @ motor_power[span]
            rhs[k].append(w @ p0[span] - (e0[end] - e0[start]) + work)
        start += m  # windows overlap by half (the error estimate widens for their correlation)
    if len(rows[0]) < len(names) + 3:
        raise ValueError("data: %d energy windows of %.3g s for %d parameters: record longer"
                         % (len(rows[0]), 2 * m * step, len(names)))
    return tuple((np.array(rows[k]), np.array(rhs[k])) for k in range(2))


def _estimate(base, names, y, b, groups, states, check=None, torque_rms=1.0):
    """theta (base values where kept), covariance, kept names, messages, condition, residual RMS
    (per equation group), the estimates a kept value moves (_entangled). check: (y, b) of the
    same rows integrated by another rule, or None."""
    base_theta = np.array([_base_theta(base, n) for n in names])
    free = list(range(len(names)))
    kept, messages = [], []
    reasons = _motion_reasons(base, states)
    _keep_rank_deficient(names, y, free, kept, messages, reasons)
    theta = base_theta.copy()
    cov = np.zeros((len(names), len(names)))
    nan = tuple(float("nan") for _ in range(groups))
    last_estimate = {}  # of each parameter kept by the quadrature check, when it was kept
    while free:
        fixed = [j for j in range(len(names)) if j not in free]
        b_free = b - y[:, fixed] @ base_theta[fixed]
        a = y[:, free]
        theta_free, cov_free, weights = _solve(a, b_free, groups)
        if check is None:
            break
        # An estimate that changes with the integration rule is not a measurement: the motion's
        # effect of that parameter is within the data's quadrature error (a stiff servo holding
        # the crank: its torque steps every sample, u1 has a kink at each, and the crank's
        # columns are smaller than the error of integrating them). On excited data the two rules
        # agree to 4e-5 of each value; keep the worst at the base's value and fit again.
        y_check, b_check = check
        other = np.linalg.lstsq(y_check[:, free], b_check - y_check[:, fixed] @ base_theta[fixed],
                                rcond=None)[0]
        scale = [max(abs(theta_free[i]), abs(base_theta[j]),
                     0.01 * torque_rms if names[j] == "torque_offset" else 0.0)
                 for i, j in enumerate(free)]
        ratio = np.abs(other - theta_free) / np.maximum(scale, 1e-300)
        worst = int(np.argmax(ratio))
        if ratio[worst] <= QUADRATURE_TOLERANCE:
            break
        j = free[worst]
        last_estimate[j] = theta_free[worst]
        messages.append("%s: its effect on this motion is within the data's integration error "
                        "(Simpson's rule gives %.3g, the trapezoid rule %.3g)%s: kept at the "
                        "base's value" % (names[j], theta_free[worst], other[worst], reasons))
        kept.append(names[j])
        free.remove(j)
        _keep_rank_deficient(names, y, free, kept, messages, reasons)
    if not free:
        return theta, cov, kept, messages, float("inf"), nan, []
    wres = (b_free - a @ theta_free) * weights
    # Filtered data's errors are correlated over the filter's window: widen the errors by the
    # residual's integrated autocorrelation (per equation, the larger).
    inflation = max(_effective_samples_factor(wres[r::groups]) for r in range(groups))
    cov_free *= inflation ** 2
    theta[free] = theta_free
    for a_i, i in enumerate(free):
        cov[i, free] = cov_free[a_i]
    residual = b_free - a @ theta_free
    rms = tuple(float(np.sqrt(np.mean(residual[r::groups] ** 2))) for r in range(groups))
    aw = a * weights[:, None]
    s = np.linalg.svd(aw / np.linalg.norm(aw, axis=0), compute_uv=False)
    entangled = _entangled(names, y, free, theta, base_theta, last_estimate, messages)
    return theta, cov, kept, messages, float(s[0] / s[-1]), rms, entangled


def _entangled(names, y, free, theta, base_theta, last_estimate, messages):
    """The free estimates that a kept parameter's error would move by more than 1 %: each kept
    column regressed on the free ones gives d theta_free / d theta_kept (the least squares puts
    the kept parameter's unexplained effect there). Its error is taken as its own size (the base's
    value, or its estimate when the quadrature check kept it). Names each in `messages`."""
    entangled = []
    a = y[:, free]
    for j in (j for j in range(len(names)) if j not in free):
        size = max(abs(base_theta[j]), abs(last_estimate.get(j, 0.0)))
        if size == 0.0:
            continue
        slope = np.linalg.lstsq(a, y[:, j], rcond=None)[0]
        moved = [(free[i], -slope[i] * size) for i in range(len(free))
                 if abs(slope[i] * size) > 0.01 * max(abs(theta[free[i]]),
                                                     abs(base_theta[free[i]]), 1e-300)]
        if not moved:
            continue
        entangled += [names[i] for i, _ in moved if names[i] not in entangled]
        messages.append("%s (kept at %.4g): were it %.4g higher, %s" % (
            names[j], base_theta[j], size,
            ", ".join("%s would read %.4g (%+.0f %%)" % (names[i], theta[i] - shift,
                                                        100 * -shift / abs(theta[i]) if theta[i] else 0)
                      for i, shift in moved)))
    return [n for n in names if n in entangled]


def _keep_rank_deficient(names, y, free, kept, messages, reasons):
    """Moves from `free` to `kept` what the regressor's rank cannot tell apart, naming it."""
    # Rank: on unit-norm columns, a singular value below 1e-7 of the largest is a combination
    # the motion cannot tell apart (noise-free data reaches 1e-12; measured data's smallest
    # informative ones stay above 1e-4). Keep one of the combination at its base value, and look
    # again.
    while free:
        a = y[:, free]
        norms = np.linalg.norm(a, axis=0)
        zero = [free[i] for i in range(len(free)) if norms[i] <= 1e-12 * max(norms.max(), 1e-300)]
        if zero:
            for j in zero:
                kept.append(names[j])
                free.remove(j)
                messages.append("%s: the motion never excites it%s" % (names[j], reasons))
            continue
        _, s, vt = np.linalg.svd(a / norms, full_matrices=False)
        if s[-1] > 1e-7 * s[0]:
            break
        v = vt[-1]
        involved = [free[i] for i in np.argsort(-np.abs(v)) if abs(v[i]) > 0.05]
        # Keep the last in the parameter order of those that carry the combination (|v| within
        # half the largest): the same one whatever the noise (c_A, and c_O is estimated).
        j = max(free[i] for i in range(len(free)) if abs(v[i]) >= 0.5 * np.max(np.abs(v)))
        carrier = next((i for i in involved if i != j), None)
        carries = "" if carrier is None else "; %s carries the combination" % names[carrier]
        messages.append("%s are not separately identifiable%s: kept %s at the base's value%s"
                        % (" and ".join(names[i] for i in involved), reasons, names[j], carries))
        kept.append(names[j])
        free.remove(j)


def _solve(a, b, groups):
    """Weighted least squares of a theta = b: theta, covariance, row weights."""
    weights = np.ones(len(b))
    theta, cov = _fit(a, b, weights)
    if groups > 1:
        # Equations of different units (N m, N): weight each by its residual's spread from the
        # unweighted fit, then fit again (feasible generalised least squares).
        residual = b - a @ theta
        for r in range(groups):
            spread = np.sqrt(np.mean(residual[r::groups] ** 2))
            floor = 1e-12 * (1 + np.sqrt(np.mean(b[r::groups] ** 2)))
            weights[r::groups] = 1.0 / max(spread, floor)
        theta, cov = _fit(a, b, weights)
    return theta, cov, weights


def _rms(x):
    return float(np.sqrt(np.mean(np.square(x))))


def _base_theta(base, name):
    """The base's value of a regressor column's parameter: the rest length's column is the
    preload k s0."""
    value = _core.identification_base_value(base._core, name)
    if name == "spring_rest_length":
        value *= base["mechanism.spring_stiffness"]
    return value


def _rest_length(names, theta, cov):
    """theta and cov with the preload k s0 turned into s0 = (k s0) / k (the delta method)."""
    if "spring_rest_length" not in names:
        return theta, cov
    p, k = names.index("spring_rest_length"), names.index("mechanism.spring_stiffness")
    gradient = np.zeros(len(names))
    gradient[p], gradient[k] = 1.0 / theta[k], -theta[p] / theta[k] ** 2
    jacobian = np.eye(len(names))
    jacobian[p] = gradient
    theta = theta.copy()
    theta[p] = theta[p] / theta[k]
    return theta, jacobian @ cov @ jacobian.T


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


def _motion_reasons(base, states):
    parts = []
    span = np.ptp(states[:, 0])
    if span < 0.05:
        parts.append("the crank hardly moved (q1 spanned %.3g rad)" % span)
    separation = _separation(base, states[:, 0], states[:, 1])
    if np.ptp(separation) < 1e-3:
        parts.append("slider 4 never moved relative to slider 3 (x_C - x_B spanned %.3g m)"
                     % np.ptp(separation))
    return " (" + "; ".join(parts) + ")" if parts else ""


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


def parameters():
    """Every parameter identify() can estimate: dicts of name, unit, symbol, by_default."""
    return _core.identifiable_parameters()


def fitted_config(base, estimates, std_errors=None):
    """The base Config with the estimates written in, and the names of those written at their
    bound: an estimate below a parameter's bound (a damper's 0) by less than 3 standard errors is
    noise around it and is written as the bound; further below, ValueError (the model does not
    describe the data). The rest length goes in as initial_state.q2 (the config's spring is
    unstretched at the initial state); the torque offset is not a config value."""
    values, clipped = {}, []
    for name, value in estimates.items():
        if name == "torque_offset":
            continue
        if name == "spring_rest_length":
            q1 = np.array([base["initial_state.q1"]])
            values["initial_state.q2"] = float(value - _separation(base, q1, np.zeros(1))[0])
            continue
        bound = 0.0
        dissipative = _dissipative(name)
        if value < bound or (value <= bound and not dissipative):
            err = (std_errors or {}).get(name, 0.0)
            if dissipative and value > bound - 3 * err:
                values[name] = bound
                clipped.append(name)
                continue
            raise ValueError("%s estimated %.6g (+- %.3g): not physical, the model does not "
                             "describe this data (check the torque's sign and units, the base's "
                             "L and g)" % (name, value, err))
        values[name] = float(value)
    if "mechanism.rod_mass" in values and "mechanism.rod_inertia" not in estimates:
        values["mechanism.rod_inertia"] = float(
            values["mechanism.rod_mass"] * base["mechanism.rod_inertia"]
            / base["mechanism.rod_mass"])
    return base.with_values(values), clipped


def _torque_on_grid(motion, times, step):
    """The recorded torque at the physics steps starting at `times`: held from each sample to the
    next when the data is sampled at the physics rate (the simulator's own samples); otherwise
    the torque between samples by a cubic spline (linear interpolation's error, (w h)^2 / 8 of a
    4 Hz torque sampled at 100 Hz, biased the dampers by several per cent), at each step's start:
    a sample is the torque in force from its instant, as a driver holds a command for its step
    (at the step's middle the replay ran half a step early and the spring damper came out 5 %
    low)."""
    if motion.rate * step > 0.999:
        index = np.searchsorted(motion.t, times + 1e-9 * step, side="right") - 1
        return motion.torque[np.clip(index, 0, len(motion) - 1)]
    from scipy.interpolate import CubicSpline
    return CubicSpline(motion.t, motion.torque)(np.clip(times, motion.t[0], motion.t[-1]))


def _replay(config, motion, x0, start, torque_offset=0.0):
    """`config` driven by the recorded torque (plus `torque_offset`) from state x0 at time
    `start` to the end of the recording: (t, q (M, 2)), rows at the data's rate when it divides
    the physics rate, else every physics step."""
    limit = float(np.max(np.abs(motion.torque)) + abs(torque_offset) + 1.0)
    sim = Simulator(Config(config).with_values(
        {"sensors.enabled": False, "command.mode": "effort", "command.torque_limit": limit}))
    sim.set_state([float(v) for v in x0])
    step = sim.step_size
    n = int(math.floor((motion.t[-1] - start) / step + 1e-9))
    steps_per_sample = round(1.0 / (motion.rate * step))
    output_rate = None
    if steps_per_sample >= 1 and abs(steps_per_sample * motion.rate * step - 1) < 1e-3:
        output_rate = 1.0 / (steps_per_sample * step)
        n -= n % steps_per_sample  # a whole number of output periods
    torque = _torque_on_grid(motion, start + step * np.arange(n), step) + torque_offset
    run = sim.run(n * step, torque=torque, output_rate=output_rate)
    return run.t + start, run.q


def simulate_motion(config, motion, torque_offset=0.0, bandwidth="auto"):
    """Re-simulates `motion`'s recorded torque (plus `torque_offset`) with `config`, from the
    recorded state where the derivative filter's output starts. Returns (t, q (M, 2))."""
    prepared = estimate_rates(motion, bandwidth)
    return _replay(config, motion, prepared.states[0], prepared.t[0], torque_offset)


# [s] knot spacing of the crank encoder's drift in the output-error fit (_refine)
BIAS_KNOT_SPACING = 10.0


def _refine(base, names, theta, kept, motion, prepared, max_evaluations=50):
    """Output error: the parameters (and the start state) that make the model, driven by the
    recorded torque, pass closest to the recorded positions, each coordinate weighted by its
    noise (the filter's residual). Position noise enters only the residual here, not the
    regressor, so it does not bias the estimate as it biases the least squares. The crank
    encoder's slow drift is fitted beside them (a linear spline added to the model's q1). Starts
    from the least-squares theta; parameters kept at the base stay there. Returns (theta, cov,
    report)."""
    from scipy.optimize import least_squares
    free = [i for i, n in enumerate(names) if n not in kept]
    keep = prepared.keep
    sigma = np.sqrt(np.mean((motion.q[keep] - prepared.states[:, :2]) ** 2, axis=0))
    sigma = np.maximum(sigma, 1e-9)
    start = prepared.t[0]
    measured = slice(keep.start, None)
    t_data, q_data = motion.t[measured], motion.q[measured]
    # The crank encoder's slow drift (a bias walk, an encoder's zero): a linear spline in time
    # added to the model's q1, knots every BIAS_KNOT_SPACING seconds. Without it the fit bends
    # the dampers to follow the drift (their error grew with the recording's length).
    knots = np.linspace(t_data[0], t_data[-1],
                        max(2, int(np.ceil((t_data[-1] - t_data[0]) / BIAS_KNOT_SPACING)) + 1))
    n_state = 4
    x0 = np.concatenate([theta[free], prepared.states[0], np.zeros(len(knots))])
    floors = [0.01 if _dissipative(names[i]) or names[i] == "torque_offset" else 1e-3
              for i in free] + [0.1, 0.01, 0.5, 0.1] + [0.01] * len(knots)
    scale = np.maximum(np.abs(x0), floors)
    lower = np.array([0.0 if _dissipative(names[i])
                      else (-np.inf if names[i] == "torque_offset" else 1e-6 * scale[k])
                      for k, i in enumerate(free)] + [-np.inf] * (n_state + len(knots))) / scale
    z0 = np.maximum(x0 / scale, lower + 1e-12)

    def estimates(z):
        out = dict(zip(names, theta))
        out.update({names[i]: float(v) for i, v in zip(free, z[:len(free)] * scale[:len(free)])})
        return out

    def residual(z, tolerant=True):
        est = estimates(z)
        try:
            config, _ = fitted_config(base, est)
            x = z[len(free):] * scale[len(free):]
            t, q = _replay(config, motion, x[:n_state], start, est.get("torque_offset", 0.0))
            q = q.copy()
            q[:, 0] += np.interp(t, knots, x[n_state:])
        except (ValueError, RuntimeError):  # a refused config or step: far from the data
            if not tolerant:
                raise
            return np.full(2 * len(t_data), 1e3)
        return np.concatenate([(np.interp(t_data, t, q[:, k]) - q_data[:, k]) / sigma[k]
                               for k in (0, 1)])

    residual(z0, tolerant=False)  # the start must simulate: a failure here is named, not hidden
    solution = least_squares(residual, z0, bounds=(lower, np.inf), diff_step=1e-6,
                             max_nfev=max_evaluations, ftol=1e-10, xtol=1e-10, gtol=1e-10)
    z = solution.x
    out = theta.copy()
    out[free] = z[:len(free)] * scale[:len(free)]
    r = solution.fun
    dof = max(len(r) - len(z), 1)
    jtj = solution.jac.T @ solution.jac
    cov_z = (r @ r / dof) * np.linalg.pinv(jtj)
    # Correlated residuals (a sensor's bias walk, unmodelled dynamics) widen the errors.
    half = len(r) // 2
    inflation = max(_effective_samples_factor(r[:half]), _effective_samples_factor(r[half:]))
    cov_z *= inflation ** 2
    cov = np.zeros((len(names), len(names)))
    scaled = cov_z[:len(free), :len(free)] * np.outer(scale[:len(free)], scale[:len(free)])
    for a_i, i in enumerate(free):
        cov[i, free] = scaled[a_i]
    rms = tuple(float(np.sqrt(np.mean((r[k * half:(k + 1) * half] * sigma[k]) ** 2)))
                for k in (0, 1))
    bias = z[len(free) + n_state:] * scale[len(free) + n_state:]
    return out, cov, {"evaluations": int(solution.nfev), "position_rms": rms,
                      "noise": tuple(float(x) for x in sigma),
                      "crank_bias": (knots.tolist(), bias.tolist())}


def validation(motion, base, fitted, torque_offset=0.0, bandwidth="auto"):
    """RMS error of q1 and q2 when the recorded torque is re-simulated with the fitted config
    (and the fitted torque offset) and with the base config, over the whole recording."""
    out = {"duration": float(motion.t[-1] - motion.t[0]),
           "recorded": {"t": motion.t, "q": motion.q},
           "q1_span": float(np.ptp(motion.q[:, 0])), "q2_span": float(np.ptp(motion.q[:, 1]))}
    for label, config, offset in (("fitted", fitted, torque_offset), ("base", base, 0.0)):
        try:
            t, q = simulate_motion(config, motion, offset, bandwidth)
        except (RuntimeError, ValueError) as e:
            out[label] = {"q1_rms": float("nan"), "q2_rms": float("nan"), "error": str(e)}
            continue
        recorded = np.column_stack([np.interp(t, motion.t, motion.q[:, k]) for k in (0, 1)])
        err = q - recorded
        out[label] = {"q1_rms": float(np.sqrt(np.mean(err[:, 0] ** 2))),
                      "q2_rms": float(np.sqrt(np.mean(err[:, 1] ** 2))), "t": t, "q": q}
    return out


# [s] --excite designs on at most this much of the profile (the bias sine's period is 20 s from
# 60 s on: six of them), then checks the whole once: 3600 s cost as much as 120 s plus one run.
EXCITATION_DESIGN_HORIZON = 120.0


def excitation(config=None, duration=60.0, seed=0, rate=1000.0, candidates=4):
    """A torque profile (t, torque) that identifies every default parameter well: a slow bias
    sine (3 periods over the run, at least 0.05 Hz) that swings the crank's mean angle, so that
    slider 3 moves (v_B = -4 L u1 sin q1), plus a multisine (0.2-4 Hz, random phases). Of
    `candidates` phase draws and the bias amplitudes 0, 2, 4, 8, 16 % of command.torque_limit,
    the best by the regressor's condition number on the base config, each with the largest
    multisine amplitude (a bisection) that keeps the base mechanism's sliders apart (x_C - x_B
    above contact.gap + 2 cm) over the first EXCITATION_DESIGN_HORIZON seconds; the whole profile
    is then checked (its amplitude halved until it passes); |torque| within command.torque_limit.
    Refused when the torque the limit allows cannot swing the crank. Returns (t, torque, the
    condition number)."""
    base = Config(config)
    if not (isinstance(duration, (int, float)) and math.isfinite(duration) and 2 <= duration <= 3600):
        raise ValueError("excite: duration must be in [2, 3600] s, got %r" % (duration,))
    limit = min(base["command.torque_limit"], 40.0)
    if not limit > 0:
        raise ValueError("excite: command.torque_limit is %g N m: the profile stays within it; "
                         "set it to what the rig's drive delivers" % base["command.torque_limit"])
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, duration, 1.0 / rate)
    design = t < EXCITATION_DESIGN_HORIZON
    freqs = np.linspace(0.2, 4.0, 12)
    slow = np.sin(2 * np.pi * max(3.0 / duration, 0.05) * t)
    names = [p["name"] for p in _core.identifiable_parameters() if p["by_default"]]
    best = None
    for _ in range(candidates):
        phases = rng.uniform(0, 2 * np.pi, len(freqs))
        shape = np.zeros(len(t))  # a frequency at a time: 12 x 3.6e6 samples would be 350 MB
        for frequency, phase in zip(freqs, phases):
            shape += np.sin(2 * np.pi * frequency * t + phase)
        shape /= np.max(np.abs(shape))
        for bias in (0.0, 0.02, 0.04, 0.08, 0.16):
            found = _largest_feasible(base, names, t[design], bias * limit * slow[design],
                                      shape[design], limit * (1 - bias))
            if found and (best is None or found[0] < best[0]):
                best = (found[0], found[2], bias * limit * slow, shape)
    if best is None:
        raise ValueError("excite: no multisine keeps the sliders apart on this config")
    score, amplitude, bias, shape = best
    torque = bias + amplitude * shape
    for _ in range(8):
        run = _excitation_run(base, t, torque)
        if run is not None:
            break
        amplitude *= 0.5
        torque = bias + amplitude * shape
    else:
        undamped = all(base[k] == 0 for k in Config.names("dissipative"))
        raise ValueError("excite: no multisine keeps the sliders apart over %g s on this config%s"
                         % (duration, " (it has no damping: under any long excitation its energy "
                            "drifts; give the dampers' rough values, or excite in shorter runs)"
                            if undamped else ""))
    span = np.ptp(run.q[:, 0])
    if span < 0.05:
        raise ValueError("excite: within command.torque_limit %g N m the profile swings the crank "
                         "by %.3g rad only (the parameters need a visible motion): raise the "
                         "limit to what the rig's drive delivers" % (base["command.torque_limit"],
                                                                    span))
    states, y = _run_rows(base, names, run)
    share = _torque_share(base, names, run, y)
    if share < 0.01:
        raise ValueError("excite: within command.torque_limit %g N m the torque is %.2g %% of the "
                         "torques the mechanism's own motion puts on the crank: the parameters' "
                         "scale would rest on it; raise the limit to what the rig's drive "
                         "delivers" % (base["command.torque_limit"], 100 * share))
    if not np.all(design):  # the whole profile's score, from the rows already made
        score = _condition(base, names, states, y)
    return t, torque, score


def _run_rows(base, names, run):
    """The states of a run and its regressor rows (Kane's equations, two per sample)."""
    states = np.ascontiguousarray(np.column_stack([run.q, run.u]))
    y, _ = _core.identification_rows(base._core, names, states, np.ascontiguousarray(run.u_dot),
                                     run.torque)
    return states, y.reshape(-1, len(names))


def _condition(base, names, states, y):
    # The condition number of what the mechanism can tell at all (the crank's and the coupler's
    # dampers act alike on it, whatever the motion): the fit's own rank rule drops the rest.
    return _estimate(base, names, y, np.zeros(len(y)), 2, states)[4]


def _torque_share(base, names, run, y):
    """RMS of the driving torque over the largest RMS of one parameter's term of the crank's
    equation (rows y, the base's values): near 0, the motion is the mechanism's own and fixes
    the parameters only up to a common scale."""
    theta = np.array([_base_theta(base, n) for n in names])
    terms = y[0::2] * theta
    return _rms(run.torque) / max(np.max(np.sqrt(np.mean(terms ** 2, axis=0))), 1e-300)


def _largest_feasible(base, names, t, bias, shape, most):
    """(score, torque, amplitude) of bias + amplitude shape, the amplitude the largest up to
    `most` that keeps the sliders apart (to ~10 %: a bisection in log amplitude), or None."""
    def attempt(amplitude):
        torque = bias + amplitude * shape
        score = _excitation_score(base, names, t, torque)
        return None if score is None else (score, torque, amplitude)
    found = attempt(most)
    if found:
        return found
    low, high = math.log(1e-3 * most), math.log(most)
    for _ in range(7):
        middle = 0.5 * (low + high)
        trial = attempt(math.exp(middle))
        if trial:
            found, low = trial, middle
        else:
            high = middle
    return found


def _excitation_run(base, t, torque):
    """The base mechanism driven by `torque` (100 Hz output), or None when the sliders come
    within 2 cm of contact or a step is refused."""
    cfg = base.with_values({"sensors.enabled": False, "command.mode": "effort",
                            "command.torque_limit": float(np.max(np.abs(torque))) + 1.0})
    sim = Simulator(cfg)
    step = sim.step_size
    index = np.clip(np.searchsorted(t, step * np.arange(len(t)), side="right") - 1, 0, len(t) - 1)
    try:
        run = sim.run(len(t) * step, torque=torque[index], output_rate=100.0)
    except (RuntimeError, ValueError):
        return None
    if np.min(_separation(base, run.q[:, 0], run.q[:, 1])) < base["contact.gap"] + 0.02:
        return None
    return run


def _excitation_score(base, names, t, torque):
    """The scaled regressor's condition number of the base mechanism driven by `torque`, or None
    when _excitation_run refuses it."""
    run = _excitation_run(base, t, torque)
    return None if run is None else _condition(base, names, *_run_rows(base, names, run))
