"""A family of rigs identification was not tuned on: random parameters, motion regimes and
sensors, recorded as a bag cut to /joint_states would show them (the sensors' readings stamped
at arrival, the crank's effort as the drive delivered it then), from the middle of a run.

    rig = rigs.draw(seed)                 # or draw(seed, regime="prbs", duration=60)
    data = rigs.record(rig)               # {"t", "q1", "q2", "u1", "u2", "applied_torque"}
    rigs.score(rig, fit)                  # errors, coverage, what was told and what was not

Used by test_family.py (a fixed handful, one per regime) and bench/identify_family.py (>= 30
rigs, the distribution).
"""
import math

import numpy as np

import kane_sim
import kane_sim.identify  # noqa: F401  (excitation)

REGIMES = ("oscillation", "full_turns", "prbs", "multisine_bias", "servo", "excite")
MASSES = ("mechanism.rod_mass", "mechanism.slider3_mass", "mechanism.slider4_mass")
STIFFNESS = ("mechanism.spring_stiffness",)
DAMPERS = ("damping.crank_joint", "damping.slider3_joint", "damping.slider4_joint",
           "damping.spring")
FRICTION = ("friction.crank_joint", "friction.slider3_joint", "friction.slider4_joint")
CLASSES = {"mass": MASSES, "stiffness": STIFFNESS, "damper": DAMPERS, "friction": FRICTION}


class Rig:
    """One drawn rig: truth (config values), regime, sensors (config values), duration [s] of the
    recording, start [s] of the recording within the run, seed."""

    def __init__(self, seed, regime, truth, sensors, duration, start):
        self.seed, self.regime, self.truth, self.sensors = seed, regime, truth, sensors
        self.duration, self.start = duration, start

    def config(self):
        return kane_sim.Config().with_values(dict(self.truth, **self.sensors))

    def __repr__(self):
        return "Rig(seed=%d, %s, %.0f s at %.0f Hz)" % (self.seed, self.regime, self.duration,
                                                         self.sensors["sensors.rate"])


def _log_uniform(rng, low, high):
    return float(math.exp(rng.uniform(math.log(low), math.log(high))))


def draw(seed, regime=None, duration=None):
    """A rig from `seed`: masses and k x[0.5, 2] of the defaults, each damper and friction on with
    probability 1/2 and 1/3, the rod's inertia off its default in half of them, sensors of 100 Hz
    to 1 kHz with noise, encoder counts, latency and (sometimes) a bias walk."""
    rng = np.random.default_rng(seed)
    base = kane_sim.Config()
    regime = regime or REGIMES[rng.integers(len(REGIMES))]
    truth = {name: base[name] * _log_uniform(rng, 0.5, 2.0) for name in MASSES + STIFFNESS}
    if rng.random() < 0.5:  # the rod's inertia, not fitted by default: off by up to 50 %
        truth["mechanism.rod_inertia"] = base["mechanism.rod_inertia"] * rng.uniform(0.8, 1.5)
    for name in DAMPERS:
        on = rng.random() < 0.5
        truth[name] = (_log_uniform(rng, 0.01, 0.2) if name == "damping.crank_joint" else
                       _log_uniform(rng, 0.1, 2.0)) if on else 0.0
    for name in FRICTION:
        on = rng.random() < 1 / 3
        truth[name] = (_log_uniform(rng, 0.01, 0.1) if name == "friction.crank_joint" else
                       _log_uniform(rng, 0.05, 0.5)) if on else 0.0
    truth["friction.velocity_scale"] = 0.01
    truth["command.torque_limit"] = 60.0
    rate = float(rng.choice([100.0, 200.0, 500.0, 1000.0]))
    sensors = {"sensors.enabled": True, "sensors.seed": int(seed) + 1, "sensors.rate": rate,
               "sensors.latency": float(rng.uniform(0.0, 0.004)),
               "sensors.crank_position_noise": _log_uniform(rng, 1e-4, 2e-3),
               "sensors.slider4_position_noise": _log_uniform(rng, 1e-5, 3e-4),
               "sensors.crank_velocity_noise": _log_uniform(rng, 1e-3, 2e-2),
               "sensors.slider4_velocity_noise": _log_uniform(rng, 1e-4, 3e-3),
               "sensors.crank_encoder_counts": float(rng.choice([0, 4096, 16384])),
               "sensors.crank_bias_walk": 1e-4 if rng.random() < 0.3 else 0.0}
    if regime == "servo":
        truth.update({"command.mode": "position", "command.position_kp": 60.0,
                      "command.position_kd": 4.0})
    duration = float(duration or rng.choice([20.0, 60.0, 120.0]))
    start = float(rng.uniform(0.0, 5.0))  # recorded mid-run
    return Rig(seed, regime, truth, sensors, duration, start)


def torque_profile(rig, rng=None):
    """The rig's drive (one value per physics step) over start + duration: its regime's torque,
    or a servo's setpoint."""
    rng = rng or np.random.default_rng(rig.seed + 1000)
    cfg = rig.config()
    dt = 1.0 / cfg["simulation.physics_rate"]
    n = int(round((rig.start + rig.duration) / dt))
    t = dt * np.arange(n)
    limit = 0.5 * cfg["command.torque_limit"]
    if rig.regime == "excite":
        try:  # designed on the rig's own config, as a user with a good base would
            te, torque, _ = kane_sim.identify.excitation(cfg, max(rig.duration, 2.0) + rig.start,
                                                         seed=rig.seed % 7)
            return np.interp(t, te, torque)
        except ValueError:  # no multisine keeps this rig's sliders apart: a plain one
            pass
    if rig.regime == "prbs":
        edges = np.cumsum(rng.uniform(0.2, 2.0, size=int(n * dt / 0.2) + 2))
        levels = rng.uniform(-1.0, 1.0, size=len(edges)) * rng.uniform(2.0, 6.0)
        return levels[np.searchsorted(edges, t)]
    freqs = np.array([0.3, 0.7, 1.3, 2.1, 3.4])
    phases = rng.uniform(0, 2 * np.pi, size=len(freqs))
    shape = np.sum(np.sin(2 * np.pi * np.outer(t, freqs) + phases), axis=1) / len(freqs)
    if rig.regime == "oscillation":
        return 1.5 * shape
    if rig.regime in ("multisine_bias", "excite"):
        return 4.0 * shape + 2.0 * np.sin(2 * np.pi * 0.05 * t)
    if rig.regime == "full_turns":  # a bias that spins the crank through full turns
        return np.clip(6.0 * shape + 9.0, -limit, limit)
    if rig.regime == "servo":  # the position servo's setpoint [rad]
        return 0.5 * np.sin(2 * np.pi * 0.2 * t) + 0.3 * shape
    raise ValueError("regime %r" % rig.regime)


def record(rig, drive=None, mode=None):
    """What the rig's bag cut to /joint_states holds: the sensors' readings at their arrival
    stamps (t, q1 = crank, q2 = slider 4, u1, u2), the crank's effort then (the torque in
    force), from `start` on. drive: one value per physics step (default: the regime's,
    torque_profile); mode: the command mode (default: the rig's)."""
    config = rig.config()
    if mode:
        config = config.with_values({"command.mode": mode})
    sim = kane_sim.Simulator(config)
    drive = torque_profile(rig) if drive is None else drive
    run = sim.run(len(drive) / sim.config["simulation.physics_rate"], torque=drive,
                  output_rate=sim.config["simulation.physics_rate"])
    s = run.sensors
    t = np.asarray(s["t"])
    keep = t >= rig.start
    applied = np.asarray(run.applied_torque)
    index = np.clip(np.searchsorted(run.t, t[keep] + 1e-9, side="right") - 1, 0, len(applied) - 1)
    position, velocity = np.asarray(s["position"])[keep], np.asarray(s["velocity"])[keep]
    return {"t": t[keep], "q1": position[:, 0], "q2": position[:, 3], "u1": velocity[:, 0],
            "u2": velocity[:, 3], "applied_torque": applied[index]}


def record_closed_loop(rig, duration=None, rate=100.0, gains=(30.0, 3.0), seed=0):
    """What the rig's bag holds when the example PD controller drives it in lockstep, as
    `lockstep_controller` does: every 1/rate s the controller reads the newest sensor reading
    (noisy, late), sets the torque kp (setpoint - q1) - kd u1 within 20 N m, and the rig runs on
    with it held; the setpoint jumps to a random angle in [-1.5, 2.5] rad every 0.3-1.5 s.
    Returns record()'s columns (effort: the torque in force at each reading's stamp) with the
    commands as the node's ~input_log holds them: command_t (the instant each took effect) and
    command."""
    config = rig.config().with_values({"command.mode": "effort"})
    sim = kane_sim.Simulator(config)
    rng = np.random.default_rng(seed)
    steps = int(round(config["simulation.physics_rate"] / rate))
    kp, kd = gains
    setpoint, change_at, reading = 1.0, 0.0, None
    command_t, command, chunks = [], [], []
    for _ in range(int(round((rig.start + (duration or rig.duration)) * rate))):
        if sim.time >= change_at:
            setpoint, change_at = rng.uniform(-1.5, 2.5), sim.time + rng.uniform(0.3, 1.5)
        torque = 0.0 if reading is None else \
            float(np.clip(kp * (setpoint - reading[0]) - kd * reading[1], -20.0, 20.0))
        sim.set_torque(torque)
        command_t.append(sim.time)
        command.append(torque)
        sim.step(steps)
        got = sim.take_readings()
        if len(got["t"]):
            chunks.append(got)
            reading = (got["position"][-1][0], got["velocity"][-1][0])
    t = np.concatenate([np.asarray(c["t"]) for c in chunks])
    position = np.concatenate([np.asarray(c["position"]) for c in chunks])
    velocity = np.concatenate([np.asarray(c["velocity"]) for c in chunks])
    command_t, command = np.array(command_t), np.array(command)
    effort = command[np.clip(np.searchsorted(command_t, t + 1e-9, side="right") - 1, 0, None)]
    keep = t >= rig.start
    return {"t": t[keep], "q1": position[keep, 0], "q2": position[keep, 3],
            "u1": velocity[keep, 0], "u2": velocity[keep, 3], "applied_torque": effort[keep],
            "command_t": command_t, "command": command}


# Closed-loop kinds (closed_loop): the example PD controller in lockstep (its commands logged),
# a position servo and a velocity servo (integral off) driven by setpoint steps (logged).
CLOSED_LOOP = ("pd", "position_servo", "velocity_servo")


def draw_closed_loop(seed, kind, duration=None):
    """draw(seed)'s rig under a controller of `kind` (CLOSED_LOOP), its sensors at 100, 200 or
    500 Hz in turn by seed, with 2 ms of latency jitter (readings stamped on arrival)."""
    rig = draw(seed, regime="servo" if kind == "position_servo" else "oscillation",
               duration=duration)
    rig.regime = kind
    rig.sensors.update({"sensors.rate": (100.0, 200.0, 500.0)[seed % 3],
                        "sensors.latency_jitter": 0.002})
    if kind == "velocity_servo":
        rig.truth.update({"command.mode": "velocity", "command.velocity_kp": 5.0,
                          "command.velocity_ki": 0.0})
    return rig


def record_servo_steps(rig, seed=0):
    """record() of a servo rig driven by setpoint steps every 0.3-1.5 s (position: [-1.5, 2.5]
    rad; velocity: [-4, 4] rad/s), with the setpoints as logged (setpoint_t: where each took
    effect, setpoint)."""
    config = rig.config()
    step = 1.0 / config["simulation.physics_rate"]
    n = int(round((rig.start + rig.duration) / step))
    rng = np.random.default_rng(20_000 + seed)
    edges = np.cumsum(rng.uniform(0.3, 1.5, size=int(n * step / 0.3) + 2))
    low, high = (-1.5, 2.5) if config["command.mode"] == "position" else (-4.0, 4.0)
    setpoints = rng.uniform(low, high, size=len(edges))[np.searchsorted(edges, step * np.arange(n))]
    data = record(rig, drive=setpoints)
    changed = np.flatnonzero(np.diff(setpoints, prepend=np.nan) != 0)
    data.update(setpoint_t=step * changed, setpoint=setpoints[changed])
    return data


def record_closed(rig, seed=0):
    """A closed-loop rig's recording with its logged commands or setpoints: record_closed_loop
    for "pd", record_servo_steps for the servos; seed: the setpoint sequence."""
    if rig.regime == "pd":
        return record_closed_loop(rig, seed=seed)
    return record_servo_steps(rig, seed=seed)


def score(rig, fit):
    """Per fitted parameter: truth, estimate, relative error, reported sigma, z = error / sigma,
    whether it was told (not kept at the base, not marked as moving with a kept value)."""
    rows = {}
    config = rig.config()  # the rig's own values (the rod's inertia follows its mass if not set)
    for name in fit.names:
        truth = 0.0 if name == "torque_offset" else config[name]
        est, sigma = fit.estimates[name], fit.std_errors[name]
        told = name not in fit.kept and name not in fit.entangled
        scale = abs(truth) if truth else 1.0
        rows[name] = {"truth": truth, "estimate": est, "sigma": sigma, "told": told,
                      "error": (est - truth) / scale,
                      "z": abs(est - truth) / sigma if sigma > 0 else math.inf}
    return rows


def _fresh_torque(rig, duration, seed):
    """A torque the fit never saw: another multisine within 3 N m, one value per physics step
    over `duration` s, and the step [s]."""
    rng = np.random.default_rng(10_000 + seed)
    dt = 1.0 / rig.config()["simulation.physics_rate"]
    t = dt * np.arange(int(round(duration / dt)))
    freqs = rng.uniform(0.2, 3.0, 4)
    phases = rng.uniform(0, 2 * np.pi, 4)
    return 3.0 * np.sum(np.sin(2 * np.pi * np.outer(t, freqs) + phases), axis=1) / 4, dt


def sensor_noise(rig):
    """(crank [rad], slider 4 [m]): the standard deviation of the rig's position readings, the
    crank encoder's counts (uniform within a count: count / sqrt(12)) included."""
    counts = rig.sensors["sensors.crank_encoder_counts"]
    quantum = 2 * math.pi / counts / math.sqrt(12) if counts else 0.0
    return (math.hypot(rig.sensors["sensors.crank_position_noise"], quantum),
            rig.sensors["sensors.slider4_position_noise"])


def fresh_recording_error(rig, fit, duration=10.0, seed=0, data=None):
    """How the fitted config follows a recording it never saw, as its user would check it: the
    true rig, its sensors on, driven by a fresh torque (_fresh_torque) and recorded as record()
    does; the fitted config, every parameter held, follows it as the fit follows its own data
    (identify's output error with nothing free but each segment's start state, the drift and the
    lag). Returns (q1 RMS / crank noise, q2 RMS / slider-4 noise), the noise sensor_noise's:
    1 is a model that explains the fresh recording down to its sensors. data: the fresh
    recording to follow instead (a closed-loop one: record_closed with another seed), read with
    its logged commands as identify reads them."""
    from kane_sim.identify.data import load_motion
    from kane_sim.identify.rates import estimate_rates
    from kane_sim.identify.refinement import refine_segments
    if data is None:
        torque, _ = _fresh_torque(rig, rig.start + duration, seed)
        data = record(rig, drive=torque, mode="effort")
    motion = load_motion(data, None, fit.config)
    theta = np.array([fit.estimates[n] for n in fit.names])
    _, _, report = refine_segments(fit.config, fit.names, theta, list(fit.names), motion,
                                   estimate_rates(motion))
    return tuple(rms / noise for rms, noise in zip(report["position_rms"], sensor_noise(rig)))


def fresh_torque_error(rig, fit, duration=10.0, seed=0, horizon=2.0):
    """How the fitted config predicts a motion it never saw, against the truth itself: the true
    rig and the fitted config, no sensors, driven by a fresh torque (_fresh_torque) from the
    rig's initial state for `duration` s, the fitted one restarted from the truth's state every
    `horizon` s (as the fit's segments: open loop over 10 s a 0.5 % error in k shifts a
    lightly damped oscillation's phase by far more than the noise). Returns (q1 RMS [rad], q2
    RMS [m]) of their difference, and the rig's sensor noise (sensor_noise)."""
    torque, dt = _fresh_torque(rig, duration, seed)
    truth = rig.config().with_values({"sensors.enabled": False, "command.mode": "effort"})
    fitted = fit.config.with_values({"sensors.enabled": False, "command.mode": "effort",
                                     "simulation.physics_rate":
                                         truth["simulation.physics_rate"]})
    true_sim, fit_sim = kane_sim.Simulator(truth), kane_sim.Simulator(fitted)
    per = int(round(horizon / dt))
    errors = []
    for start in range(0, len(torque), per):
        chunk = torque[start:start + per]
        fit_sim.set_state(true_sim.state)
        a = true_sim.run(len(chunk) * dt, torque=chunk, states_only=True).q
        b = fit_sim.run(len(chunk) * dt, torque=chunk, states_only=True).q
        errors.append(a - b)
    err = np.concatenate(errors)
    rms = tuple(float(np.sqrt(np.mean(err[:, k] ** 2))) for k in (0, 1))
    return rms, sensor_noise(rig)


def parameter_class(name):
    for label, names in CLASSES.items():
        if name in names:
            return label
    return "other"
