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

from kane_sim import _core
from kane_sim.core import Config, _real


def _lane_configs(n, config, params):
    """One Config per mechanism: `config` with row i of `params` ({name: scalar or n values});
    identical rows share one Config. ConfigError names the mechanism."""
    base = config if isinstance(config, Config) else Config(config)
    params = dict(params or {})
    columns = {}
    for name, values in params.items():
        if not isinstance(name, str):
            raise TypeError("params: names must be config names ('section.key'), got %r" % (name,))
        array = np.asarray(values, dtype=float)
        if array.ndim == 0:
            array = np.full(n, float(array))
        if array.shape != (n,):
            raise ValueError("params[%r]: one value or %d (one per mechanism), got shape %s"
                             % (name, n, array.shape))
        columns[name] = array
    names = list(columns)
    rows = np.column_stack([columns[k] for k in names]) if names else np.zeros((n, 0))
    built = {}
    configs = []
    for i in range(n):
        key = rows[i].tobytes()
        if key not in built:
            try:
                built[key] = base.with_values(dict(zip(names, rows[i].tolist())))
            except _core.ConfigError as e:
                raise _core.ConfigError("mechanism %d: %s" % (i, e)) from None
        configs.append(built[key])
    return configs


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
        if n > 1 << 24:
            raise ValueError("BatchSimulator: n = %d mechanisms is more than 2^24" % n)
        if threads is None:
            threads = 2 if n >= 256 else 1
        if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)) or \
                not 1 <= threads <= 64:
            raise ValueError("BatchSimulator: threads must be a whole number in [1, 64], got %r"
                             % (threads,))
        if not isinstance(simd, str):
            raise TypeError("BatchSimulator: simd must be a string, got %r" % (simd,))
        self._configs = _lane_configs(int(n), config, params)
        self._batch = _core.BatchSimulator([c._core for c in self._configs], simd,
                                           bool(vector_trig), int(threads))
        self._lock = threading.Lock()

    def __len__(self):
        return self._batch.size

    @property
    def path(self):
        """How the mechanisms step: "avx512 lanes", or "drivers (why not lanes)"."""
        return self._batch.path

    def config(self, i):
        """Mechanism i's Config."""
        return self._configs[i]

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
        a = np.asarray(actions, dtype=float)
        if a.ndim == 0:
            raise ValueError("step: actions must hold one value per mechanism (%d), got a scalar"
                             % len(self))
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
            if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or \
                    not 0 <= seed < 2 ** 63:
                raise ValueError("reset: seed must be a whole number in [0, 2^63), got %r"
                                 % (seed,))
            for i in np.flatnonzero(m):
                self._configs[i] = self._configs[i].with_values({"sensors.seed": int(seed) + int(i)})
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
        return self._batch.reading_positions, self._batch.reading_velocities


def _default_reward(states, actions):
    """Keep the crank turning with little torque: u1 minus 1e-3 torque^2, per mechanism."""
    return states[:, 2] - 1e-3 * np.square(actions)


class VectorEnv:
    """n mechanisms in the shape of Gymnasium's vector environments (gymnasium.vector.VectorEnv;
    Gymnasium is not needed): reset(seed=None, options=None) -> (obs, info);
    step(actions) -> (obs, reward, terminated, truncated, info), each an array over the
    mechanisms. obs: the states (n, 4), or with sensors the readings' positions and velocities
    (n, 8). reward: reward(obs, actions) -> (n,) (default: u1 - 1e-3 torque^2). An episode is
    truncated after max_episode_steps actions; each action is held for `substeps` physics steps.
    Autoreset as Gymnasium 1.x's default (next step): the step after a mechanism's episode
    ended resets it and returns its first observation, with reward 0 and both flags false."""

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
        self.reward = reward or _default_reward
        self._sensors = self.sim._batch.sensors
        self.single_observation_shape = (8,) if self._sensors else (4,)
        self.single_action_shape = ()
        limits = np.array([self.sim.config(i)["command.torque_limit"]
                           for i in range(self.num_envs)])
        self.action_low, self.action_high = -limits, limits  # effort mode: the torque limit
        self._steps = np.zeros(self.num_envs, dtype=np.int64)
        self._ended = np.zeros(self.num_envs, dtype=bool)

    def _observe(self):
        if self._sensors:
            return np.hstack(self.sim.readings())
        return self.sim.states

    def reset(self, seed=None, options=None):
        """All mechanisms back to their start (seed: their sensors' noise drawn afresh from
        seed + i). options={"mask": bools} resets only those. Returns (obs, info)."""
        mask = None if not options else options.get("mask")
        self.sim.reset(mask, seed)
        m = np.ones(self.num_envs, dtype=bool) if mask is None else np.asarray(mask, dtype=bool)
        self._steps[m] = 0
        self._ended[m] = False
        return self._observe(), {}

    def step(self, actions):
        a = np.asarray(actions, dtype=float)
        if a.shape != (self.num_envs,):
            raise ValueError("step: actions must have shape (%d,), got %s"
                             % (self.num_envs, a.shape))
        restart = self._ended.copy()  # their episode ended last step: this step resets them
        if restart.any():
            self.sim.reset(restart)
            self._steps[restart] = 0
        self.sim.step(np.where(restart, 0.0, a), self.substeps, mask=~restart)
        obs = self._observe()
        self._steps[~restart] += 1
        reward = np.asarray(self.reward(obs, a), dtype=float)
        if reward.shape != (self.num_envs,):
            raise ValueError("reward(obs, actions) must return shape (%d,), got %s"
                             % (self.num_envs, reward.shape))
        terminated = self.sim.terminated & ~restart
        truncated = (self._steps >= self.max_episode_steps) & ~terminated & ~restart
        reward = np.where(restart, 0.0, reward)
        self._ended = terminated | truncated
        info = {"reasons": self.sim.reasons, "times": self.sim.times}
        return obs, reward, terminated, truncated, info
