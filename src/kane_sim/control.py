"""Controllers designed from the twin (the `design` tool's library).

    import kane_sim.control
    g = kane_sim.control.lqr("config/mechanism.yaml", q1=math.pi)   # hold the crank upright
    g.K          # (1, 4): M_m = g.torque - g.K @ (x - g.state), x = (q1, q2, u1, u2)
    g.closed_loop_eigenvalues    # of A - B K, as complex numbers
    open("upright.yaml", "w").write(g.yaml)    # the law, as `design lqr --out` writes it
"""
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


def _number(name, value):
    """A real number (not a bool or text), finite."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer,
                                                                      np.floating)):
        raise ValueError("lqr: %s must be a number, got %r" % (name, value))
    value = float(value)
    if not np.isfinite(value):
        raise ValueError("lqr: %s must be finite, got %r" % (name, value))
    return value


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
    if Q is not None:
        try:
            Q = np.asarray(Q, dtype=float)
        except (TypeError, ValueError):
            raise ValueError("lqr: Q must be 4 numbers or a 4 x 4 matrix of numbers, got %r"
                             % (Q,)) from None
        if Q.shape not in ((4,), (4, 4)):
            raise ValueError("lqr: Q must be 4 numbers (the diagonal on q1, q2, u1, u2) or a "
                             "4 x 4 matrix, got shape %s" % (Q.shape,))
        Q = Q.reshape(4, 1) if Q.ndim == 1 else Q
    R = None if R is None else _number("R", R)
    return LqrDesign(core._core.design_lqr(cfg._core, q1, Q, R))
