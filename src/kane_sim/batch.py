"""Many mechanisms stepped together, for learning loops and Monte Carlo.

    import kane_sim
    batch = kane_sim.BatchSimulator(4096, params={"mechanism.rod_mass": masses})
    states = batch.step(torques)             # (n, 4): q1, q2, u1, u2 of each mechanism
    done = batch.terminated                  # per mechanism: a refused step, crossed sliders

Mechanism i is a single kane_sim.Simulator of its config (the base config with row i of
`params`) that receives action i with set_torque (servo modes: the setpoint) and then steps:
bit for bit, on SIMD lanes (effort mode, rk4, generated equations, no contact, motor line,
command latency or sensors) and on drivers (everything else). VectorEnv wraps it in the shape
Gymnasium's vector environments have.
"""
import contextlib
import enum
import threading

import numpy as np

from kane_sim import _core, columns
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
    columns = {}
    for name, values in params.items():
        if not isinstance(name, str):
            raise TypeError("params: names must be config names ('section.key'), got %r" % (name,))
        array = np.asarray(values)
        if array.dtype.kind == "c" or array.dtype.kind not in "biufUSO":
            raise TypeError("params[%r]: numbers, strings or bools, got %s" % (name, array.dtype))
        if array.ndim == 0:
            array = np.full(n, array.item(), dtype=object)
        if array.shape != (n,):
            raise ValueError("params[%r]: one value or %d (one per mechanism), got shape %s"
                             % (name, n, array.shape))
        columns[name] = [v.item() if isinstance(v, np.generic) else v for v in array]
    names = list(columns)
    built = {}
    configs = []
    for i in range(n):
        row = tuple(columns[k][i] for k in names)
        key = tuple((type(v).__name__, v) for v in row)
        if key not in built:
            for name, value in zip(names, row):
                if isinstance(value, complex) or not isinstance(value, (bool, int, float, str)):
                    raise TypeError("params[%r][%d]: a number, a string or a bool, got %r"
                                    % (name, i, value))
            try:
                built[key] = base.with_values(dict(zip(names, row)))
            except _core.ConfigError as e:
                raise _core.ConfigError("mechanism %d: %s" % (i, e)) from None
        configs.append(built[key])
    return configs


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
            self._base, self._table = base, table
            self._configs = None
            self._batch = _core.BatchSimulator.from_numbers(
                base._core, table[0], table[1], simd, bool(vector_trig), int(threads))
        else:
            self._configs = _lane_configs(int(n), base, params)
            self._batch = _core.BatchSimulator([c._core for c in self._configs], simd,
                                               bool(vector_trig), int(threads))
        self._lock = threading.Lock()   # held by a step and by a read of the mechanisms
        self._claim = threading.Lock()  # guards _busy: a step under way
        self._busy = False
        self._seeds = self._batch.values("sensors.seed").astype(np.int64)

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
        if self._configs is None:
            names, values = self._table
            c = self._base.with_values({k: float(v) for k, v in zip(names, values[i])})
        else:
            c = self._configs[i]
        seed = int(self._seeds[i])
        return c if seed == c["sensors.seed"] else c.with_values({"sensors.seed": seed})

    def values(self, name):
        """Every mechanism's value of config name `name`: an array (n,) of numbers, or a list of
        n strings (command.mode, ...). Without building n Configs."""
        return self._read(lambda: self._batch.values(name))

    @contextlib.contextmanager
    def _exclusive(self, call):
        """A call that moves mechanisms: refused while another is under way (from another
        thread); it waits for a read in progress, which is short."""
        with self._claim:
            if self._busy:
                raise RuntimeError("%s: the BatchSimulator is in a step (from another thread); "
                                   "one call at a time" % call)
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
        with self._exclusive("reset"):
            if seed is None:
                return self._batch.reset(m)
            if isinstance(seed, (list, tuple, np.ndarray)):
                seeds = np.asarray(seed)
                if seeds.shape != (len(self),) or seeds.dtype.kind not in "iu" or \
                        seeds.min() < 0 or seeds.max() > MAX_SEED:
                    raise ValueError("reset: seed as a list holds %d whole numbers in [0, %d] "
                                     "(one per mechanism), got %s of %s"
                                     % (len(self), MAX_SEED, seeds.shape, seeds.dtype))
            else:
                most = MAX_SEED - (len(self) - 1)
                if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or \
                        not 0 <= seed <= most:
                    raise ValueError("reset: seed must be a whole number in [0, %d] (mechanism "
                                     "i takes sensors.seed = seed + i <= %d) or a list of %d, "
                                     "got %r" % (most, MAX_SEED, len(self), seed))
                seeds = int(seed) + np.arange(len(self))
            self._seeds[m] = seeds[m]  # config(i) applies it when asked
            return self._batch.reseed(m, [int(v) for v in seeds])

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

    def check_states(self, states, mask=None):
        """Raises what set_states(states, mask) would (nothing is set)."""
        m = self._mask("set_states", mask)
        x = _real_array("set_states: states", states, len(self))
        if x.shape != (len(self), 4):
            raise ValueError("set_states: states must have shape (%d, 4) (q1, q2, u1, u2 of "
                             "each mechanism), got %s" % (len(self), x.shape))
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


class AutoresetMode(enum.Enum):
    """Gymnasium's gymnasium.vector.AutoresetMode (the same names and values), for when
    Gymnasium is not installed; with it, VectorEnv's metadata holds Gymnasium's own member."""
    NEXT_STEP = "NextStep"
    SAME_STEP = "SameStep"
    DISABLED = "Disabled"


def _gymnasium():
    """gymnasium when it is importable (spaces and AutoresetMode are then its own), else None."""
    try:
        import gymnasium
        import gymnasium.spaces  # noqa: F401
        import gymnasium.vector  # noqa: F401
        return gymnasium
    except ImportError:
        return None


class Box:
    """A stand-in for gymnasium.spaces.Box when Gymnasium is not installed: shape, dtype, low,
    high, sample() (uniform where bounded, normal where not, as Gymnasium's), contains(),
    seed()."""

    def __init__(self, low, high, shape, dtype):
        self.shape, self.dtype = tuple(shape), np.dtype(dtype)
        self.low = np.broadcast_to(np.asarray(low, dtype=self.dtype), self.shape).copy()
        self.high = np.broadcast_to(np.asarray(high, dtype=self.dtype), self.shape).copy()
        self.np_random = np.random.default_rng()

    def seed(self, seed=None):
        self.np_random = np.random.default_rng(seed)
        return [seed]

    def sample(self):
        bounded = np.isfinite(self.low) & np.isfinite(self.high)
        x = self.np_random.normal(size=self.shape)
        u = self.np_random.uniform(np.where(bounded, self.low, 0.0),
                                   np.where(bounded, self.high, 1.0))
        return np.where(bounded, u, x).astype(self.dtype)

    def contains(self, x):
        x = np.asarray(x)
        return x.shape == self.shape and bool(np.all((x >= self.low) & (x <= self.high)))

    def __contains__(self, x):
        return self.contains(x)

    def __repr__(self):
        return "Box(%s, %s, %s, %s)" % (self.low.min(), self.high.max(), self.shape, self.dtype)


def _inward(values, dtype, toward):
    """values in `dtype`, rounded toward `toward` (+inf for a lower bound, -inf for an upper):
    float32's nearest of 6283185.307 is 6283185.5, a setpoint the servo refuses."""
    v = np.asarray(values, dtype=float)
    cast = v.astype(dtype)
    beyond = (cast < v) if toward > 0 else (cast > v)
    return np.where(beyond & np.isfinite(v), np.nextafter(cast, np.array(toward, dtype)), cast)


def _box(low, high, shape, dtype):
    low = np.broadcast_to(_inward(low, dtype, np.inf), shape)
    high = np.broadcast_to(_inward(high, dtype, -np.inf), shape)
    gym = _gymnasium()
    if gym is not None:
        return gym.spaces.Box(np.broadcast_to(np.asarray(low, dtype=dtype), shape),
                              np.broadcast_to(np.asarray(high, dtype=dtype), shape),
                              shape=shape, dtype=dtype)
    return Box(low, high, shape, dtype)


def _autoreset_mode(mode):
    """Gymnasium's AutoresetMode member (or this module's when Gymnasium is absent) for a member
    of either, its value ("NextStep") or its name in any case ("next_step")."""
    gym = _gymnasium()
    modes = gym.vector.AutoresetMode if gym is not None else AutoresetMode
    text = getattr(mode, "value", mode)
    if isinstance(text, str):
        for member in modes:
            if text in (member.value, member.name) or text.upper() == member.name:
                return member
    raise ValueError("VectorEnv: autoreset_mode must be one of next_step, same_step, disabled "
                     "(or Gymnasium's AutoresetMode), got %r" % (mode,))


START_NOISE_KEYS = ("q1", "q2", "u1", "u2")
# Gymnasium's wrappers (RecordEpisodeStatistics, ClipAction, NormalizeObservation) assert
# isinstance(env, gymnasium.vector.VectorEnv): with Gymnasium installed, VectorEnv is one.
_VECTOR_ENV_BASE = _gymnasium().vector.VectorEnv if _gymnasium() is not None else object


class VectorEnv(_VECTOR_ENV_BASE):
    """n mechanisms in the shape of Gymnasium 1.x's vector environments
    (gymnasium.vector.VectorEnv; Gymnasium is not needed, its spaces are used when installed).

    reset(seed=None, options=None) -> (obs, info); step(actions) -> (obs, reward, terminated,
    truncated, info), each an array over the mechanisms. obs: the states (n, 4), or with
    sensors the readings' positions and velocities (n, 8; the true joints until a mechanism's
    first reading arrives), as `dtype` (float64, or np.float32 on request). actions: (n,) or
    (n, 1) (what a Box(shape=(1,)) policy emits): a torque [N m] (servo modes: the setpoint),
    held for `substeps` physics steps. reward: reward(obs, actions) -> (n,) finite reals
    (default: the crank's speed u1 minus 1e-3 times the square of the torque delivered, the
    action clamped to command.torque_limit; in servo modes u1 alone). An episode is truncated
    after max_episode_steps actions.

    Spaces: single_observation_space, single_action_space (shape (1,), the range every
    mechanism accepts), observation_space and action_space (batched, per-mechanism ranges);
    action_low / action_high: each mechanism's range (effort: the torque limit; velocity: what
    the servo follows; position: a million turns).

    autoreset_mode (metadata["autoreset_mode"], Gymnasium's AutoresetMode): "next_step" (the
    default: the step after a mechanism's episode ended resets it and returns its first
    observation, reward 0 and both flags false; its action is ignored), "same_step" (the ending
    step resets it at once and returns the new episode's first observation; the ended one's last
    is in info["final_obs"], with info["_final_obs"] the mask) or "disabled" (reset them with
    reset(options={"reset_mask": mask}); stepping one that ended is refused).

    reset: seed an int (each mechanism's sensor noise from seed + i, and the random starts'
    generator) or a list of n ints (each mechanism's own); options {"reset_mask": bools} resets
    only those, {"states": (n, 4)} starts them from the given states instead of the config's.
    start_noise {"q1": a, "q2": b, "u1": c, "u2": d} draws every start (reset and autoreset)
    uniformly within +- those of the config's initial state, from reset's seed (a draw the
    simulator refuses, such as sliders crossed, is drawn again, up to 100 times).

    info: "times" (each mechanism's sim time), "reasons" (why a mechanism terminated) when one
    did, each with its "_key" mask as Gymnasium's vector infos. close() (and `with VectorEnv(...)
    as env:`) ends it: later calls are refused."""

    def __init__(self, n, config=None, params=None, reward=None, substeps=10,
                 max_episode_steps=1000, autoreset_mode="next_step", dtype=np.float64,
                 start_noise=None, **batch):
        if isinstance(substeps, bool) or not isinstance(substeps, (int, np.integer)) or \
                substeps < 1:
            raise ValueError("VectorEnv: substeps must be a whole number >= 1, got %r"
                             % (substeps,))
        if isinstance(max_episode_steps, bool) or \
                not isinstance(max_episode_steps, (int, np.integer)) or max_episode_steps < 1:
            raise ValueError("VectorEnv: max_episode_steps must be a whole number >= 1, got %r"
                             % (max_episode_steps,))
        if reward is not None and not callable(reward):
            raise TypeError("VectorEnv: reward must be callable reward(obs, actions), got %r"
                            % (reward,))
        try:
            self.dtype = np.dtype(dtype)
        except TypeError:
            raise TypeError("VectorEnv: dtype must be np.float64 or np.float32, got %r"
                            % (dtype,)) from None
        if self.dtype not in (np.dtype(np.float64), np.dtype(np.float32)):
            raise TypeError("VectorEnv: dtype must be np.float64 or np.float32, got %r"
                            % (dtype,))
        unknown = set(batch) - {"simd", "vector_trig", "threads"}
        if unknown:
            raise TypeError("VectorEnv: unknown argument %s (VectorEnv takes n, config, params, "
                            "reward, substeps, max_episode_steps, autoreset_mode, dtype, "
                            "start_noise, and BatchSimulator's simd, vector_trig, threads; the "
                            "seed goes to reset(seed=...))" % ", ".join(sorted(unknown)))
        self.start_noise = self._start_noise(start_noise)
        self.metadata = {"autoreset_mode": _autoreset_mode(autoreset_mode)}
        self.render_mode = None
        self.spec = None
        self.closed = False
        self.sim = BatchSimulator(n, config, params, **batch)
        self.num_envs = len(self.sim)
        self.substeps = int(substeps)
        self.max_episode_steps = int(max_episode_steps)
        self.reward = reward or self._default_reward
        self._sensors = self.sim._batch.sensors
        # What each observation column is: the state's columns of the output table, or each
        # joint's reading (position_<joint> then velocity_<joint>, the joint_states order).
        joints = _core.joint_names()
        self.observation_names = tuple(
            ["position_" + j for j in joints] + ["velocity_" + j for j in joints]
            if self._sensors else columns.STATE)
        self.single_observation_shape = (len(self.observation_names),)
        self.single_action_shape = ()
        self._mode = np.array(self.sim.values("command.mode"))
        self._effort = self._mode == "effort"
        # The command's range: effort the torque limit; velocity the servo's refusal (0.5 rad a
        # physics step); position a million turns.
        self.action_high = np.where(
            self._effort, self.sim.values("command.torque_limit"),
            np.where(self._mode == "velocity", 0.5 * self.sim.values("simulation.physics_rate"),
                     2e6 * np.pi))
        self.action_low = -self.action_high
        self._initial = np.column_stack([self.sim.values("initial_state." + k)
                                         for k in START_NOISE_KEYS])
        obs_dim = len(self.observation_names)
        self.single_observation_space = _box(-np.inf, np.inf, (obs_dim,), self.dtype)
        self.single_action_space = _box(self.action_low.max(), self.action_high.min(), (1,),
                                        self.dtype)
        self.observation_space = _box(-np.inf, np.inf, (self.num_envs, obs_dim), self.dtype)
        self.action_space = _box(self.action_low[:, None], self.action_high[:, None],
                                 (self.num_envs, 1), self.dtype)
        self._rng = np.random.default_rng()
        self._seeds = None  # per mechanism, after reset(seed=[...])
        self._draws = np.zeros(self.num_envs, dtype=np.int64)
        self._steps = np.zeros(self.num_envs, dtype=np.int64)
        self._ended = np.zeros(self.num_envs, dtype=bool)
        self._started = False

    @staticmethod
    def _start_noise(noise):
        if noise is None:
            return None
        if not isinstance(noise, dict):
            raise TypeError("VectorEnv: start_noise must be a dict such as {'q1': 0.1}, got %r"
                            % (noise,))
        out = np.zeros(4)
        for key, value in noise.items():
            if key not in START_NOISE_KEYS:
                raise ValueError("VectorEnv: start_noise takes %s, got %r"
                                 % (", ".join(START_NOISE_KEYS), key))
            if isinstance(value, bool) or not isinstance(value, (int, float, np.floating,
                                                                 np.integer)) \
                    or not (np.isfinite(value) and 0 <= value <= 1e3):
                raise ValueError("VectorEnv: start_noise[%r] must be a half-width in [0, 1e3], "
                                 "got %r" % (key, value))
            out[START_NOISE_KEYS.index(key)] = float(value)
        return out

    def _default_reward(self, obs, actions):
        u1 = obs[:, self.observation_names.index("velocity_crank_joint" if self._sensors else "u1")]
        delivered = np.clip(actions, self.action_low, self.action_high)
        return u1 - 1e-3 * np.where(self._effort, np.square(delivered), 0.0)

    @property
    def unwrapped(self):
        return self

    def render(self):
        raise NotImplementedError("VectorEnv draws nothing: kane_sim.animate(result) draws a "
                                  "run, rviz the node")

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def close(self, **kwargs):
        """Ends the environment (Gymnasium's API): later reset and step calls are refused."""
        self.closed = True

    def _open(self, call):
        if self.closed:
            raise RuntimeError("%s: the VectorEnv is closed" % call)

    def _observe(self):
        obs = np.hstack(self.sim.readings()) if self._sensors else self.sim.states
        return obs.astype(self.dtype, copy=False)

    def _start(self, mask, states=None):
        """The chosen mechanisms back to their start: the config's initial state, the given
        states, or a draw within start_noise of the initial state."""
        self.sim.reset(mask)
        if states is None and self.start_noise is not None and mask.any():
            chosen = np.flatnonzero(mask)
            x = self._initial.copy()
            pending = chosen
            for _ in range(100):
                x[pending] = self._initial[pending] + self._draw(pending)
                refused = [i for i in pending if not self._accepted(i, x[i])]
                if not refused:
                    break
                pending = np.array(refused)
            else:
                raise ValueError("start_noise: 100 draws for mechanism %d were all refused "
                                 "(the sliders crossed, or too fast for rk4): narrow it"
                                 % pending[0])
            states = x
        if states is not None:
            self.sim.set_states(states, mask)
        self._steps[mask] = 0
        self._ended[mask] = False

    def _draw(self, chosen):
        """Uniform offsets within start_noise for the chosen mechanisms: from the env's
        generator (an int seed), or each from its own seed and how many starts it has drawn (a
        list of seeds: mechanism i's starts depend on seed[i] alone, as Gymnasium's)."""
        if self._seeds is None:
            return self._rng.uniform(-self.start_noise, self.start_noise, size=(len(chosen), 4))
        out = np.empty((len(chosen), 4))
        for k, i in enumerate(chosen):
            rng = np.random.default_rng([int(self._seeds[i]), int(self._draws[i])])
            self._draws[i] += 1
            out[k] = rng.uniform(-self.start_noise, self.start_noise)
        return out

    def _accepted(self, i, x):
        return self.sim._batch.check_state(int(i), [float(v) for v in x]) == ""

    def reset(self, seed=None, options=None):
        """All mechanisms (or those of options["reset_mask"]) back to their start. Returns
        (obs, info)."""
        self._open("reset")
        if options is not None and not isinstance(options, dict):
            raise TypeError("reset: options must be a dict ({'reset_mask': bools, 'states': "
                            "(n, 4)}), got %r" % (options,))
        options = dict(options or {})
        unknown = set(options) - {"reset_mask", "mask", "states"}
        if unknown:
            raise ValueError("reset: options takes reset_mask and states, got %s"
                             % ", ".join(sorted(unknown)))
        mask = options.get("reset_mask", options.get("mask"))
        m = np.ones(self.num_envs, dtype=bool) if mask is None else np.asarray(mask)
        if m.dtype != bool or m.shape != (self.num_envs,):
            raise TypeError("reset: reset_mask must be %d booleans, got %s of %s"
                            % (self.num_envs, m.shape, m.dtype))
        states = options.get("states")
        if states is not None:  # every chosen state checked before anything moves
            states = _real_array("reset: options['states']", states, self.num_envs)
            self.sim.check_states(states, m)
        if seed is not None:
            self.sim.reset(m, seed)  # the sensors' noise afresh; validates the seed
            if np.ndim(seed) == 0:
                self._rng, self._seeds = np.random.default_rng(seed), None
            else:  # each mechanism its own stream of starts: seed[i] and its start count
                self._seeds = np.array([int(v) for v in seed])
                self._draws = np.zeros(self.num_envs, dtype=np.int64)
        self._start(m, states)
        self._started = True
        return self._observe(), {}

    def _actions(self, actions):
        a = _real_array("step: actions", actions, self.num_envs)
        if a.shape == (self.num_envs, 1):
            a = a[:, 0]
        if a.shape != (self.num_envs,):
            raise ValueError("step: actions must have shape (%d,) or (%d, 1), got %s"
                             % (self.num_envs, self.num_envs, a.shape))
        bad = np.flatnonzero(~np.isfinite(a))
        if bad.size:
            raise ValueError("step: actions[%d] = %r is not finite" % (bad[0], a[bad[0]]))
        return a

    def step(self, actions):
        self._open("step")
        if not self._started:
            raise RuntimeError("step: call reset() first (Gymnasium's order)")
        a = self._actions(actions)
        mode = self.metadata["autoreset_mode"].value
        restart = np.zeros(self.num_envs, dtype=bool)
        if mode == "NextStep":
            restart = self._ended.copy()  # their episode ended last step: this step resets them
            if restart.any():
                self._start(restart)
        elif mode == "Disabled" and self._ended.any():
            ended = np.flatnonzero(self._ended)
            raise ValueError("step: mechanisms %s ended their episode: reset them first with "
                             "reset(options={'reset_mask': ...}) (autoreset_mode Disabled)"
                             % ", ".join(str(i) for i in ended[:10]))
        self.sim.step(np.where(restart, 0.0, a), self.substeps, mask=~restart)
        obs = self._observe()
        self._steps[~restart] += 1
        # The physics has stepped: a reward that fails is raised with the step taken.
        reward = np.asarray(self.reward(obs, a))
        if reward.shape != (self.num_envs,) or reward.dtype.kind not in "iuf" or \
                not np.all(np.isfinite(reward)):
            raise ValueError("reward(obs, actions) must return %d finite reals, got %s of %s"
                             % (self.num_envs, reward.shape, reward.dtype))
        reward = np.where(restart, 0.0, reward.astype(float))
        terminated = self.sim.terminated & ~restart
        truncated = (self._steps >= self.max_episode_steps) & ~terminated & ~restart
        ended = terminated | truncated
        info = {"times": self.sim.times, "_times": np.ones(self.num_envs, dtype=bool)}
        if terminated.any():  # n strings only when one has a reason
            reasons = np.array(self.sim.reasons, dtype=object)
            info["reasons"], info["_reasons"] = np.where(terminated, reasons, None), terminated
        if mode == "SameStep" and ended.any():
            final = np.empty(self.num_envs, dtype=object)
            for i in np.flatnonzero(ended):
                final[i] = obs[i].copy()
            info["final_obs"], info["_final_obs"] = final, ended.copy()
            info["final_info"], info["_final_info"] = np.array(
                [{} if e else None for e in ended], dtype=object), ended.copy()
            self._start(ended)
            obs = self._observe()
        else:
            self._ended = ended
        return obs, reward, terminated, truncated, info
