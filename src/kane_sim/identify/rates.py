"""The rates the equations need: u and u' from the recorded positions by zero-phase
Savitzky-Golay differentiation (the torque through the same filter), or the data as recorded."""
import math

import numpy as np



DEFAULT_BANDWIDTH = 8.0  # [Hz] of the derivative filter: above the mechanism's modes (~1-4 Hz)


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


def _roughness(motion):
    """(q1, q2) RMS of what a 7-point quintic fit leaves of the positions, away from the ends."""
    rough = motion.q - _savgol(motion.q, 7, 5, 0, 1.0 / motion.rate)
    return np.sqrt(np.mean(rough[3:-3] ** 2 if len(rough) > 6 else rough ** 2, axis=0))


def noise_free(motion):
    """True when the positions are smooth to rounding: a 7-point quintic fit leaves less than
    NOISE_FREE_ROUGHNESS (rad, m) per unit of their span (a simulation's output; a sensor's
    noise or a 12-bit encoder leaves far more)."""
    span = 1.0 + np.ptp(motion.q, axis=0)
    return bool(np.all(_roughness(motion) < NOISE_FREE_ROUGHNESS * span))


def position_noise(motion):
    """(q1 [rad], q2 [m]): the standard deviation of the positions' noise, encoder counts
    included, from what a 7-point quintic fit leaves: that residual is the noise through
    (1 - c0), c0 the fit's own weight on the middle sample (0.57), so its RMS over
    sqrt(1 - c0) is the noise's. Over the 30-rig family it gives the sensors' noise to within
    5 % on every rig; the derivative filter's residual, used before, gave up to 200 times it
    (an 8 Hz filter does not follow fast motion), and the output-error fit took it as the
    noise to weigh by and to converge to."""
    from scipy.signal import savgol_coeffs
    return _roughness(motion) / math.sqrt(1.0 - savgol_coeffs(7, 5)[3])


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
