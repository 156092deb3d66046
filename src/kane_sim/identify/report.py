"""What identify() found (Identification) and its text report."""
from kane_sim import _core
from kane_sim.identify.least_squares import DEFAULT_METHOD
from kane_sim.identify.refinement import SEGMENT_SECONDS

# A fitted value whose reported error is above this fraction of it is named as told poorly.
POORLY_TOLD = 0.05


class Identification:
    """What identify() found: `estimates` and `std_errors` by parameter name, the scaled
    regressor's `condition_number`, `unidentifiable` (messages naming what the motion could not
    tell apart; those parameters keep the base's values), `entangled` (estimates that move by more
    than 1 % when a kept value is off by its own size: named in `unidentifiable`), `config` (the
    base with the estimates written in; the torque offset is not a config value), `residual_rms`
    (N m, N), `samples`, `holdout` (cross-validation on the last part of the data: the fit of the
    rest predicting its torque; or why it was skipped), `notes`, `warnings` (the base config's
    unknown keys; what of it the recording contradicts), `refusal` (why it must not be written:
    the output-error fit did not converge to the noise, or the fit follows the recording no
    better than the base; None when it may be)."""

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
        self.refusal = None  # why the fit must not be written (identify._refusal), or None
        self.warnings = []

    @property
    def poorly_told(self):
        """The fitted parameters (not kept, not zero within their error, not the torque offset)
        whose reported error is above POORLY_TOLD of their value: written, but the motion told
        them only that well (a slider that hardly moves, a damper on a joint that barely
        slides). Measured on the family of rigs: a mass 4.8 % off with its error at 10 %."""
        return [n for n in self.names
                if n not in self.kept and n != "torque_offset"
                and abs(self.estimates[n]) > self.std_errors[n]
                and self.std_errors[n] > POORLY_TOLD * abs(self.estimates[n])]

    def report(self):
        """The fit as text: how it was fitted, each parameter with its error and base, what it
        could not tell, the output error's refinement, the checks and the decision."""
        how = ("the work-energy form, %d windows" % self.rows if self.method == "energy"
               else "Kane's equations, %d rows" % self.rows)
        rates = ("data as recorded" if self.bandwidth is None
                 else "Savitzky-Golay %.3g Hz" % self.bandwidth)
        lines = ["identified by %s from %d samples (%s; %s); condition number %.3g"
                 % (how, self.samples, rates, ", ".join(self.notes) or "uniform stamps",
                    self.condition_number)]
        lines += self._parameter_lines()
        lines += self._told_lines()
        if self.refined:
            lines += self._refinement_lines()
        lines += self._check_lines()
        return "\n".join(lines)

    def _parameter_lines(self):
        """One line per parameter: its value, error and base, or why it was kept."""
        lines = []
        info = {p["name"]: p for p in _core.identifiable_parameters()}
        for name in self.names:
            unit = info[name]["unit"]
            if name in self.kept:
                lines.append("  %-28s %12.6g %-9s kept at the base's value (not identifiable)"
                             % (name, self.estimates[name], unit))
                continue
            value, err = self.estimates[name], self.std_errors[name]
            # A relative error only where it means something: a value within its error of zero
            # (no friction on the joint, fitted to 1e-20 at its bound) says "zero within error".
            rel = (" (%.2g %%)" % (100 * err / abs(value)) if abs(value) > err
                   else " (zero within its error)")
            bound = ", written as 0" if name in self.clipped else ""
            if name == "torque_offset":
                bound += ", not written (no config key: add it to the torque you command)"
            if name in self.entangled:
                bound += ", moves with a kept value (below)"
            lines.append("  %-28s %12.6g %-9s +- %.3g%s   base %.6g%s"
                         % (name, value, unit, err, rel, self.base_values[name], bound))
        return lines

    def _told_lines(self):
        """What the data could not tell, what it told poorly, and the notes."""
        lines = []
        for message in self.unidentifiable:
            lines.append("  not identifiable: " + message)
        poor = self.poorly_told
        if poor:
            lines.append("  told poorly by this motion (error above %g %% of the value: use it "
                         "with its error, or record more motion of its joint): %s"
                         % (100 * POORLY_TOLD, ", ".join(
                             "%s (%.2g %%)" % (n, 100 * self.std_errors[n] / abs(self.estimates[n]))
                             for n in poor)))
        for warning in self.warnings:
            lines.append("note: " + warning)
        return lines

    def _refinement_lines(self):
        """The output error: its segments, how close it came, and what it fitted beside."""
        lines = []
        r = self.refined
        part = ""
        if r.get("segments_of", r["segments"]) > r["segments"] or r.get("stride", 1) > 1:
            part = " (%d of the recording's %d spread over it%s: a long recording's fit " \
                   "looks at a bounded part, its errors are that part's)" % (
                       r["segments"], r["segments_of"],
                       ", one sample in %d" % r["stride"] if r["stride"] > 1 else "")
        lines.append("refined by output error (%d segments of %g s%s, %d evaluations): "
                     "positions fitted to %.3g rad, %.3g m RMS (their noise %.3g rad, "
                     "%.3g m)%s"
                     % ((r["segments"],
                         r.get("segment_seconds", SEGMENT_SECONDS), part,
                         r["evaluations"]) + r["position_rms"]
                        + r["noise"]
                        + ("" if r["converged"] else ": NOT converged",)))
        floor = r.get("torque_sampling", (0.0, 0.0))
        if any(f > 0.5 * n for f, n in zip(floor, r["noise"])):
            lines.append("the recorded torque steps between its samples (its steps' instants "
                         "are known to a sample): that alone leaves the positions about "
                         "%.3g rad, %.3g m from any model's (the fit is judged against it "
                         "and the noise together; record the node's ~input_log with it, e.g. "
                         "rosbag record -a, whose commands give the torque between samples, "
                         "or the effort at the physics rate, to remove it)" % floor)
        if r.get("servo_effort"):
            mismatch, effort = r["servo_effort"]
            lines.append("the servo replayed with its law gives the recorded effort to a "
                         "median %.3g N m (%.2g %% of the effort's median %.3g N m)"
                         % (mismatch, 100 * mismatch / max(effort, 1e-300), effort))
        if r.get("refit"):
            lines.append("fitted by the output error alone (their effect on the energy "
                         "windows is within the windows' integration error): %s"
                         % ", ".join(r["refit"]))
        if "lag" in r:
            lines.append("the positions lag the torque by %.3g +- %.2g ms (fitted beside them: "
                         "a sensor's latency, an effort read late)"
                         % (1e3 * r["lag"], 1e3 * r["lag_error"]))
        knots, bias = r.get("crank_bias", ([], []))
        if bias:
            values = (" ".join("%.3g" % b for b in bias) if len(bias) <= 8 else
                      "%d knots from %.3g to %.3g" % (len(bias), min(bias), max(bias)))
            lines.append("crank encoder drift (fitted beside them, a knot every %.3g s): %s "
                         "rad" % (knots[1] - knots[0], values))
        return lines

    def _check_lines(self):
        """The residual, the held-out part, the re-simulation and the refusal."""
        lines = []
        if self.method == "energy":
            lines.append("residual RMS: %.4g J per window" % self.residual_rms)
        else:
            lines.append("residual RMS: %.4g N m (crank equation), %.4g N (slider equation)"
                         % self.residual_rms)
        if self.holdout and "skipped" in self.holdout:
            lines.append("held-out last %.2g %%: skipped (%s)" % (100 * self.holdout["fraction"],
                                                                self.holdout["skipped"]))
        elif self.holdout:
            h = self.holdout
            worse = h["torque_rms_error"] > h["torque_rms"]
            lines.append("held-out last %.0f %% (fit on the rest): torque predicted to %.4g N m "
                         "RMS (recorded torque RMS %.4g N m)%s"
                         % (100 * h["fraction"], h["torque_rms_error"], h["torque_rms"],
                            ": worse than predicting none, the fit does not carry over to it"
                            if worse else ""))
        if self.validation:
            v = self.validation
            lines.append("re-simulated with the recorded torque over %.3g s: RMS error q1 %.4g "
                         "rad, q2 %.4g m (fitted); q1 %.4g rad, q2 %.4g m (base)"
                         % (v["duration"], v["fitted"]["q1_rms"], v["fitted"]["q2_rms"],
                            v["base"]["q1_rms"], v["base"]["q2_rms"]))
        if self.refusal:
            lines.append("REFUSED: " + self.refusal)
        return lines
