"""Many mechanisms stepped together, for learning loops and Monte Carlo.

    import kane_sim
    batch = kane_sim.BatchSimulator(4096, params={"mechanism.rod_mass": masses})
    states = batch.step(torques)             # (n, 4): q1, q2, u1, u2 of each mechanism
    done = batch.terminated                  # per mechanism: a refused step, crossed sliders

Mechanism i is a single kane_sim.Simulator of its config (the base config with row i of
`params`) that receives action i with set_torque (servo modes: the setpoint) and then steps:
bit for bit, on SIMD lanes (effort mode, rk4, generated equations, no contact, motor line,
command latency or sensors) and on drivers (everything else). kane_sim.vector_env wraps it in
the shape Gymnasium's vector environments have.
"""
import contextlib
import threading

import numpy as np

from kane_sim import _core
from kane_sim.core import Config

MAX_MECHANISMS = 1_000_000  # state ~1 KB a mechanism on lanes, ~7 KB on drivers: 1 / 7 GB
MAX_SEED = 2 ** 31 - 1      # sensors.seed's range


def _numbers_table(n, base, params):
    """(names, values (n, k)) when every param is a real number (or n of them) of the physics or
    the initial state and the sensors are off: the batch is built in C++ from the table (the
    loader's rules per number, no Config per row: 10^6 mechanisms in seconds). None otherwise."""
    if not params or base["sensors.enabled"]:
        return None
    names, columns = [], []
    for name, values in params.items():
        if not isinstance(name, str):
            return None
        try:
            if not _core.BatchSimulator.takes_directly(name):
                return None
        except _core.ConfigError:
            return None  # an unknown name: the loader's path names it
        array = np.asarray(values)
        if array.dtype.kind not in "iuf" or array.ndim > 1 or \
                (array.ndim == 1 and array.shape != (n,)):
            return None  # the loader's path refuses it by name
        names.append(name)
        columns.append(np.broadcast_to(array.astype(float), (n,)))
    return names, np.ascontiguousarray(np.column_stack(columns))


def _lane_configs(n, config, params):
    """One Config per mechanism: `config` with row i of `params` ({name: scalar or n values});
    identical rows share one Config. ConfigError names the mechanism."""
    base = config if isinstance(config, Config) else Config(config)
    params = dict(params or {})
    if base["sensors.enabled"] and "sensors.seed" not in params:
        # Each mechanism its own noise (Monte Carlo over n copies of one draw would be one draw).
        first = base["sensors.seed"]
        if first + n - 1 > MAX_SEED:
            raise ValueError("sensors.seed %d + %d mechanisms passes %d: give a smaller seed"
                             % (first, n, MAX_SEED))
        params["sensors.seed"] = np.arange(first, first + n)
    columns = _param_columns("params", params, n)
    names = list(columns)
    built = {}
    configs = []
    for i in range(n):
        row = tuple(columns[k][i] for k in names)
        key = tuple((type(v).__name__, v) for v in row)
        if key not in built:
            _check_row("params", names, row, i)
            try:
                built[key] = base.with_values(dict(zip(names, row)))
            except _core.ConfigError as e:
                raise _core.ConfigError("mechanism %d: %s" % (i, e)) from None
        configs.append(built[key])
    return configs


def _param_columns(call, params, n):
    """{name: n values} from {config name: one value or n values} (NumPy scalars as Python's)."""
    columns = {}
    for name, values in params.items():
        if not isinstance(name, str):
            raise TypeError("%s: names must be config names ('section.key'), got %r"
                            % (call, name))
        try:
            array = np.asarray(values)
        except ValueError:  # NumPy's "inhomogeneous shape"
            raise ValueError("%s[%r]: one value or %d, got ragged rows" % (call, name, n)) \
                from None
        if array.dtype.kind == "c" or array.dtype.kind not in "biufUSO":
            raise TypeError("%s[%r]: numbers, strings or bools, got %s"
                            % (call, name, array.dtype))
        if array.ndim == 0:
            array = np.full(n, array.item(), dtype=object)
        if array.shape != (n,):
            raise ValueError("%s[%r]: one value or %d (one per mechanism), got shape %s"
                             % (call, name, n, array.shape))
        columns[name] = [v.item() if isinstance(v, np.generic) else v for v in array]
    return columns


def _check_row(call, names, row, i):
    for name, value in zip(names, row):
        if isinstance(value, complex) or not isinstance(value, (bool, int, float, str)):
            raise TypeError("%s[%r][%d]: a number, a string or a bool, got %r"
                            % (call, name, i, value))


def _as_float(value, name, i):
    try:
        return float(value)
    except OverflowError:
        raise ValueError("set_params: params[%r][%d] = an integer of %d digits, beyond any "
                         "float" % (name, i, len(str(abs(value))))) from None


def _real_array(what, values, n):
    """values as n finite-or-not real numbers (ints, floats): TypeError for bools, complex
    numbers, strings; ValueError for a scalar or a wrong shape."""
    try:
        a = np.asarray(values)
    except ValueError:  # NumPy's "inhomogeneous shape": rows of different lengths
        raise ValueError("%s must be an array of real numbers, got ragged rows" % what) from None
    if a.ndim == 0:
        raise ValueError("%s must hold one value per mechanism (%d), got a scalar" % (what, n))
    if a.dtype.kind not in "iuf":
        raise TypeError("%s must be real numbers (ints or floats), got %s" % (what, a.dtype))
    return a.astype(float)


class BatchSimulator:
    """n mechanisms stepped together.

    config: the base (a Config, a path, a dict or None for config/mechanism.yaml); params:
    {config name: one value or n values} per mechanism (initial states too:
    "initial_state.q1"). simd: "auto" (the widest this CPU runs), an instruction set (avx512,
    avx2, sse2, scalar) or "off" (drivers only); vector_trig: SIMD lanes with a vector sin/cos
    (faster; no longer the single run's bits: doc/guide/batches.md); threads: lanes split over
    this many threads per step, and the threads that build them (default: 2, or 1 below 256
    mechanisms).

    step(actions, steps=1) -> states (n, 4); reset(mask=None, seed=None) -> states; terminated,
    reasons, times, states; with sensors, readings() -> (positions, velocities) of the last
    reading to reach each mechanism's joint_states."""

    def __init__(self, n, config=None, params=None, simd="auto", vector_trig=False,
                 threads=None):
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
            raise ValueError("BatchSimulator: n must be a whole number of mechanisms >= 1, got %r"
                             % (n,))
        if n > MAX_MECHANISMS:
            raise ValueError("BatchSimulator: n = %d mechanisms is more than %d (state memory: "
                             "~1 KB each on SIMD lanes, ~7 KB on drivers)" % (n, MAX_MECHANISMS))
        if threads is None:
            threads = 2 if n >= 256 else 1
        if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or \
                not 1 <= threads <= 64:
            raise ValueError("BatchSimulator: threads must be a whole number in [1, 64], got %r"
                             % (threads,))
        if not isinstance(simd, str):
            raise TypeError("BatchSimulator: simd must be a string, got %r" % (simd,))
        if not isinstance(vector_trig, (bool, np.bool_)):
            raise TypeError("BatchSimulator: vector_trig must be True or False, got %r"
                            % (vector_trig,))
        base = config if isinstance(config, Config) else Config(config)
        table = _numbers_table(int(n), base, dict(params or {}))
        if table is not None:
            # Domain randomisation of the physics: the C++ batch holds each mechanism's config
            # (~1 KB); a Python Config is made only when config(i) asks for one.
            self._batch = _core.BatchSimulator.from_numbers(
                base._core, table[0], table[1], simd, bool(vector_trig), int(threads))
        else:
            self._batch = _core.BatchSimulator([c._core for c in _lane_configs(int(n), base,
                                                                               params)],
                                               simd, bool(vector_trig), int(threads))
        # The batch's mechanisms' configs are the one record of them (rows, set_params, seeds):
        # config(i) reads back how mechanism i's differs from the base.
        self._base = base
        self._inertia_follows = _core.BatchSimulator.inertia_follows_mass(base._core)
        self._lock = threading.Lock()   # held by a step and by a read of the mechanisms
        self._claim = threading.Lock()  # guards _busy: a call that moves mechanisms under way
        self._busy = False

    def __len__(self):
        return self._batch.size

    def __copy__(self):
        raise TypeError("a BatchSimulator cannot be copied (a copy would share its mechanisms): "
                        "build another with the same n, config and params")

    def __deepcopy__(self, memo):
        raise TypeError("a BatchSimulator cannot be deep-copied: build another with the same n, "
                        "config and params, and set its states by stepping")

    def __reduce__(self):
        raise TypeError("a BatchSimulator cannot be pickled: pickle its configs' yaml() and "
                        "states instead")

    @property
    def path(self):
        """How the mechanisms step: "avx512 lanes", or "drivers (why not lanes)"."""
        return self._batch.path

    def config(self, i):
        """Mechanism i's Config (with the sensors.seed a reset(seed=) gave it); i in [0, n)."""
        if isinstance(i, bool) or not isinstance(i, (int, np.integer)) or not 0 <= i < len(self):
            raise IndexError("config: mechanism must be a whole number in [0, %d), got %r"
                             % (len(self), i))
        return self._base.with_values(dict(self._read(
            lambda: self._batch.differences(int(i), self._base._core))))

    def set_params(self, params, mask=None, states=None):
        """Mechanisms where `mask` is true (default: all) take new values of config names
        (params: {name: one value or n values}; only the chosen mechanisms' are read), each
        written into that mechanism's config and checked as the loader checks it (a refused
        value changes nothing: ConfigError naming the mechanism), and start afresh from the new
        config, as reset(seed=) does: its initial state (or states[i], (n, 4), when given:
        judged by the new config), time 0, running again. Physics and initial-state numbers
        cost ~15 us a mechanism on the batch's threads (the loader's rules in C++; Ctrl-C stops
        a long one, changing nothing); other names go through the loader (~0.5 ms a mechanism).
        A change that would take a mechanism off the batch's SIMD lanes (command.mode, sensors,
        ...) is refused: build the batch with it. config(i) and values() read the new values.
        Returns the states (n, 4)."""
        m = self._mask("set_params", mask)
        starts = None
        if states is not None:
            x = self._state_table("set_params", states)
            starts = [[float(v) for v in x[i]] for i in np.flatnonzero(m)]
        if not isinstance(params, dict) or not params:
            raise TypeError("set_params: params must be a non-empty dict {config name: one value "
                            "or n values}, got %r" % (params,))
        try:  # every name known, even when no mechanism is chosen
            direct = all([_core.BatchSimulator.takes_directly(k) for k in params])
        except _core.ConfigError as e:
            raise _core.ConfigError("set_params: %s" % e) from None
        columns = _param_columns("set_params: params", params, len(self))
        names = list(columns)
        chosen = [int(i) for i in np.flatnonzero(m)]
        rows = []
        for i in chosen:
            row = tuple(columns[k][i] for k in names)
            _check_row("set_params: params", names, row, i)
            rows.append(dict(zip(names, row)))
        if not chosen:
            return self.states
        numbers = direct and all(isinstance(v, (int, float)) and not isinstance(v, bool)
                                 for row in rows for v in row.values())
        with self._exclusive("set_params"):
            if numbers:
                values = np.array([[_as_float(row[k], k, i) for k in names]
                                   for i, row in zip(chosen, rows)])
                return self._batch.reconfigure_numbers(chosen, names, values,
                                                       self._inertia_follows, starts)
            configs = []
            for i, row in zip(chosen, rows):
                try:
                    configs.append(self._base.with_values({**dict(
                        self._batch.differences(i, self._base._core)), **row}))
                except _core.ConfigError as e:
                    raise _core.ConfigError("set_params: mechanism %d: %s" % (i, e)) from None
            return self._batch.reconfigure(chosen, [c._core for c in configs], starts)

    def values(self, name, mask=None):
        """Every mechanism's value of config name `name` (or those where `mask` is true): an
        array (n,) of numbers, or a list of n strings (command.mode, ...). Without building n
        Configs."""
        lanes = None if mask is None else [int(i) for i in np.flatnonzero(self._mask("values",
                                                                                    mask))]
        return self._read(lambda: self._batch.values(name, lanes))

    @contextlib.contextmanager
    def _exclusive(self, call):
        """A call that moves mechanisms: refused while another is under way (from another
        thread); it waits for a read in progress, which is short."""
        with self._claim:
            if self._busy:
                raise RuntimeError("%s: the BatchSimulator is busy with a call from another "
                                   "thread (a step, a reset, set_params); one call at a time"
                                   % call)
            self._busy = True
        try:
            with self._lock:
                yield
        finally:
            with self._claim:
                self._busy = False

    def _read(self, read):
        """read() of the mechanisms between steps: a read from another thread waits for a step
        in progress to end (never half of its mechanisms updated)."""
        with self._lock:
            return read()

    def step(self, actions, steps=1, mask=None):
        """Each running mechanism (where `mask` is true, default all) takes its action (a
        torque [N m], clamped to its command.torque_limit; servo modes: the setpoint) and steps
        `steps` physics steps; terminated ones stay as they are. The action is held (re-sent)
        for all of them, as Simulator.step holds set_torque's. Returns the states (n, 4). A
        non-finite action is refused (ValueError naming it) before any moves. Ctrl-C stops every
        mechanism where it is: they may then stand at different times (see `times`)."""
        steps = _whole_steps("step", steps)
        a = _real_array("step: actions", actions, len(self))
        m = None if mask is None else np.asarray(mask)
        if m is not None and m.dtype != bool:
            raise TypeError("step: mask must be booleans (one per mechanism), got %s" % m.dtype)
        with self._exclusive("step"):
            return self._batch.step(a, steps, m)

    def rollout(self, actions, steps=1):
        """An open-loop plan at once (MuJoCo's rollout): actions (n, T), mechanism i taking
        actions[i, t] for `steps` physics steps at time step t. Returns the states (n, T + 1, 4):
        [:, 0] now, [:, t + 1] after time step t (a terminated mechanism keeps its state). The
        same numbers as T calls of step(actions[:, t], steps), without T calls' overhead."""
        steps = _whole_steps("rollout", steps)
        a = _real_array("rollout: actions", actions, len(self))
        if a.ndim != 2 or a.shape[0] != len(self):
            raise ValueError("rollout: actions must have shape (%d, T), got %s"
                             % (len(self), a.shape))
        if a.shape[1] * steps > 10_000_000:
            raise ValueError("rollout: %d time steps of %d physics steps is more than 1e7"
                             % (a.shape[1], steps))
        with self._exclusive("rollout"):
            return self._batch.rollout(a, steps)  # a: _real_array's float copy already

    def _mask(self, call, mask):
        m = np.ones(len(self), dtype=bool) if mask is None else np.asarray(mask)
        if m.dtype != bool:
            raise TypeError("%s: mask must be booleans (one per mechanism), got %s"
                            % (call, m.dtype))
        if m.shape != (len(self),):
            raise ValueError("%s: mask must hold one bool per mechanism (%d), got shape %s"
                             % (call, len(self), m.shape))
        return m

    def reset(self, mask=None, seed=None):
        """Mechanisms where `mask` is true (default: all) back to their initial state, running
        again; sim time runs on. With `seed` they start afresh from their config (time 0
        again) with sensors.seed = seed + i (an int >= 0), or seed[i] (a list of n ints): the
        same noise as a Simulator of that config. Returns the states (n, 4)."""
        m = self._mask("reset", mask)
        seeds = None if seed is None else self.seeds_of(seed)
        with self._exclusive("reset"):
            if seeds is None:
                return self._batch.reset(m)
            return self._batch.reseed(m, [int(v) for v in seeds])

    def seeds_of(self, seed):
        """Each mechanism's sensors.seed for reset(seed=seed): seed + i (an int), or the list;
        ValueError naming what is wrong."""
        if isinstance(seed, (list, tuple, np.ndarray)):
            seeds = np.asarray(seed)
            if seeds.shape != (len(self),) or seeds.dtype.kind not in "iu" or \
                    seeds.min() < 0 or seeds.max() > MAX_SEED:
                raise ValueError("reset: seed as a list holds %d whole numbers in [0, %d] "
                                 "(one per mechanism), got %s of %s"
                                 % (len(self), MAX_SEED, seeds.shape, seeds.dtype))
            return seeds
        most = MAX_SEED - (len(self) - 1)
        if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or \
                not 0 <= seed <= most:
            raise ValueError("reset: seed must be a whole number in [0, %d] (mechanism "
                             "i takes sensors.seed = seed + i <= %d) or a list of %d, "
                             "got %r" % (most, MAX_SEED, len(self), seed))
        return int(seed) + np.arange(len(self))

    def set_states(self, states, mask=None):
        """Mechanisms where `mask` is true (default: all) put into states[i] = (q1, q2, u1, u2)
        (states: (n, 4); a Simulator's set_state: an episode started anywhere), running again;
        sim time runs on. Every chosen state is checked first (finite, the sliders apart, within
        rk4's reach): one refused changes nothing (ValueError naming the mechanism). Returns the
        states (n, 4)."""
        m = self._mask("set_states", mask)
        x = _real_array("set_states: states", states, len(self))
        with self._exclusive("set_states"):
            return self._batch.set_states(x, m)

    def _state_table(self, call, states):
        x = _real_array("%s: states" % call, states, len(self))
        if x.shape != (len(self), 4):
            raise ValueError("%s: states must have shape (%d, 4) (q1, q2, u1, u2 of "
                             "each mechanism), got %s" % (call, len(self), x.shape))
        return x

    def check_states(self, states, mask=None):
        """Raises what set_states(states, mask) would (nothing is set)."""
        m = self._mask("set_states", mask)
        x = self._state_table("set_states", states)
        for i in np.flatnonzero(m):
            why = self._batch.check_state(int(i), [float(v) for v in x[i]])
            if why:
                raise ValueError("set_states: mechanism %d: %s" % (i, why))

    @property
    def states(self):
        """(n, 4): q1 [rad], q2 [m], u1 [rad/s], u2 [m/s] of each mechanism now."""
        return self._read(lambda: self._batch.states)

    @property
    def times(self):
        """(n,): each mechanism's sim time [s]."""
        return self._read(lambda: self._batch.times)

    @property
    def terminated(self):
        """(n,) bool: stopped by a refused step or crossed sliders, until reset."""
        return self._read(lambda: self._batch.terminated)

    @property
    def reasons(self):
        """Per mechanism why it stopped ("" while running)."""
        return self._read(lambda: self._batch.reasons)

    def readings(self):
        """With sensors: (positions, velocities), each (n, 4) in joint_states' order (crank,
        coupler, slider 3, slider 4), of the last reading to reach each mechanism (the true
        joints at the start until the first arrives)."""
        if not self._batch.sensors:
            raise ValueError("readings: the sensors are off (sensors.enabled false): the states "
                             "are the mechanisms' exact values")
        return self._read(lambda: (self._batch.reading_positions,
                                   self._batch.reading_velocities))


def _whole_steps(call, steps):
    if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 1:
        raise ValueError("%s: steps must be a whole number of physics steps >= 1, got %r"
                         % (call, steps))
    if steps > 10_000_000:
        raise ValueError("%s: steps = %d is more than 1e7 physics steps" % (call, steps))
    return int(steps)
