"""Controllers designed from the twin (the `design` tool's library).

    import kane_sim.control
    g = kane_sim.control.lqr("config/mechanism.yaml", q1=math.pi)   # hold the crank upright
    g.K          # (1, 4): M_m = g.torque - g.K @ (x - g.state), x = (q1, q2, u1, u2)
    g.closed_loop_eigenvalues    # of A - B K, as complex numbers
    open("upright.yaml", "w").write(g.yaml)    # the law, as `design lqr --out` writes it
    p = kane_sim.control.plan("config/swing_up.yaml", to=math.pi, duration=3,
                              torque_limit=8, intervals=200, Q=[100, 1, 1, 1], R=1)
    p.write("plan.csv")                           # what the tracking controller follows
    run = kane_sim.control.follow("config/swing_up.yaml", "plan.csv", duration=10)
"""
import os

import numpy as np

from kane_sim import core


class LqrDesign:
    """LQR at the crank held at rest at q1: the law (K, state, torque, periodic), the weights it
    used (Q, R), the linearization (A, B), the Riccati solution P, the eigenvalues and the YAML
    file a controller reads."""

    def __init__(self, fields):
        self.K = np.asarray(fields["K"]).reshape(1, 4)
        self.state = np.asarray(fields["state"]).reshape(4)
        self.torque = float(fields["torque"])
        self.periodic = bool(fields["periodic"])
        self.Q = np.asarray(fields["Q"])
        self.R = float(fields["R"])
        self.A = np.asarray(fields["A"])
        self.B = np.asarray(fields["B"]).reshape(4, 1)
        self.P = np.asarray(fields["P"])
        rows = np.asarray(fields["open_loop"])
        self.open_loop_eigenvalues = rows[:, 0] + 1j * rows[:, 1]
        rows = np.asarray(fields["closed_loop"])
        self.closed_loop_eigenvalues = rows[:, 0] + 1j * rows[:, 1]
        self.riccati_residual = float(fields["riccati_residual"])
        # The states the torque can move (4 x r, orthonormal columns): r < 4 at q1 = 0 and pi,
        # where slider 4's oscillation is out of the crank's reach; notes says so.
        self.controllable_basis = np.asarray(fields["controllable_basis"])
        self.notes = list(fields["notes"])
        # Readings per second a sampled controller needs: 5 x the fastest closed-loop
        # |eigenvalue| (a rule of thumb, |lambda| dt <= 0.2); slower, raise R.
        self.sample_rate_needed = float(fields["sample_rate_needed"])
        self.yaml = fields["yaml"]

    def command(self, x):
        """M_m for the state x = (q1, q2, u1, u2), the crank's error within (-pi, pi] when the
        mechanism repeats every turn. A state that is not 4 finite numbers is a ValueError."""
        x = np.asarray(x, dtype=float).reshape(-1)
        if x.shape != (4,) or not np.all(np.isfinite(x)):
            raise ValueError("command: x must be 4 finite numbers (q1, q2, u1, u2), got %r"
                             % (x.tolist(),))
        error = x - self.state
        if self.periodic:
            error[0] = np.remainder(error[0] + np.pi, 2 * np.pi) - np.pi
        return self.torque - float(self.K @ error)

    def __repr__(self):
        return "LqrDesign(q1=%g, K=%s)" % (self.state[0], np.array2string(self.K[0]))


def _number(name, value, what="lqr"):
    """A real number (not a bool or text), finite."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer,
                                                                      np.floating)):
        raise ValueError("%s: %s must be a number, got %r" % (what, name, value))
    value = float(value)
    if not np.isfinite(value):
        raise ValueError("%s: %s must be finite, got %r" % (what, name, value))
    return value


def _weights(what, Q):
    """Q as the core takes it: None, the diagonal (4 x 1) or a 4 x 4 matrix."""
    if Q is None:
        return None
    try:
        Q = np.asarray(Q, dtype=float)
    except (TypeError, ValueError):
        raise ValueError("%s: Q must be 4 numbers or a 4 x 4 matrix of numbers, got %r"
                         % (what, Q)) from None
    if Q.shape not in ((4,), (4, 4)):
        raise ValueError("%s: Q must be 4 numbers (the diagonal on q1, q2, u1, u2) or a "
                         "4 x 4 matrix, got shape %s" % (what, Q.shape))
    return Q.reshape(4, 1) if Q.ndim == 1 else Q


def lqr(config, q1, Q=None, R=None):
    """LQR at the crank held at rest at q1 [rad] (math.pi: upright). config: a path, a dict, YAML
    text or a kane_sim.Config (None: config/mechanism.yaml). Q: None (Bryson's rule: 1/0.1^2,
    1/0.01^2, 1, 1/0.1^2), 4 numbers (the diagonal on q1, q2, u1, u2) or a 4 x 4 matrix; R: None
    (1/torque_limit^2) or a number > 0. A refused design (no equilibrium, bad weights, no
    stabilizing gain, a holding moment beyond the torque limit) is a ValueError saying why."""
    cfg = config if isinstance(config, core.Config) else core.Config(config)
    q1 = _number("q1", q1)
    if abs(q1) > 1e6:
        raise ValueError("lqr: q1 must be an angle within 1e6 rad, got %r" % q1)
    Q = _weights("lqr", Q)
    R = None if R is None else _number("R", R)
    return LqrDesign(core._core.design_lqr(cfg._core, q1, Q, R))


class Plan:
    """A planned move (`design plan`): rows every `step` seconds of the time t, the state
    x = (q1, q2, u1, u2), the torque M_m held over the row's step and the time-varying LQR gain
    K (M_m = torque - K (x_measured - x)); the last row holds the goal by its LQR. Also what the
    collocation found: duration, effort (the integral of M_m^2), status, iterations, the largest
    defect and the first guess it solved from; `csv`, the file a tracking controller reads."""

    def __init__(self, fields):
        self.t = np.asarray(fields["t"])
        self.x = np.asarray(fields["x"])
        self.torque = np.asarray(fields["torque"])
        self.K = np.asarray(fields["K"])
        self.step = float(fields["step"])
        self.periodic = bool(fields["periodic"])
        self.duration = float(fields["duration"])
        self.effort = float(fields["effort"])
        self.status = fields["status"]
        self.iterations = int(fields["iterations"])
        self.max_defect = float(fields["max_defect"])
        self.guess_swings = int(fields["guess_swings"])
        self.goal_K = np.asarray(fields["goal_K"]).reshape(1, 4)
        self.csv = fields["csv"]

    def write(self, path):
        """The plan CSV, as `design plan --out` writes it."""
        with open(path, "w") as out:
            out.write(self.csv)

    def __repr__(self):
        return "Plan(duration=%g s, %d rows, effort=%g)" % (self.duration, len(self.t),
                                                           self.effort)


def _optional(what, name, value):
    return None if value is None else _number(name, value, what)


def plan(config, to, start=None, objective="effort", duration=3.0, max_duration=0.0,
         intervals=100, torque_limit=None, q2_range=None, gap=None, rate=None, Q=None, R=None,
         max_iterations=3000):
    """The optimal move from `start` (None: the config's initial state; a number: the crank held
    at rest there) to the crank held at rest at `to` [rad], as `design plan` finds it: Hermite-
    Simpson collocation solved by IPOPT, minimum effort in `duration` s or minimum time
    (objective="time", `duration` the first guess, at most max_duration, 0: 10 x duration);
    |M_m| <= torque_limit (None: command.torque_limit), slider 4 within q2_range (MIN, MAX),
    the sliders `gap` apart; rows every 1/rate s (None: the physics rate) with the time-varying
    LQR gains of weights Q, R (as lqr's). A refused problem or one IPOPT does not solve is a
    ValueError saying why; Ctrl-C stops IPOPT (KeyboardInterrupt)."""
    cfg = config if isinstance(config, core.Config) else core.Config(config)
    to = _number("to", to, "plan")
    if isinstance(start, str) and start == "initial":
        start = None  # as the command line's --from initial
    start = _optional("plan", "start", start)
    for name, value in (("to", to), ("start", start)):
        if value is not None and abs(value) > 1e6:
            raise ValueError("plan: %s must be an angle within 1e6 rad, got %r" % (name, value))
    if objective not in ("effort", "time"):
        raise ValueError("plan: objective must be 'effort' or 'time', got %r" % (objective,))
    duration = _number("duration", duration, "plan")
    max_duration = _number("max_duration", max_duration, "plan")
    for name, value, lo, hi in (("intervals", intervals, 2, 20000),
                                ("max_iterations", max_iterations, 1, 10**6)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
            raise ValueError("plan: %s must be a whole number, got %r" % (name, value))
        if not lo <= value <= hi:
            raise ValueError("plan: %s must be in [%d, %d], got %d" % (name, lo, hi, value))
    if q2_range is not None:
        if len(q2_range) != 2:
            raise ValueError("plan: q2_range must be (MIN, MAX), got %r" % (q2_range,))
        q2_range = np.array([_number("q2_range", v, "plan") for v in q2_range])
    Q = _weights("plan", Q)
    fields = core._core.design_plan(
        cfg._core, to, start, objective, duration, max_duration, int(intervals),
        _optional("plan", "torque_limit", torque_limit), q2_range,
        _optional("plan", "gap", gap), _optional("plan", "rate", rate), Q,
        _optional("plan", "R", R), int(max_iterations))
    return Plan(fields)


def follow(config, plan_csv, duration, torque_limit=None):
    """The plan file `plan_csv` (a path) followed in the loop as the tracking controller runs it
    in lockstep on the node (the config's sensors, readings answered before the next step), for
    `duration` s: a dict of t (every physics step), x (q1, q2, u1, u2: the truth) and torque (the
    drive's). The node in lockstep gives the same states bit for bit. A plan for another
    mechanism or start is a ValueError naming what differs."""
    cfg = config if isinstance(config, core.Config) else core.Config(config)
    if not isinstance(plan_csv, (str, os.PathLike)):
        raise TypeError("follow: plan_csv must be a path, got %r" % (plan_csv,))
    duration = _number("duration", duration, "follow")
    fields = core._core.follow_plan(cfg._core, str(plan_csv), duration,
                                    _optional("follow", "torque_limit", torque_limit))
    return {k: np.asarray(v) for k, v in fields.items()}
