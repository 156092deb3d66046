"""Designing a torque that excites every parameter (identify --excite)."""
import math

import numpy as np

from kane_sim import _core
from kane_sim.core import Config, ConfigError, Simulator
from kane_sim.identify.least_squares import _base_theta, _estimate, _rms, _separation
from kane_sim.identify.refinement import replay_settings


# [s] --excite designs on at most this much of the profile (the bias sine's period is 20 s from
# 60 s on: six of them), then checks the whole once: 3600 s cost as much as 120 s plus one run.
EXCITATION_DESIGN_HORIZON = 120.0


# The largest multisine a servo's setpoint profile may have: position [rad], velocity [rad/s].
SERVO_SETPOINT_RANGE = {"position": 1.5, "velocity": 8.0}


# The example PD controller's private parameters (config/controller.yaml) and PdGains' defaults
# for those of its law; the others are checked as the controller checks them.
PD_CONTROLLER_GAINS = {"kp": 500.0, "kd": 30.0, "ki": 0.0, "torque_limit": 50.0}
PD_CONTROLLER_OTHER_KEYS = ("setpoint", "stamped", "setpoint_table")
# [rad] the largest setpoint the controller takes (a million turns, as the simulator's servo)
MAX_SETPOINT = 2e6 * math.pi
# The controller's gains as the position servo's config keys.
PD_AS_SERVO = {"kp": "command.position_kp", "kd": "command.position_kd",
               "ki": "command.position_ki", "torque_limit": "command.torque_limit"}


def _number(value):
    """A number as rosparam reads it (YAML 1.1 reads 1e3, with no dot, as text), else value."""
    if isinstance(value, str):
        try:
            return float(value)
        except ValueError:
            pass
    return value


def _check_controller_key(key, value):
    """ValueError naming `key` when `value` is not what pd_controller takes for it."""
    if key not in PD_CONTROLLER_GAINS and key not in PD_CONTROLLER_OTHER_KEYS:
        raise ValueError("the controller's %r is not one of its parameters (%s)"
                         % (key, ", ".join(list(PD_CONTROLLER_GAINS)
                                           + list(PD_CONTROLLER_OTHER_KEYS))))
    if key == "stamped":
        if not isinstance(value, bool):
            raise ValueError("the controller's stamped must be true or false, got %r" % (value,))
        return
    if key == "setpoint_table":
        if not isinstance(value, str):
            raise ValueError("the controller's setpoint_table must be a file path, got %r"
                             % (value,))
        return
    number = _number(value)
    if isinstance(number, bool) or not isinstance(number, (int, float)) or \
            not math.isfinite(number) or (key != "setpoint" and number < 0):
        raise ValueError("the controller's %s must be a finite number%s, got %r"
                         % (key, "" if key == "setpoint" else " >= 0",
                            number if isinstance(number, float) else value))
    if key == "setpoint" and abs(number) > MAX_SETPOINT:
        raise ValueError("the controller's setpoint %r rad is beyond a million turns" % number)
    if key in ("kp", "torque_limit") and number == 0:
        raise ValueError("the controller's %s is 0: its setpoint cannot move the crank" % key)


def pd_controller_base(config, gains):
    """The base config as the example PD controller (pd_controller, its `gains`: a dict of
    config/controller.yaml's keys) drives it, for excitation(): a position servo with the
    controller's kp, kd and ki, which is the controller's law (M_m = kp (setpoint - q1) - kd u1
    + ki * the error's integral, clamped), the smaller of the two torque limits, no feedforward.
    The setpoint table it designs plays through pd_controller's ~setpoint_table. One difference
    the design does not see: the servo acts at every physics step, the controller at every
    reading (100 Hz by default, a sensor's latency later), so the rig's loop is a little softer.
    ValueError names a key that is not the controller's, a value the controller refuses, and
    ~law (a state feedback: no setpoint to play)."""
    base = Config(config)
    if not isinstance(gains, dict):
        raise ValueError("the controller's file must be a mapping of its parameters (%s), got "
                         "%r" % (", ".join(PD_CONTROLLER_GAINS), gains))
    if "law" in gains:
        raise ValueError("the controller's law: %r is a state feedback, which has no setpoint "
                         "to excite through: remove it to design for the PD" % (gains["law"],))
    values = dict(PD_CONTROLLER_GAINS)
    for key, value in gains.items():
        _check_controller_key(key, value)
        if key in PD_CONTROLLER_GAINS:
            values[key] = float(_number(value))
    values["torque_limit"] = min(values["torque_limit"], base["command.torque_limit"])
    try:
        return base.with_values(dict({PD_AS_SERVO[k]: v for k, v in values.items()},
                                     **{"command.mode": "position",
                                        "command.feedforward": "none"}))
    except ConfigError as e:  # beyond what the servo takes (kp 1e308): named as the file's key
        key = next((k for k, name in PD_AS_SERVO.items() if name in str(e)), None)
        raise ValueError("the controller's %s as the position servo's: %s" % (key, e)) \
            if key else e from None


def excitation(config=None, duration=60.0, seed=0, rate=1000.0, candidates=4):
    """A torque profile (t, torque) that identifies every default parameter well: a slow bias
    sine (3 periods over the run, at least 0.05 Hz) that swings the crank's mean angle, so that
    slider 3 moves (v_B = -4 L u1 sin q1), plus a multisine (0.2-4 Hz, random phases). Of
    `candidates` phase draws and the bias amplitudes 0, 2, 4, 8, 16 % of command.torque_limit,
    the best by the regressor's condition number on the base config, each with the largest
    multisine amplitude (a bisection) that keeps the base mechanism's sliders apart (x_C - x_B
    above contact.gap + 2 cm) over the first EXCITATION_DESIGN_HORIZON seconds; the whole profile
    is then checked (its amplitude halved until it passes); |torque| within command.torque_limit.
    With a base in a servo mode (command.mode position or velocity) the profile is the servo's
    setpoint [rad or rad/s], designed the same way with the servo in the loop (its law, gains
    and torque limit: the loop keeps the rig where the design saw it), the multisine up to
    SERVO_SETPOINT_RANGE and the bias sine 0, 25, 50 or 75 % of it. Refused when the torque the limit
    allows cannot swing the crank. Returns (t, torque or setpoint, the condition number)."""
    base = Config(config)
    if not (isinstance(duration, (int, float)) and math.isfinite(duration) and 2 <= duration <= 3600):
        raise ValueError("excite: duration must be in [2, 3600] s, got %r" % (duration,))
    if not base["command.torque_limit"] > 0:
        raise ValueError("excite: command.torque_limit is %g N m: the profile stays within it; "
                         "set it to what the rig's drive delivers" % base["command.torque_limit"])
    mode = base["command.mode"]
    gain = "command.%s_kp" % mode
    if mode in SERVO_SETPOINT_RANGE and not base[gain] > 0:
        raise ValueError("excite: %s = %g: the %s servo's setpoint cannot move the crank; give "
                         "the rig's gain" % (gain, base[gain], mode))
    limit = SERVO_SETPOINT_RANGE[mode] if mode in SERVO_SETPOINT_RANGE else \
        min(base["command.torque_limit"], 40.0)
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
        # A servo's mean angle (or speed) may swing by most of its range: it holds the rig.
        for bias in (0.0, 0.25, 0.5, 0.75) if mode in SERVO_SETPOINT_RANGE else \
                (0.0, 0.02, 0.04, 0.08, 0.16):
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
                                     run.applied_torque)
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
    return _rms(run.applied_torque) / max(np.max(np.sqrt(np.mean(terms ** 2, axis=0))), 1e-300)


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
    """The base mechanism driven by `torque` (a servo's setpoint in its modes: the servo in the
    loop; 100 Hz output), or None when the sliders come within 2 cm of contact or a step is
    refused."""
    cfg = base.with_values({"sensors.enabled": False} if base["command.mode"] != "effort" else
                           replay_settings(float(np.max(np.abs(torque))) + 1.0))
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
