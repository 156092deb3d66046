"""The output-error stage: the parameters that make the re-simulated positions follow the
recorded ones, from the least-squares values (the regressor's noise biases those)."""
import copy
import math
import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from kane_sim import _core
from kane_sim.core import Config, Simulator
from kane_sim.identify.least_squares import _dissipative, fitted_config
from kane_sim.identify.rates import _effective_samples_factor, estimate_rates, position_noise


def _torque_on_grid(motion, times, step):
    """The recorded torque at the physics steps starting at `times`: held from each sample to the
    next when the data is sampled at the physics rate (the simulator's own samples); otherwise
    the torque between samples by a cubic spline (linear interpolation's error, (w h)^2 / 8 of a
    4 Hz torque sampled at 100 Hz, biased the dampers by several per cent), at each step's start:
    a sample is the torque in force from its instant, as a driver holds a command for its step
    (at the step's middle the replay ran half a step early and the spring damper came out 5 %
    low). With logged commands that reproduce the samples (motion.held), the torque they held,
    exactly, from the first command on."""
    if motion.held is not None:
        held = motion.held.at(times)
        before = np.isnan(held)
        if not np.any(before):
            return held
        return np.where(before, _torque_from_samples(motion, times, step), held)
    return _torque_from_samples(motion, times, step)


def _drive_on_grid(motion, times, step):
    """What drives the replays at the physics steps starting at `times`: in a servo mode with
    its setpoints logged (motion.servo), the setpoints (the servo's law makes the torque from
    the model's state, as the driver made it); else the torque (_torque_on_grid)."""
    if motion.servo is not None:
        return motion.servo.at(times)
    return _torque_on_grid(motion, times, step)


def replay_settings_of(motion, limit):
    """replay_settings, or for a servo replayed with its law (motion.servo) only the sensors
    off: the config's own mode, gains and torque limit drive the model."""
    if motion.servo is not None:
        return {"sensors.enabled": False}
    return replay_settings(limit)


def _torque_from_samples(motion, times, step):
    """_torque_on_grid from the effort samples alone."""
    if motion.rate * step > 0.999:
        index = np.searchsorted(motion.t, times + 1e-9 * step, side="right") - 1
        return motion.torque[np.clip(index, 0, len(motion) - 1)]
    from scipy.interpolate import CubicSpline
    # The spline through the samples around `times` only (a segment of an hour's recording
    # need not fit all of it): 40 samples either side, where a cubic spline's reach has
    # fallen below 1e-22 of a sample's (0.27 a sample), so the values are the whole spline's.
    lo = max(int(np.searchsorted(motion.t, times[0])) - 40, 0)
    hi = min(int(np.searchsorted(motion.t, times[-1])) + 40, len(motion))
    t, torque = motion.t[lo:hi], motion.torque[lo:hi]
    return CubicSpline(t, torque)(np.clip(times, motion.t[0], motion.t[-1]))


# With another attempt to follow (refine_segments' shorter segments), the output-error fit gives
# up early when, still further from the recording than CONVERGED_NOISE_FACTOR times the noise,
# its cost fell so slowly over the last STALL_ITERATIONS iterations that at that pace the
# evaluations left would not bring it there: a local minimum it will not leave (seed 113 of the
# family, 2 s segments: 40 iterations at 80 times slider 4's noise, the positions' RMS moving in
# its third digit from the fourth on; on 1 s segments it then fits them to the noise). On the
# first attempt only: a fit can crawl for a few iterations and then find its way (seed 127 on
# 1 s segments, stopped by this rule after 7 evaluations at 100 times the noise, converges to
# it after 23).
STALL_ITERATIONS = 6


class _Stalled(Exception):
    """Raised from the Jacobian when the fit has stalled: the point it stopped at, as a solution
    (x, fun, jac)."""

    def __init__(self, x, fun, jac):
        super().__init__("stalled")
        self.x, self.fun, self.jac = x, fun, jac


# A second difference of the recorded torque beyond this many times their median is a step.
STEP_FACTOR = 10.0


def _torque_sampling_floor(motion, segments, step, model_q, z):
    """(q1 [rad], q2 [m]): how far the positions may lie from any model's because the recorded
    torque is known only at its samples. Between samples the replay takes a cubic spline, exact
    to (w h)^4 for a smooth torque; a torque that steps between two samples (a PRBS, a stepped
    command) stepped at an instant the recording does not hold, anywhere within the sample
    period h, and each step's impulse is uncertain by |jump| h / sqrt(12). The jumps are the
    torque's second differences (a smooth torque's are (w h)^2 of it); one replay with the
    samples moved by that much at random gives the positions' spread. 0 when the data is
    sampled at the physics rate (each sample held for its step, as the simulator held it).
    Measured: a 200 Hz PRBS rig replayed with its true parameters stays 58 um from slider 4's
    readings against 17.6 um of noise; this floor names it. 0 when logged commands give the
    torque between samples (motion.held) from before the first segment on."""
    if motion.rate * step > 0.999 or motion.servo is not None or \
            (motion.held is not None and motion.held.changes[0] <= segments.start[0]):
        return (0.0, 0.0)
    jumps = np.zeros(len(motion))
    jumps[2:] = np.abs(np.diff(motion.torque, 2))
    # Steps only: a second difference beyond STEP_FACTOR times their median. A smooth torque's
    # are all alike ((w h)^2 of it) and a noisy reading's are the noise, neither a step: moved
    # by them, the replay of a fast motion far from the optimum spread by itself, and the report
    # blamed steps a multisine never had.
    jumps[jumps <= STEP_FACTOR * np.median(jumps)] = 0.0
    if not np.any(jumps):
        return (0.0, 0.0)
    moved = copy.copy(motion)
    rng = np.random.default_rng(0)
    # A sample moved by d carries an impulse of about d h, and a step of J shows in two second
    # differences (+J at i, -J at i + 1): each moved by J / sqrt(24), the two carry J h / sqrt(12).
    moved.torque = motion.torque + rng.standard_normal(len(motion)) * jumps / math.sqrt(24.0)
    torques = [_torque_on_grid(moved, start + step * np.arange(n), step)
               for start, n in zip(segments.start, segments.steps)]
    try:
        spread = model_q(z, torques) - model_q(z)
    except (ValueError, RuntimeError):  # not to be had: the fit is judged by the noise alone
        return (0.0, 0.0)
    return tuple(float(np.sqrt(np.mean(spread[:, k] ** 2))) for k in (0, 1))


def replay_settings(limit):
    """What a replay of recorded torque needs of a config: no sensors (the positions are the
    model's own), effort mode (the torque drives as recorded), a limit above the torque."""
    return {"sensors.enabled": False, "command.mode": "effort", "command.torque_limit": limit}


# A replay's rows at most (an hour at 1 kHz compared at 100 Hz): the comparison and the plot
# need no more, and an hour's rows at the data's rate cost 150 MB a replay.
MAX_REPLAY_ROWS = 400000


def _replay(config, motion, x0, start, torque_offset=0.0):
    """`config` driven by the recorded torque (plus `torque_offset`) from state x0 at time
    `start` to the end of the recording: (t, q (M, 2)), rows at the data's rate when it divides
    the physics rate, else every physics step; every k-th of them beyond MAX_REPLAY_ROWS."""
    limit = float(np.max(np.abs(motion.torque)) + abs(torque_offset) + 1.0)
    sim = Simulator(Config(config).with_values(replay_settings(limit)))
    sim.set_state([float(v) for v in x0])
    step = sim.step_size
    n = int(math.floor((motion.t[-1] - start) / step + 1e-9))
    steps_per_row = round(1.0 / (motion.rate * step))
    if not (steps_per_row >= 1 and abs(steps_per_row * motion.rate * step - 1) < 1e-3):
        steps_per_row = 1  # the data's rate does not divide the physics rate: every step
    steps_per_row *= max(1, int(math.ceil(n / steps_per_row / MAX_REPLAY_ROWS)))
    n -= n % steps_per_row  # a whole number of output periods
    torque = _torque_on_grid(motion, start + step * np.arange(n), step) + torque_offset
    run = sim.run(n * step, torque=torque, output_rate=1.0 / (steps_per_row * step),
                  states_only=True)
    return run.t + start, run.q


def simulate_motion(config, motion, torque_offset=0.0, bandwidth="auto", start=None):
    """Re-simulates `motion`'s recorded torque (plus `torque_offset`) with `config`, from the
    recorded state where the derivative filter's output starts (start: that (t, state) when
    known, else the filter runs here). Returns (t, q (M, 2))."""
    if start is None:
        prepared = estimate_rates(motion, bandwidth)
        start = (prepared.t[0], prepared.states[0])
    return _replay(config, motion, start[1], start[0], torque_offset)


# [s] knot spacing of the crank encoder's drift in the output-error fit (_refine)
BIAS_KNOT_SPACING = 10.0
# [s] length of the output-error fit's segments (multiple shooting): long enough for the
# mechanism's slowest mode (~1 Hz) to show the parameters, short enough that a trajectory of a
# slightly wrong model does not wander off the recording (one 30 s replay did: 0.3 rad RMS).
SEGMENT_SECONDS = 2.0
# [s] the largest lag of the positions behind the torque (either way) the fit may find: a
# sensor's latency, an effort read a few messages late.
MAX_LAG = 0.025
# [s] how long a segment's replay runs before its first row and after its last: the model is
# compared at t - lag, so each row's t - lag must fall inside the replay. No more than the lag
# needs: the start states are the filter's guesses, and a longer replay from them kept a 100 Hz
# recording of full turns from converging (0.1 s: 21 times the noise; 0.02 s: masses 0.02 %).
REPLAY_MARGIN = MAX_LAG
# The fit has converged when the positions are fitted to within this many times the sensors'
# noise (rates.position_noise).
CONVERGED_NOISE_FACTOR = 3.0


# A long recording's output-error fit looks at a bounded part of it, so that an hour at 1 kHz
# costs what a minute does (the least squares before it sees every sample): at most
# MAX_SEGMENTS segments, spread evenly over the recording, and at most MAX_ROWS positions per
# coordinate (every k-th sample). The Jacobian then stays below 2 * MAX_ROWS x (4 * MAX_SEGMENTS
# + the parameters + the drift knots) doubles (~30 MB), its SVD (the solver's, each iteration)
# below half a second.
MAX_SEGMENTS = 30


def _max_segments(seconds):
    """MAX_SEGMENTS, twice as many for segments under 1 s (they replay as much motion as 30 of
    1 s at most): a saturating PD loop's recording fitted on 0.25 s segments was told by 30 of
    them to 2.1 of its errors, rod inertia 9 % off; by 60, 2.8 % (120 did not converge in the
    evaluations allowed)."""
    return MAX_SEGMENTS * (2 if seconds < 1.0 - 1e-9 else 1)
MAX_ROWS = 12000
MAX_KNOTS = 20  # drift knots (and a last one) of a long recording: a knot every span / 20


def _on_the_drives_ticks(motion, time, step):
    """`time`, or with logged commands or setpoints (motion.held, motion.servo: their changes on
    the simulation's physics ticks) the tick nearest it: a replay steps on the rig's own grid.
    Readings whose jittered stamps were taken as a regular sampling lie a few microseconds off
    that grid, and a replay started from one applied some of a servo's setpoint steps a whole
    step early or late: seed 123 of the closed-loop family (a velocity servo, 100 Hz, 2 ms of
    jitter) left its true parameters 4.2 times slider 4's noise from the readings on 2 s
    segments; without the jitter, at the noise."""
    drive = motion.held if motion.held is not None else motion.servo
    if drive is None:
        return time
    tick = drive.changes[0]  # one tick, in the recording's time
    return tick + step * round((time - tick) / step)


class _Segments:
    """The recording cut into SEGMENT_SECONDS pieces, each replayed from its own start state (a
    free parameter: multiple shooting); of a long one MAX_SEGMENTS spread evenly, of their
    samples every `stride`-th so that at most MAX_ROWS are compared. Holds per segment the data
    rows, the physics steps' torques and the start state's first guess (the filter's)."""

    def __init__(self, motion, prepared, step, seconds=SEGMENT_SECONDS):
        t0, t1 = prepared.t[0], prepared.t[-1]
        self.count = max(1, int(math.floor((t1 - t0) / seconds)))
        edges = np.linspace(t0, t1, self.count + 1)
        most = _max_segments(seconds)
        chosen = np.unique(np.round(np.linspace(0, self.count - 1, min(self.count, most)))
                           .astype(int))
        samples = len(motion) * len(chosen) / self.count
        self.stride = max(1, int(math.ceil(samples / MAX_ROWS)))
        self.rows, self.steps, self.torque, self.x0, self.start = [], [], [], [], []
        for k in chosen:
            # The replay starts REPLAY_MARGIN before the segment's first row and runs as long
            # past its last: a row whose t - lag fell outside the replay was compared with its
            # first or last value (a 4 ms latency at 0.9 m/s left slider 4 at 3.6 mm on each
            # segment's first row; the fit bent the lag and the start states to spread it:
            # 0.11 mm RMS against 17 um of noise with the true parameters).
            first = max(int(np.searchsorted(prepared.t, edges[k] - REPLAY_MARGIN,
                                            side="right")) - 1, 0)
            start = _on_the_drives_ticks(motion, prepared.t[first], step)
            end = edges[k + 1]
            rows = np.flatnonzero((motion.t >= max(edges[k], start + REPLAY_MARGIN)) &
                                  (motion.t < end if k < self.count - 1 else motion.t <= end)
                                  )[::self.stride]
            last = min(motion.t[rows[-1]] + REPLAY_MARGIN, motion.t[-1])
            n = int(math.floor((last - start) / step + 1e-9)) + 1
            self.rows.append(rows)
            self.steps.append(n)
            self.torque.append(_drive_on_grid(motion, start + step * np.arange(n), step))
            self.x0.append(prepared.states[first])
            self.start.append(start)

    def __len__(self):
        return len(self.rows)


class _Problem:
    """One output-error fit by multiple shooting: its unknowns z (scaled: the free parameters,
    each segment's start state, the crank encoder's drift knots, the lag), their bounds, the rows
    compared, and the model's positions and residual at a z. Built from the least squares'
    values theta; parameters in `kept` stay at theta."""

    def __init__(self, base, names, theta, kept, motion, prepared, segment_seconds):
        if motion.servo is not None:
            # The servo's law makes the torque: an offset in the effort reading moves nothing.
            kept = list(kept) + ["torque_offset"]
        self.base, self.names, self.theta, self.motion = base, names, theta, motion
        self.free = [i for i, n in enumerate(names) if n not in kept]
        self.sigma = np.maximum(position_noise(motion), 1e-9)
        limit = float(np.max(np.abs(motion.torque)) + 1.0)
        self.settings = replay_settings_of(motion, limit)
        self.step = 1.0 / Config(base).with_values(self.settings)["simulation.physics_rate"]
        self.segments = _Segments(motion, prepared, self.step, segment_seconds)
        self.rows = np.concatenate(self.segments.rows)
        self.q_data = motion.q[self.rows]
        t_data = motion.t[self.rows]
        n_seg = len(self.segments)
        # A knot every BIAS_KNOT_SPACING, no more than one per segment (a long recording's
        # segments lie apart: a knot between two of them would be told by none) nor MAX_KNOTS,
        # and a last one.
        self.knots = np.linspace(
            t_data[0], t_data[-1],
            max(2, min(int(np.ceil((t_data[-1] - t_data[0]) / BIAS_KNOT_SPACING)), n_seg,
                       MAX_KNOTS) + 1))
        self.n_free, self.n_seg = len(self.free), n_seg
        self.first_knot = self.n_free + 4 * n_seg
        # The last unknown: how late the positions are against the torque [s] (a sensor's
        # latency: readings stamped when they arrive, the effort when it is read; 0-4 ms biased
        # dampers by tens of per cent). The model's positions are compared at t - lag.
        self.n_lag = self.first_knot + len(self.knots)
        self._bounds(np.concatenate([theta[self.free], np.concatenate(self.segments.x0),
                                     np.zeros(len(self.knots)), [0.0]]))
        self.bias_basis = np.column_stack([np.interp(t_data, self.knots, np.eye(len(self.knots))[j])
                                           for j in range(len(self.knots))])
        owner = np.concatenate([np.full(len(seg), k) for k, seg in enumerate(self.segments.rows)])
        self.owner = np.concatenate([owner, owner])  # q1 rows, then q2 rows

    def _bounds(self, x0):
        """scale (z = x / scale), lower, upper and the start z0: masses and stiffnesses above 0,
        dissipative coefficients at or above it, the lag within MAX_LAG."""
        free_names = [self.names[i] for i in self.free]
        floors = [0.01 if _dissipative(n) or n == "torque_offset" else 1e-3 for n in free_names] \
            + [0.1, 0.01, 0.5, 0.1] * self.n_seg + [0.01] * len(self.knots) + [1e-3]
        self.scale = np.maximum(np.abs(x0), floors)
        self.lower = np.array([0.0 if _dissipative(n)
                               else (-np.inf if n == "torque_offset" else 1e-6 * self.scale[k])
                               for k, n in enumerate(free_names)]
                              + [-np.inf] * (4 * self.n_seg + len(self.knots)) + [-MAX_LAG]) \
            / self.scale
        self.upper = np.full(len(x0), np.inf)
        self.upper[self.n_lag] = MAX_LAG / self.scale[self.n_lag]
        self.z0 = np.maximum(x0 / self.scale, self.lower + 1e-12)

    def estimates(self, z):
        """{name: value} of every parameter at z (the kept ones at theta)."""
        out = dict(zip(self.names, self.theta))
        out.update({self.names[i]: float(v) for i, v in
                    zip(self.free, z[:self.n_free] * self.scale[:self.n_free])})
        return out

    def _segment_runs(self, z, torques=None, states_only=True):
        """(segment index, its replay, the replay's times on the recording's clock) of each
        segment, from its start state at z; torques: each segment's physics-step drive in place
        of the recorded one."""
        est = self.estimates(z)
        config, _ = fitted_config(self.base, est, extra=self.settings)  # one validation
        sim = Simulator(config)
        offset = 0.0 if self.motion.servo is not None else est.get("torque_offset", 0.0)
        x = z * self.scale
        for k in range(self.n_seg):
            sim.set_state([float(v) for v in x[self.n_free + 4 * k:self.n_free + 4 * k + 4]])
            run = sim.run(self.segments.steps[k] * self.step,
                          torque=(torques or self.segments.torque)[k] + offset,
                          output_rate=1.0 / self.step, states_only=states_only)
            yield k, run, run.t - run.t[0] + self.segments.start[k]

    def lag(self, z):
        return z[self.n_lag] * self.scale[self.n_lag]

    def model_q(self, z, torques=None):
        """The model's positions at the rows; torques: each segment's physics-step torques in
        place of the recorded ones'."""
        q = np.empty((len(self.rows), 2))
        at = 0
        for k, run, t in self._segment_runs(z, torques):
            seg_rows = self.segments.rows[k]
            for c in (0, 1):
                q[at:at + len(seg_rows), c] = np.interp(self.motion.t[seg_rows] - self.lag(z), t,
                                                        run.q[:, c])
            at += len(seg_rows)
        q[:, 0] += self.bias_basis @ (z * self.scale)[self.first_knot:self.n_lag]
        return q

    def residual(self, z, tolerant=True):
        """The positions' misfit at z in noise units (q1 rows, then q2 rows)."""
        try:
            q = self.model_q(z)
        except (ValueError, RuntimeError):  # a refused config or step: far from the data
            if not tolerant:
                raise
            return np.full(2 * len(self.rows), 1e3)
        return np.concatenate([(q[:, k] - self.q_data[:, k]) / self.sigma[k] for k in (0, 1)])

    def position_rms(self, r):
        """(q1 [rad], q2 [m]) RMS of a residual vector (q1 rows, then q2 rows, in noise units)."""
        half = len(r) // 2
        return tuple(float(self.sigma[k] * np.sqrt(np.mean(r[k * half:(k + 1) * half] ** 2)))
                     for k in (0, 1))

    def servo_effort_mismatch(self, z):
        """(the median |servo law's torque in the replays - the recorded effort| at the rows,
        the median |effort|) [N m]: how well the config's servo (its gains, limit) is the rig's.
        A reading's effort is the torque in force at its stamp (a script's record) or, from the
        node's sensors, at its sample, the lag before: the closer of the two."""
        motion = self.motion
        diffs = ([], [])
        for k, run, t in self._segment_runs(z, states_only=False):
            seg_rows = self.segments.rows[k]
            for diff, shift in zip(diffs, (0.0, self.lag(z))):
                at = np.searchsorted(t, motion.t[seg_rows] - shift + 1e-9, side="right") - 1
                model = np.asarray(run.applied_torque)[np.clip(at, 0, len(t) - 1)]
                diff.append(model - motion.torque[seg_rows])
        # Medians: a reading stamped within the sensors' jitter of a setpoint's step compares
        # the torque on the step's other side (a 2 ms jitter put 10 % of the effort's RMS into
        # the RMS mismatch of a servo with the rig's own gains).
        mismatch = min(float(np.median(np.abs(np.concatenate(d)))) for d in diffs)
        return mismatch, float(np.median(np.abs(motion.torque[self.rows])))

    def at_base(self, z):
        """z with the parameters at the base's values (the start states, drift and lag kept)."""
        out = z.copy()
        out[:self.n_free] = np.array([
            0.0 if self.names[i] == "torque_offset" else
            _core.identification_base_value(self.base._core, self.names[i])
            for i in self.free]) / self.scale[:self.n_free]
        return out


class _Jacobian:
    """The residual's Jacobian by forward differences, grouped: a segment's start state moves
    only its own rows, so one evaluation perturbs that component of every segment's state at
    once (4 evaluations for all of them); each parameter takes one, the lag one. The drift knots
    enter q1 linearly (q1 + basis @ bias): their columns are the basis, no replay. The
    evaluations are independent replays (the simulator lets go of the GIL while it steps): they
    run on every core this process may use. Keeps the cost at each call (`iterations`); with
    give_up_early raises _Stalled when the fit has stalled far from the recording."""

    def __init__(self, problem, max_evaluations, give_up_early, progress):
        p = problem
        self.problem, self.max_evaluations = p, max_evaluations
        self.give_up_early, self.progress = give_up_early, progress
        self.groups = [[j] for j in range(p.n_free)] + \
            [[p.n_free + 4 * k + c for k in range(p.n_seg)] for c in range(4)] + [[p.n_lag]]
        self.workers = min(len(self.groups), len(os.sched_getaffinity(0)))
        self.iterations = []  # the cost (sum of squared residuals) at each Jacobian
        self.calls = 0  # the solver's evaluations of the residual

    def residual(self, z):
        """The solver's residual, counted."""
        self.calls += 1
        return self.problem.residual(z)

    def __call__(self, z):
        p = self.problem
        steps = []
        for group in self.groups:
            h = 1e-6 * np.maximum(np.abs(z[group]), 1.0)
            steps.append(np.where(z[group] + h > p.upper[group], -h, h))  # inside the bounds

        def moved(k):
            z1 = z.copy()
            if k >= 0:
                z1[self.groups[k]] += steps[k]
            return p.residual(z1)
        with ThreadPoolExecutor(self.workers) as pool:
            results = list(pool.map(moved, range(-1, len(self.groups))))  # -1: z itself
        r0 = results[0]
        rms0 = p.position_rms(r0)
        if self.progress:
            self.progress("output error: iteration %d, positions %.3g rad, %.3g m RMS (noise "
                          "%.3g rad, %.3g m)" % ((len(self.iterations) + 1,) + rms0
                                                 + tuple(p.sigma)))
        self.iterations.append(float(r0 @ r0))
        jac = np.zeros((len(r0), len(z)))
        for group, h, r1 in zip(self.groups, steps, results[1:]):
            delta = r1 - r0
            if len(group) == 1:
                jac[:, group[0]] = delta / h[0]
            else:  # each segment's rows to its own state's column
                for k, j in enumerate(group):
                    mine = p.owner == k
                    jac[mine, j] = delta[mine] / h[k]
        jac[:len(p.rows), p.first_knot:p.n_lag] = \
            p.bias_basis * (p.scale[p.first_knot:p.n_lag] / p.sigma[0])
        if self._stalled(rms0, len(r0)):
            raise _Stalled(z, r0, jac)
        return jac

    def _stalled(self, rms, rows):
        """Far from the recording, and the cost's fall per iteration over the last
        STALL_ITERATIONS, against what is left to fall (to CONVERGED_NOISE_FACTOR times the
        noise on every row) and the evaluations left, says it will not get there."""
        sigma, it = self.problem.sigma, self.iterations
        far = any(rms[k] > CONVERGED_NOISE_FACTOR * sigma[k] for k in (0, 1))
        if not (self.give_up_early and far and len(it) > STALL_ITERATIONS):
            return False
        rate = math.log(it[-1 - STALL_ITERATIONS] / it[-1]) / STALL_ITERATIONS
        needed = math.log(it[-1] / (CONVERGED_NOISE_FACTOR ** 2 * rows))
        return rate * (self.max_evaluations - self.calls) < needed


def _covariance(problem, r, jac, z):
    """The unknowns' covariance (scaled z) at the solution: the Gauss-Newton one from the
    residual's variance, widened for correlated residuals and by the segments' disagreement."""
    dof = max(len(r) - len(z), 1)
    a_inv = np.linalg.pinv(jac.T @ jac)
    cov_z = (r @ r / dof) * a_inv
    # Correlated residuals (a sensor's bias walk, unmodelled dynamics) widen the errors.
    half = len(r) // 2
    inflation = max(_effective_samples_factor(r[:half]), _effective_samples_factor(r[half:]))
    cov_z *= inflation ** 2
    # And the segments as independent blocks (a cluster-robust sandwich, A^-1 B A^-1 with B the
    # sum over segments of their score's outer product): what is left of a misfit (a lag, a
    # quantiser, an unmodelled load) shows in how much the segments disagree. Each parameter's
    # variance is the larger of the two.
    n_seg, owner = problem.n_seg, problem.owner
    if n_seg >= 3:
        scores = np.array([jac[owner == k].T @ r[owner == k] for k in range(n_seg)])
        sandwich = a_inv @ (scores.T @ scores) @ a_inv * n_seg / (n_seg - 1)
        wider = np.sqrt(np.maximum(np.diag(sandwich), 0.0) / np.maximum(np.diag(cov_z), 1e-300))
        widen = np.maximum(wider, 1.0)
        cov_z = cov_z * np.outer(widen, widen)
    return cov_z


def _refine(base, names, theta, kept, motion, prepared, max_evaluations=40, progress=None,
            segment_seconds=SEGMENT_SECONDS, give_up_early=False):
    """Output error by multiple shooting: the parameters that make the model, driven by the
    recorded torque, pass closest to the recorded positions, each coordinate weighted by its
    noise (rates.position_noise). The recording is cut into SEGMENT_SECONDS segments, each
    replayed from a start state of its own (fitted beside the parameters, first guessed by the
    filter), so a slightly wrong model never drifts far from the data and the fit converges
    from the least-squares values (one replay of the whole recording stopped far off). Closed-loop
    data (a servo's torque) is fitted as recorded: within a segment the recorded torque drives.
    Position noise enters only the residual, not the regressor, so it does not bias the estimate
    as it biases the least squares. The crank encoder's slow drift is fitted beside them (a
    linear spline added to the model's q1). Parameters kept at the base stay there. Returns
    (theta, cov, report): report["converged"] says whether the positions were fitted to within
    CONVERGED_NOISE_FACTOR times the noise. progress (when given) hears each iteration.
    give_up_early: stop when the fit stalls far from the recording (STALL_ITERATIONS), for a
    caller with another attempt to make."""
    from scipy.optimize import least_squares
    p = _Problem(base, names, theta, kept, motion, prepared, segment_seconds)
    jacobian = _Jacobian(p, max_evaluations, give_up_early, progress)
    if progress:
        progress("output error: %d segments of %g s%s, %d parameters, at most %d evaluations"
                 % (p.n_seg, segment_seconds, " (of %d)" % p.segments.count
                    if p.segments.count > p.n_seg else "", p.n_free, max_evaluations))
    p.residual(p.z0, tolerant=False)  # the start must simulate: a failure here is named
    stalled = False
    try:
        solution = least_squares(jacobian.residual, p.z0, jac=jacobian,
                                 bounds=(p.lower, p.upper), max_nfev=max_evaluations,
                                 ftol=1e-8, xtol=1e-8, gtol=1e-8)
    except _Stalled as stop:  # far from the recording and no longer getting closer
        solution = stop
        solution.nfev = jacobian.calls
        stalled = True
    z, r = solution.x, solution.fun
    cov_z = _covariance(p, r, solution.jac, z)
    out = theta.copy()
    out[p.free] = z[:p.n_free] * p.scale[:p.n_free]
    cov = np.zeros((len(names), len(names)))
    scaled = cov_z[:p.n_free, :p.n_free] * np.outer(p.scale[:p.n_free], p.scale[:p.n_free])
    for a_i, i in enumerate(p.free):
        cov[i, p.free] = scaled[a_i]
    rms = p.position_rms(r)
    floor = _torque_sampling_floor(motion, p.segments, p.step, p.model_q, z)
    converged = all(rms[k] <= CONVERGED_NOISE_FACTOR * math.hypot(p.sigma[k], floor[k])
                    for k in (0, 1))
    # The base's parameters through the same segments (the fitted start states, drift and lag):
    # what the fit gained, judged where the model is judged (a whole-recording replay of a
    # crank in full turns diverges for any parameters, fitted or not).
    base_rms = p.position_rms(p.residual(p.at_base(z)))
    bias = z[p.first_knot:p.n_lag] * p.scale[p.first_knot:p.n_lag]
    return out, cov, {"evaluations": int(solution.nfev), "position_rms": rms,
                      "servo_effort": p.servo_effort_mismatch(z) if motion.servo is not None
                      else None,
                      "noise": tuple(float(x) for x in p.sigma), "segments": p.n_seg,
                      "stalled": stalled, "torque_sampling": floor,
                      "segments_of": p.segments.count, "stride": p.segments.stride,
                      "converged": converged, "evaluation_limit": max_evaluations,
                      "base_position_rms": base_rms, "segment_seconds": segment_seconds,
                      "crank_bias": (p.knots.tolist(), bias.tolist()),
                      "lag": float(p.lag(z)),
                      "lag_error": float(np.sqrt(max(cov_z[p.n_lag, p.n_lag], 0.0))
                                         * p.scale[p.n_lag])}


# [s] the shortest segments refine_segments tries: a crank whipped by a saturating PD loop (50 N m
# bang-bang, 100 slider crossings in 40 s, live node) left its true parameters 0.86 rad from the
# readings on 1 s segments (the filter's start states too far off for the fit to find its way)
# and at the noise on 0.5 s ones; from the least squares' values (30-70 % off on that data) the
# fit reached the noise on 0.25 s segments only.
SHORTEST_SEGMENT_SECONDS = 0.25
# The evaluations a fit on segments under 1 s may take: from the least squares' values (30-70 %
# off on a whipped crank) a /clock-stamped live recording was at 13 times the noise after 40 on
# 0.25 s segments, its true parameters at the noise.
SHORT_SEGMENT_EVALUATIONS = 80
# The evaluations of the last attempt (refine_segments), from where the shortest stopped: seed 103
# of the closed-loop family converged within them (masses within 0.006 %); a model that does not
# describe the data (a wrong L, a lag beyond MAX_LAG) spends them all, at every refusal, so no
# more than that.
RETRY_EVALUATIONS = 40


def refine_segments(base, names, theta, kept, motion, prepared, progress=None):
    """_refine on SEGMENT_SECONDS segments, and again on segments half as long while that does
    not converge, down to SHORTEST_SEGMENT_SECONDS: fast motion at a low sensor rate leaves the
    filter's start states of 2 s segments too far off for the fit to find its way (a 100 Hz
    recording of full turns stopped at 30 times the noise); half as long, each start matters
    less (the same rig: 1.5 times the noise, masses within 0.02 %). When none converges, the
    shortest is tried once more from where it stopped. Returns what _refine does, of the best
    attempt."""
    seconds = SEGMENT_SECONDS
    best = None
    while True:
        last = seconds / 2 < SHORTEST_SEGMENT_SECONDS - 1e-9
        out = _refine(base, names, theta, kept, motion, prepared, progress=progress,
                      segment_seconds=seconds, give_up_early=seconds == SEGMENT_SECONDS,
                      max_evaluations=_evaluations(seconds))
        if best is None or out[2]["converged"] or \
                sum(out[2]["position_rms"]) < sum(best[2]["position_rms"]):
            best = out
        if last and not out[2]["converged"]:
            # Once more from where the shortest stopped: its own values, the solver's trust
            # region afresh. Seed 103 of the closed-loop family (a PD loop at 200 Hz, 120 s, the
            # least squares' values 0.34 rad off on 2 s segments) crawled at 31 times the crank's
            # noise after 80 evaluations on 0.25 s segments, its true parameters at the noise;
            # restarted there, it converged (masses within 0.006 %).
            if progress:
                progress("output error: not converged with %g s segments; once more from where "
                         "it stopped" % seconds)
            again = _refine(base, names, out[0], kept, motion, prepared, progress=progress,
                            segment_seconds=seconds, max_evaluations=RETRY_EVALUATIONS)
            if again[2]["converged"] or \
                    sum(again[2]["position_rms"]) < sum(best[2]["position_rms"]):
                best = again
        if out[2]["converged"] or last:
            return best
        if progress:
            progress("output error: not converged with %g s segments; again with %g s"
                     % (seconds, seconds / 2))
        seconds /= 2


def _evaluations(seconds):
    """The evaluations a fit on segments `seconds` long may take."""
    return SHORT_SEGMENT_EVALUATIONS if seconds < 1.0 - 1e-9 else 40
