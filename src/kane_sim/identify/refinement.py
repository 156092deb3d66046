"""The output-error stage: the parameters that make the re-simulated positions follow the
recorded ones, from the least-squares values (the regressor's noise biases those)."""
import math

import numpy as np

from kane_sim.core import Config, Simulator
from kane_sim.identify.least_squares import _dissipative, fitted_config
from kane_sim.identify.rates import _effective_samples_factor, estimate_rates


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
