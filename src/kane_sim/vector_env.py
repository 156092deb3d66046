"""kane_sim.VectorEnv: a batch of mechanisms (kane_sim.BatchSimulator) in the shape Gymnasium's
vector environments have (observations, rewards, terminations, truncations, infos; autoreset),
a subclass of gymnasium.vector.VectorEnv when Gymnasium is installed, with its own Box and
AutoresetMode otherwise.

    env = kane_sim.VectorEnv(256, max_episode_steps=500)
    obs, info = env.reset(seed=0)
    obs, reward, terminated, truncated, info = env.step(actions)
"""
import enum

import numpy as np

from kane_sim import _core, columns
from kane_sim.batch import BatchSimulator, _real_array


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

    reset: seed an int s (the same as the list s, s + 1, ..., s + n - 1; also seeds np_random)
    or a list of n ints (each mechanism's sensor noise and stream of random starts its own);
    options {"reset_mask": bools} resets
    only those, {"states": (n, 4)} starts them from the given states instead of the config's,
    {"params": {config name: one value or n values}} writes those into the reset mechanisms'
    configs first (BatchSimulator.set_params: checked as the loader checks them, a refusal
    changes nothing; they start afresh, their time at 0; action_space follows their limits).
    reset_params(np_random, mask) -> {config name: n values}, when given, does the same at every
    reset and autoreset for the mechanisms starting (mask): domain randomisation per episode,
    at the cost of the mechanisms that change.
    start_noise {"q1": a, "q2": b, "u1": c, "u2": d} draws every start (reset and autoreset)
    uniformly within +- those of the config's initial state, from reset's seed (a draw the
    simulator refuses, such as sliders crossed, is drawn again, up to 100 times).

    info: "times" (each mechanism's sim time, running on across episodes), "episode_steps" (the
    actions of each mechanism's episode so far), "clamped" (the actions beyond a mechanism's range,
    clamped to it), "reasons" (why a mechanism terminated) when one did, each with its "_key" mask
    as Gymnasium's vector infos. A reward that is not finite is refused naming the mechanism;
    the step is kept, its observation in env.last_obs. close() (and `with VectorEnv(...)
    as env:`) ends it: later calls are refused."""

    def __init__(self, n, config=None, params=None, reward=None, substeps=10,
                 max_episode_steps=1000, autoreset_mode="next_step", dtype=np.float64,
                 start_noise=None, reset_params=None, **batch):
        if isinstance(substeps, bool) or not isinstance(substeps, (int, np.integer)) or \
                substeps < 1:
            raise ValueError("VectorEnv: substeps must be a whole number >= 1, got %r"
                             % (substeps,))
        if isinstance(max_episode_steps, bool) or \
                not isinstance(max_episode_steps, (int, np.integer)) or max_episode_steps < 1:
            raise ValueError("VectorEnv: max_episode_steps must be a whole number >= 1, got %r"
                             % (max_episode_steps,))
        if reset_params is not None and not callable(reset_params):
            raise TypeError("VectorEnv: reset_params must be callable reset_params(np_random, "
                            "mask) -> {config name: n values}, got %r" % (reset_params,))
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
                            "start_noise, reset_params, and BatchSimulator's simd, vector_trig, "
                            "threads; the "
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
        self.reset_params = reset_params
        self._sensors = self.sim._batch.sensors
        # What each observation column is: the state's columns of the output table, or each
        # joint's reading (position_<joint> then velocity_<joint>, the joint_states order).
        joints = _core.joint_names()
        self.observation_names = tuple(
            ["position_" + j for j in joints] + ["velocity_" + j for j in joints]
            if self._sensors else columns.STATE)
        self.single_observation_shape = (len(self.observation_names),)
        self.single_action_shape = ()
        obs_dim = len(self.observation_names)
        self.single_observation_space = _box(-np.inf, np.inf, (obs_dim,), self.dtype)
        self.observation_space = _box(-np.inf, np.inf, (self.num_envs, obs_dim), self.dtype)
        self._read_configs()
        self._rng = np.random.default_rng()
        self.last_obs = None  # the last step's observation (kept when its reward is refused)
        self._seeds = None  # per mechanism, after reset(seed=[...])
        self._draws = np.zeros(self.num_envs, dtype=np.int64)
        self._steps = np.zeros(self.num_envs, dtype=np.int64)
        self._ended = np.zeros(self.num_envs, dtype=bool)
        # same_step: mechanisms whose autoreset failed (reset_params raised): started before the
        # next step moves anything.
        self._pending = np.zeros(self.num_envs, dtype=bool)
        self._started = False

    def _read_configs(self, mask=None):
        """What the env takes from the mechanisms' configs: their command modes, action ranges
        (and the action spaces of them) and initial states; again for those of `mask` after
        their params change (the spaces rebuilt only when a range changed)."""
        every = mask is None
        rows = slice(None) if every else mask
        def values(name):
            return self.sim.values(name, mask)
        if every:
            self._mode = np.empty(self.num_envs, dtype=object)
            self.action_high = np.empty(self.num_envs)
            self._initial = np.empty((self.num_envs, 4))
        mode = np.array(values("command.mode"), dtype=object)
        # The command's range: effort the torque limit; velocity the servo's refusal (0.5 rad a
        # physics step); position a million turns.
        high = np.where(mode == "effort", values("command.torque_limit"),
                        np.where(mode == "velocity", 0.5 * values("simulation.physics_rate"),
                                 2e6 * np.pi))
        changed = every or not np.array_equal(self.action_high[rows], high)
        self._mode[rows] = mode
        self._effort = self._mode == "effort"
        self.action_high[rows] = high
        self.action_low = -self.action_high
        self._initial[rows] = np.column_stack([values("initial_state." + k)
                                               for k in START_NOISE_KEYS])
        if changed:
            self.single_action_space = _box(self.action_low.max(), self.action_high.min(), (1,),
                                            self.dtype)
            self.action_space = _box(self.action_low[:, None], self.action_high[:, None],
                                     (self.num_envs, 1), self.dtype)

    def _set_params(self, call, params, mask, states=None):
        """The chosen mechanisms' configs with `params` ({name: one value or n values}), checked
        as the loader checks them (a refusal changes nothing), started afresh (from `states`
        when given). Returns whether any mechanism changed."""
        if not isinstance(params, dict):
            raise TypeError("%s must be a dict {config name: one value or %d values}, got %r"
                            % (call, self.num_envs, params))
        if "sensors.enabled" in params:
            raise ValueError("%s: sensors.enabled sets what the observation is: build the "
                             "VectorEnv with it" % call)
        if not params:
            return False
        try:
            self.sim.set_params(params, mask, states)
        except (ValueError, TypeError, _core.ConfigError) as e:
            raise type(e)("%s: %s" % (call, e)) from None
        if not mask.any():
            return False
        self._read_configs(mask)
        return True

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

    def _start(self, mask, states=None, fresh=None, draw_params=True):
        """The chosen mechanisms back to their start, from the config's initial state, the given
        states, or a draw within start_noise of the initial state; first (draw_params) with what
        reset_params gives written into their configs. `fresh` (a mask): mechanisms just
        rebuilt (new params or seeds), which a driver's reset would not leave as they are (it
        draws the sensors' first reading again)."""
        if draw_params and self.reset_params is not None and mask.any():
            params = self.reset_params(self.np_random, mask.copy())
            if self._set_params("reset_params(np_random, mask)", params, mask):
                fresh = mask
        stale = mask if fresh is None else mask & ~fresh
        if stale.any():
            self.sim.reset(stale)
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
        unknown = set(options) - {"reset_mask", "mask", "states", "params"}
        if unknown:
            raise ValueError("reset: options takes reset_mask, states and params, got %s"
                             % ", ".join(sorted(unknown)))
        mask = options.get("reset_mask", options.get("mask"))
        m = np.ones(self.num_envs, dtype=bool) if mask is None else np.asarray(mask)
        if m.dtype != bool or m.shape != (self.num_envs,):
            raise TypeError("reset: reset_mask must be %d booleans, got %s of %s"
                            % (self.num_envs, m.shape, m.dtype))
        # Everything is checked before anything changes: the seed, the states (against the new
        # params when there are any), the params.
        seeds = None if seed is None else self.sim.seeds_of(seed)
        states = options.get("states")
        if states is not None:
            states = self.sim._state_table("reset: options['states']", states)
        # An int seed also seeds np_random (a list: its seeds), which reset_params draws from.
        rng = self._rng if seeds is None else np.random.default_rng(
            seed if np.ndim(seed) == 0 else [int(v) for v in seeds])
        params, call = options.get("params"), "reset: options['params']"
        drawn = params is None and self.reset_params is not None and m.any()
        if drawn:
            params, call = self.reset_params(rng, m.copy()), "reset_params(np_random, mask)"
        fresh = None
        if (params is not None or drawn) and self._set_params(call, params, m, states):
            fresh = m  # the states were judged by the new params
        elif states is not None:
            self.sim.check_states(states, m)
        if seeds is not None:
            self.sim.reset(m, seeds)  # the sensors' noise afresh
            fresh = m
            # Each mechanism its own stream of starts, seed[i] and its start count; an int s is
            # the list s, s + 1, ... (as Gymnasium's vector envs take it, and as the sensors' noise).
            self._seeds = np.array([int(v) for v in seeds])
            self._rng = rng
            self._draws = np.zeros(self.num_envs, dtype=np.int64)
        self._pending &= ~m
        self._start(m, states, fresh, draw_params=False)
        self._started = True
        return self._observe(), {}

    @property
    def np_random(self):
        """The env's generator (numpy.random.Generator), seeded by reset(seed=int): for a
        learner's own draws. The starts come from each mechanism's own stream."""
        return self._rng

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
        elif mode == "SameStep" and self._pending.any():
            self._start(self._pending.copy())  # a failed autoreset again, before anything moves
            self._pending[:] = False
        elif mode == "Disabled" and self._ended.any():
            ended = np.flatnonzero(self._ended)
            raise ValueError("step: mechanisms %s ended their episode: reset them first with "
                             "reset(options={'reset_mask': ...}) (autoreset_mode Disabled)"
                             % ", ".join(str(i) for i in ended[:10]))
        self.sim.step(np.where(restart, 0.0, a), self.substeps, mask=~restart)
        obs = self._observe()
        self._steps[~restart] += 1
        # The physics has stepped and is kept: a reward that fails is named, and the step's
        # observation stays readable (env.last_obs) for the caller that catches it.
        self.last_obs = obs
        reward = np.asarray(self.reward(obs, a))
        if reward.shape != (self.num_envs,) or reward.dtype.kind not in "iuf":
            raise ValueError("reward(obs, actions) must return %d finite reals, got %s of %s "
                             "(the step was taken: its observation is env.last_obs)"
                             % (self.num_envs, reward.shape, reward.dtype))
        bad = np.flatnonzero(~np.isfinite(reward))
        if bad.size:
            raise ValueError("reward(obs, actions)[%d] = %r is not finite (%d of %d) (the step was "
                             "taken: its observation is env.last_obs)"
                             % (bad[0], reward[bad[0]], bad.size, self.num_envs))
        reward = np.where(restart, 0.0, reward.astype(float))
        terminated = self.sim.terminated & ~restart
        truncated = (self._steps >= self.max_episode_steps) & ~terminated & ~restart
        ended = terminated | truncated
        every = np.ones(self.num_envs, dtype=bool)
        # The mechanisms whose action was beyond their range and clamped to it (effort: the
        # torque limit), and each episode's actions so far (after an autoreset: the new one's).
        clamped = ~restart & ((a > self.action_high) | (a < self.action_low)) & self._effort
        info = {"times": self.sim.times, "_times": every,
                "clamped": clamped, "_clamped": every.copy(),
                "episode_steps": self._steps.copy(), "_episode_steps": every.copy()}
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
            try:
                self._start(ended)
            except Exception as e:  # reset_params failed: the step is kept, they start later
                self._pending = ended.copy()
                self.last_obs = obs
                e.add_note("(the step was taken: its observation is env.last_obs; mechanisms "
                           "%s, whose episodes ended, start at the next step or reset())"
                           % ", ".join(str(i) for i in np.flatnonzero(ended)[:10]))
                raise
            obs = self._observe()
        else:
            self._ended = ended
        return obs, reward, terminated, truncated, info
