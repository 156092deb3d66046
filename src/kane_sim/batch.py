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
import threading

import numpy as np

from kane_sim import _core, columns
from kane_sim.core import Config

MAX_MECHANISMS = 1_000_000  # state ~1 KB a mechanism on lanes, ~7 KB on drivers: 1 / 7 GB
MAX_SEED = 2 ** 31 - 1      # sensors.seed's range


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
    a = np.asarray(values)
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
    this many threads per step (default: 2, or 1 below 256 mechanisms).

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
        self._configs = _lane_configs(int(n), config, params)
        self._batch = _core.BatchSimulator([c._core for c in self._configs], simd,
                                           bool(vector_trig), int(threads))
        self._lock = threading.Lock()
        self._seeds = np.array([c["sensors.seed"] for c in self._configs], dtype=np.int64)

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
        """Mechanism i's Config (with the sensors.seed a reset(seed=) gave it)."""
        c = self._configs[i]
        seed = int(self._seeds[i])
        return c if seed == c["sensors.seed"] else c.with_values({"sensors.seed": seed})

    @contextlib.contextmanager
    def _exclusive(self, call):
        if not self._lock.acquire(blocking=False):
            raise RuntimeError("%s: the BatchSimulator is in a step (from another thread); one "
                               "call at a time" % call)
        try:
            yield
        finally:
            self._lock.release()

    def step(self, actions, steps=1, mask=None):
        """Each running mechanism (where `mask` is true, default all) takes its action (a
        torque [N m], clamped to its command.torque_limit; servo modes: the setpoint) and steps
        `steps` physics steps; terminated ones stay as they are. Returns the states (n, 4). A
        non-finite action, or `steps` beyond command.timeout, is refused (ValueError naming it)
        before any moves."""
        if isinstance(steps, bool) or not isinstance(steps, (int, np.integer)) or steps < 1:
            raise ValueError("step: steps must be a whole number of physics steps >= 1, got %r"
                             % (steps,))
        if steps > 10_000_000:
            raise ValueError("step: steps = %d is more than 1e7 physics steps" % steps)
        a = _real_array("step: actions", actions, len(self))
        m = None if mask is None else np.asarray(mask)
        if m is not None and m.dtype != bool:
            raise TypeError("step: mask must be booleans (one per mechanism), got %s" % m.dtype)
        with self._exclusive("step"):
            return self._batch.step(a, int(steps), m)

    def reset(self, mask=None, seed=None):
        """Mechanisms where `mask` is true (default: all) back to their initial state, running
        again; sim time runs on. With `seed` (an int >= 0) they start afresh from their config
        with sensors.seed = seed + i (time 0 again): the same noise as a Simulator of that
        config. Returns the states (n, 4)."""
        m = np.ones(len(self), dtype=bool) if mask is None else np.asarray(mask)
        if m.dtype != bool:
            raise TypeError("reset: mask must be booleans (one per mechanism), got %s" % m.dtype)
        with self._exclusive("reset"):
            if seed is None:
                return self._batch.reset(m)
            most = MAX_SEED - (len(self) - 1)
            if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or \
                    not 0 <= seed <= most:
                raise ValueError("reset: seed must be a whole number in [0, %d] (mechanism i "
                                 "takes sensors.seed = seed + i <= %d), got %r"
                                 % (most, MAX_SEED, seed))
            self._seeds[m] = int(seed) + np.flatnonzero(m)  # config(i) applies it when asked
            return self._batch.reseed(m, int(seed))

    @property
    def states(self):
        """(n, 4): q1 [rad], q2 [m], u1 [rad/s], u2 [m/s] of each mechanism now."""
        return self._batch.states

    @property
    def times(self):
        """(n,): each mechanism's sim time [s]."""
        return self._batch.times

    @property
    def terminated(self):
        """(n,) bool: stopped by a refused step or crossed sliders, until reset."""
        return self._batch.terminated

    @property
    def reasons(self):
        """Per mechanism why it stopped ("" while running)."""
        return self._batch.reasons

    def readings(self):
        """With sensors: (positions, velocities), each (n, 4) in joint_states' order (crank,
        coupler, slider 3, slider 4), of the last reading to reach each mechanism (the true
        joints at the start until the first arrives)."""
        if not self._batch.sensors:
            raise ValueError("readings: the sensors are off (sensors.enabled false): the states "
                             "are the mechanisms' exact values")
        return self._batch.reading_positions, self._batch.reading_velocities


class VectorEnv:
    """n mechanisms in the shape of Gymnasium's vector environments (gymnasium.vector.VectorEnv;
    Gymnasium is not needed): reset(seed=None, options=None) -> (obs, info);
    step(actions) -> (obs, reward, terminated, truncated, info), each an array over the
    mechanisms. obs: the states (n, 4), or with sensors the readings' positions and velocities
    (n, 8; the true joints until a mechanism's first reading arrives). reward: reward(obs,
    actions) -> (n,) finite reals (default: the crank's speed u1 minus 1e-3 times the square of
    the torque delivered, the action clamped to command.torque_limit; in servo modes u1 alone).
    An episode is truncated after max_episode_steps actions; each action is held for `substeps`
    physics steps. Autoreset as Gymnasium 1.x's default (next step): the step after a mechanism's
    episode ended resets it and returns its first observation, with reward 0 and both flags
    false. action_low / action_high: the command's range per mechanism (effort: the torque
    limit; velocity: what the servo follows; position: a million turns)."""

    metadata = {"autoreset_mode": "NextStep"}

    def __init__(self, n, config=None, params=None, reward=None, substeps=10,
                 max_episode_steps=1000, **batch):
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
        self._mode = [self.sim.config(i)["command.mode"] for i in range(self.num_envs)]
        self.action_high = np.array([self._action_range(i) for i in range(self.num_envs)])
        self.action_low = -self.action_high
        self._steps = np.zeros(self.num_envs, dtype=np.int64)
        self._ended = np.zeros(self.num_envs, dtype=bool)
        self._started = False

    def _action_range(self, i):
        c = self.sim.config(i)
        if self._mode[i] == "effort":
            return c["command.torque_limit"]
        if self._mode[i] == "velocity":  # the servo's refusal: 0.5 rad a physics step
            return 0.5 * c["simulation.physics_rate"]
        return 2e6 * np.pi  # position: a million turns

    def _default_reward(self, obs, actions):
        u1 = obs[:, self.observation_names.index("velocity_crank_joint" if self._sensors else "u1")]
        effort = np.array([m == "effort" for m in self._mode])
        delivered = np.clip(actions, self.action_low, self.action_high)
        return u1 - 1e-3 * np.where(effort, np.square(delivered), 0.0)

    def close(self):
        """Nothing to release (Gymnasium's API)."""

    def _observe(self):
        if self._sensors:
            return np.hstack(self.sim.readings())
        return self.sim.states

    def reset(self, seed=None, options=None):
        """All mechanisms back to their start (seed: their sensors' noise drawn afresh from
        seed + i). options={"mask": bools} resets only those. Returns (obs, info)."""
        if options is not None and not isinstance(options, dict):
            raise TypeError("reset: options must be a dict ({'mask': bools}), got %r" % (options,))
        unknown = set(options or {}) - {"mask"}
        if unknown:
            raise ValueError("reset: options takes 'mask' only, got %s" % ", ".join(sorted(unknown)))
        mask = None if not options else options.get("mask")
        self.sim.reset(mask, seed)
        self._started = True
        m = np.ones(self.num_envs, dtype=bool) if mask is None else np.asarray(mask, dtype=bool)
        self._steps[m] = 0
        self._ended[m] = False
        return self._observe(), {}

    def step(self, actions):
        if not self._started:
            raise RuntimeError("step: call reset() first (Gymnasium's order)")
        a = _real_array("step: actions", actions, self.num_envs)
        if a.shape != (self.num_envs,):
            raise ValueError("step: actions must have shape (%d,), got %s"
                             % (self.num_envs, a.shape))
        bad = np.flatnonzero(~np.isfinite(a))
        if bad.size:
            raise ValueError("step: actions[%d] = %r is not finite" % (bad[0], a[bad[0]]))
        restart = self._ended.copy()  # their episode ended last step: this step resets them
        if restart.any():
            self.sim.reset(restart)
            self._steps[restart] = 0
        self.sim.step(np.where(restart, 0.0, a), self.substeps, mask=~restart)
        obs = self._observe()
        self._steps[~restart] += 1
        # The physics has stepped: a reward that fails is raised with the step taken.
        reward = np.asarray(self.reward(obs, a))
        if reward.shape != (self.num_envs,) or reward.dtype.kind not in "iuf" or \
                not np.all(np.isfinite(reward)):
            raise ValueError("reward(obs, actions) must return %d finite reals, got %s of %s"
                             % (self.num_envs, reward.shape, reward.dtype))
        reward = reward.astype(float)
        terminated = self.sim.terminated & ~restart
        truncated = (self._steps >= self.max_episode_steps) & ~terminated & ~restart
        reward = np.where(restart, 0.0, reward)
        self._ended = terminated | truncated
        info = {"reasons": self.sim.reasons, "times": self.sim.times}
        return obs, reward, terminated, truncated, info
