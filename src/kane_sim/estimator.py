"""The rig's state from its readings: an extended Kalman filter on the Kane equations of a
config's mechanism (kane_sim._core.Estimator; the `observer` node's and `observer --bag`'s
filter), its model-mismatch alarm and the virtual sensors of its estimate.

    est = kane_sim.Estimator("rig.yaml")          # the mechanism, its sensors: and estimator:
    event, reason = est.update(t, q1, q2, effort)  # one reading (u1=, u2= when it has speeds)
    est.estimate["u1"], est.estimate["spring_force"], est.alarm["level"]
    rows, summary = est.run(t, q1, q2, effort)     # a whole recording, as observer --bag
    rows, summary = est.run_bag("rig.bag")
"""

import numpy as np

from kane_sim import _core
from kane_sim.core import load_config


class Estimator:
    """config: a Config, a file name, a dict or None (config/mechanism.yaml). Its sensors:
    section is the measurement model, estimator: the trust in the model."""

    def __init__(self, config=None):
        self.config = load_config(config)
        self._core = _core.Estimator(self.config._core)

    def update(self, t, q1, q2, effort, u1=None, u2=None):
        """One reading (t its stamp [s]; effort the crank's delivered torque [N m]). Returns
        (event, reason): "started", "updated", "restarted" (a gap or a diverged prediction;
        reason says which) or "refused" (reason names the field and value; nothing changed)."""
        return self._core.update(float(t), float(q1), float(q2), float(effort),
                                 None if u1 is None else float(u1),
                                 None if u2 is None else float(u2))

    def restart(self):
        """Forget the estimate (the rig was moved): the next reading starts the filter."""
        self._core.restart()

    @property
    def estimate(self):
        """The last reading's row (observer --bag's columns: the state at its stamp, sigma_*,
        bias_*, nis, alarm, the virtual sensors) with "covariance" (4 x 4 of q1, q2, u1, u2);
        None before the first."""
        return self._core.estimate

    @property
    def alarm(self):
        """The last window's verdict: level ("OK", "WARN", "ERROR"), text, since, coordinate,
        nis, dof, p_value, windows, and suspects: the parameters whose change explains the
        window, most likely first, each a dict of name, unit, change, sigma and
        over (the seconds of windows that told it)."""
        return self._core.alarm

    def run(self, t, q1, q2, effort, u1=None, u2=None, velocity_rows=None):
        """A recording through a fresh filter of this config, as `observer --bag` runs it:
        ({column: array}, summary). Rows only for the readings it used; summary counts the
        refused ones and the restarts, and holds the alarm's last verdict. velocity_rows (bools,
        one per reading): which readings carry u1, u2, when not all do."""
        arrays = [np.asarray(a, dtype=float) for a in (t, q1, q2, effort)]
        speeds = [None if u is None else np.asarray(u, dtype=float) for u in (u1, u2)]
        rows = None if velocity_rows is None else np.asarray(velocity_rows, dtype=bool)
        return _core.estimate_run(self.config._core, *arrays, *speeds, rows)

    def run_bag(self, path, topic="/joint_states"):
        """The JointState topic of a bag (crank_joint, slider4_joint) through run(). Messages
        without those joints or the crank's effort are left out (another publisher's on the same
        topic), as `observer --bag` does: summary["skipped"] counts them, summary["skip_notes"]
        names the first; summary["without_velocities"] counts the readings read without speeds."""
        from kane_sim import _bag
        if not topic.startswith("/"):
            topic = "/" + topic
        try:
            c = _bag.read_joint_states(path, topic, "crank_joint", "slider4_joint",
                                       skip_unusable=True)
        except ValueError as e:
            raise ValueError("Estimator.run_bag: %s" % e) from None
        rows, summary = self.run(c["t"], c["position_a"], c["position_b"], c["effort_a"],
                                 c.get("velocity_a"), c.get("velocity_b"),
                                 c.get("velocity_rows"))
        summary["skipped"] = c["skipped"]
        summary["skip_notes"] = c["skip_notes"]
        carried = c.get("velocity_rows")
        summary["without_velocities"] = int(
            len(c["t"]) if "velocity_a" not in c else
            (0 if carried is None else len(carried) - int(np.count_nonzero(carried))))
        return rows, summary
