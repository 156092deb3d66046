"""The linear fit: Kane's equations (or their work-energy form) as Y theta = -y0, solved in the
parameters' own scales; what the motion cannot tell apart is named and kept at the base's value.
Also the estimates written into a config (fitted_config)."""
import numpy as np

from kane_sim import _core
from kane_sim.core import Config
from kane_sim.identify.rates import _effective_samples_factor


def _dissipative(name):
    """A resistance's coefficient (a damper's, friction's): >= 0, 0 = off (the schema's role)."""
    return name in Config.names() and Config.role(name) == "dissipative"


def _friction(name):
    """Coulomb friction's coefficient (its load's law; a damper's is viscous)."""
    return name in Config.names() and Config.law(name) == "coulomb"


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
    (per equation group), the estimates a kept value moves (_entangled), and those of the kept
    names the quadrature check kept (an effect within the integration error: the output error
    may still tell them). check: (y, b) of the same rows integrated by another rule, or None."""
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
    quadrature = [names[j] for j in last_estimate]
    if not free:
        return theta, cov, kept, messages, float("inf"), nan, [], quadrature
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
    return theta, cov, kept, messages, float(s[0] / s[-1]), rms, entangled, quadrature


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


def parameters():
    """Every parameter identify() can estimate: dicts of name, unit, symbol, by_default."""
    return _core.identifiable_parameters()


def fitted_config(base, estimates, std_errors=None, extra=None):
    """The base Config with the estimates written in, and the names of those written at their
    bound: an estimate below a parameter's bound (a damper's 0) by less than 3 standard errors is
    noise around it and is written as the bound; further below, ValueError (the model does not
    describe the data). The rest length goes in as initial_state.q2 (the config's spring is
    unstretched at the initial state); the torque offset is not a config value. `extra`: other
    config values set in the same validation (a replay's settings). With `std_errors`, each
    written parameter's standard error goes in as uncertainty.<name> (the estimator considers
    the model that uncertain); the rod's inertia, scaled with its mass, that of the mass."""
    values, clipped = {}, []
    uncertain = set(Config.names())
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
    sigmas = dict(std_errors or {})
    if "mechanism.rod_mass" in sigmas and "mechanism.rod_inertia" not in estimates:
        sigmas["mechanism.rod_inertia"] = (sigmas["mechanism.rod_mass"]
                                           * base["mechanism.rod_inertia"]
                                           / base["mechanism.rod_mass"])
    for name, sigma in sigmas.items():
        if name in values and "uncertainty." + name in uncertain and np.isfinite(sigma):
            values["uncertainty." + name] = float(max(sigma, 0.0))
    return base.with_values(dict(values, **(extra or {}))), clipped
