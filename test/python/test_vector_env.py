"""kane_sim.VectorEnv as Gymnasium 1.x's vector environments are used by learning code (a
CleanRL-style PPO loop: spaces, reset, step, autoreset), without Gymnasium and with a stand-in
module that has its Box and AutoresetMode; BatchSimulator's rollout, set_states and per-mechanism
seeds, each against the single runs; reads from another thread between steps, never half of one."""
import sys
import threading
import types

import numpy as np
import pytest
import yaml

import kane_sim
from conftest import config_path


def ppo_style_rollout(env, steps, seed=1):
    """What a CleanRL-style PPO collection loop reads and calls of a vector env."""
    obs_dim = int(np.prod(env.single_observation_space.shape))
    act_dim = int(np.prod(env.single_action_space.shape))
    low, high = env.single_action_space.low, env.single_action_space.high
    obs, _ = env.reset(seed=seed)
    assert obs.shape == (env.num_envs, obs_dim)
    rng = np.random.default_rng(seed)
    dones, rewards = [], []
    for _ in range(steps):
        action = np.clip(rng.normal(0.0, 20.0, (env.num_envs, act_dim)), low, high)
        obs, reward, terminated, truncated, info = env.step(action)
        assert obs.shape == (env.num_envs, obs_dim)
        assert obs.dtype == env.single_observation_space.dtype
        assert reward.shape == (env.num_envs,) and np.all(np.isfinite(reward))
        dones.append(np.logical_or(terminated, truncated))
        rewards.append(reward)
    return np.array(dones), np.array(rewards), obs


def test_a_ppo_loop_runs_unchanged_without_gymnasium():
    with kane_sim.VectorEnv(8, config_path(), max_episode_steps=20, dtype=np.float32) as env:
        assert env.single_observation_space.shape == (4,)
        assert env.single_action_space.shape == (1,) and env.single_action_space.high[0] == 50.0
        assert env.observation_space.shape == (8, 4) and env.action_space.shape == (8, 1)
        assert env.metadata["autoreset_mode"].value == "NextStep"
        sample = env.single_action_space.sample()
        assert sample.shape == (1,) and sample.dtype == np.float32 and abs(sample[0]) <= 50.0
        dones, rewards, obs = ppo_style_rollout(env, 45)
        assert obs.dtype == np.float32
        # Truncated at 20 actions, reset on the 21st (reward 0), truncated again at 41.
        assert dones[19].all() and dones[40].all() and not dones[20].any()
        assert not rewards[20].any()
    with pytest.raises(RuntimeError, match="closed"):
        env.step(np.zeros(8))


def test_a_stand_in_gymnasium_gives_its_own_box_and_autoreset_mode(monkeypatch):
    import enum
    gym = types.ModuleType("gymnasium")
    gym.spaces = types.ModuleType("gymnasium.spaces")
    gym.vector = types.ModuleType("gymnasium.vector")

    class Box:  # gymnasium.spaces.Box's constructor and attributes
        def __init__(self, low, high, shape=None, dtype=np.float32):
            self.low, self.high = np.asarray(low, dtype), np.asarray(high, dtype)
            self.shape, self.dtype = tuple(shape), np.dtype(dtype)

    class AutoresetMode(enum.Enum):
        NEXT_STEP = "NextStep"
        SAME_STEP = "SameStep"
        DISABLED = "Disabled"
    gym.spaces.Box, gym.vector.AutoresetMode = Box, AutoresetMode
    for name, module in (("gymnasium", gym), ("gymnasium.spaces", gym.spaces),
                         ("gymnasium.vector", gym.vector)):
        monkeypatch.setitem(sys.modules, name, module)
    env = kane_sim.VectorEnv(3, config_path(), autoreset_mode=AutoresetMode.SAME_STEP)
    assert isinstance(env.single_action_space, Box) and isinstance(env.observation_space, Box)
    assert env.metadata["autoreset_mode"] is AutoresetMode.SAME_STEP
    assert env.action_space.high.shape == (3, 1)


def test_same_step_autoreset_returns_the_first_observation_and_the_last_in_final_obs():
    env = kane_sim.VectorEnv(3, config_path(), max_episode_steps=2, autoreset_mode="same_step")
    first, _ = env.reset()
    env.step(np.ones(3))
    obs, reward, terminated, truncated, info = env.step(np.ones((3, 1)))
    assert truncated.all() and info["_final_obs"].all()
    assert np.array_equal(obs, first)  # already the next episode's start
    assert not np.array_equal(info["final_obs"][0], first[0]) and reward.any()
    obs, reward, *_ = env.step(np.ones(3))
    assert not np.array_equal(obs, first) and reward.any()  # no lost step


def test_disabled_autoreset_waits_for_a_masked_reset():
    env = kane_sim.VectorEnv(3, config_path(), max_episode_steps=1, autoreset_mode="Disabled")
    first, _ = env.reset()
    _, _, _, truncated, _ = env.step(np.ones(3))
    assert truncated.all()
    with pytest.raises(ValueError, match="mechanisms 0, 1, 2 ended their episode.*reset_mask"):
        env.step(np.ones(3))
    obs, _ = env.reset(options={"reset_mask": np.array([True, False, False])})
    assert np.array_equal(obs[0], first[0]) and not np.array_equal(obs[1], first[1])
    with pytest.raises(ValueError, match="mechanisms 1, 2 ended"):
        env.step(np.ones(3))


def test_random_starts_are_seeded_within_their_bounds_and_refusals_named():
    noise = {"q1": 0.3, "u1": 2.0}
    a = kane_sim.VectorEnv(64, config_path(), start_noise=noise)
    b = kane_sim.VectorEnv(64, config_path(), start_noise=noise)
    x0 = kane_sim.Config(config_path())
    obs_a, _ = a.reset(seed=5)
    obs_b, _ = b.reset(seed=5)
    assert np.array_equal(obs_a, obs_b)  # the seed decides the draws
    assert np.all(np.abs(obs_a[:, 0] - x0["initial_state.q1"]) <= 0.3)
    assert np.all(np.abs(obs_a[:, 2]) <= 2.0) and np.ptp(obs_a[:, 2]) > 1.0
    assert np.all(obs_a[:, 1] == x0["initial_state.q2"])  # q2 not drawn
    assert not np.array_equal(a.reset(seed=6)[0], obs_a)
    for bad, words in (({"q1": float("nan")}, "half-width"), ({"q1": -1.0}, "half-width"),
                       ({"q1": float("inf")}, "half-width"), ({"q3": 0.1}, "takes q1, q2"),
                       ({"q1": 1e308}, "half-width"), ([0.1], "dict")):
        with pytest.raises((ValueError, TypeError), match=words):
            kane_sim.VectorEnv(2, config_path(), start_noise=bad)
    # A draw the simulator refuses is drawn again; refused every time: named, never a hang.
    fast = kane_sim.VectorEnv(2, config_path(), start_noise={"u1": 999.0})
    obs, _ = fast.reset(seed=0)  # |u1| h < 1 rad, but rk4 refuses some: drawn again
    assert np.all(np.abs(obs[:, 2]) < 999.0)
    fast._accepted = lambda i, x: False
    with pytest.raises(ValueError, match="100 draws for mechanism 0 were all refused"):
        fast.reset(seed=0)


def test_hostile_arguments_name_vector_env_and_the_value():
    with pytest.raises(TypeError, match="VectorEnv: unknown argument seed"):
        kane_sim.VectorEnv(2, config_path(), seed=0)
    with pytest.raises(ValueError, match="autoreset_mode"):
        kane_sim.VectorEnv(2, config_path(), autoreset_mode="sometimes")
    with pytest.raises(TypeError, match="dtype"):
        kane_sim.VectorEnv(2, config_path(), dtype=np.int32)
    env = kane_sim.VectorEnv(2, config_path())
    env.reset()
    with pytest.raises(ValueError, match=r"shape \(2,\) or \(2, 1\)"):
        env.step(np.zeros((2, 2)))
    with pytest.raises(ValueError, match="options takes reset_mask, states and params, got maks"):
        env.reset(options={"maks": [True, True]})
    with pytest.raises(ValueError, match="seed as a list holds 2"):
        env.reset(seed=[1, 2, 3])
    with pytest.raises(IndexError, match=r"\[0, 2\), got -1"):
        env.sim.config(-1)


def test_seeds_per_mechanism_are_the_single_runs_noise(tmp_path):
    import yaml
    cfg = yaml.safe_load(open(config_path()))
    cfg["sensors"] = yaml.safe_load(open(config_path("sensors.yaml")))["sensors"]
    path = tmp_path / "sensors.yaml"
    path.write_text(yaml.safe_dump(cfg))
    batch = kane_sim.BatchSimulator(3, str(path))
    batch.reset(seed=[40, 7, 123])
    assert [batch.config(i)["sensors.seed"] for i in range(3)] == [40, 7, 123]
    for _ in range(20):
        batch.step(np.array([1.0, 2.0, 3.0]), 10)
    sim = kane_sim.Simulator(batch.config(1))
    sim.set_torque(2.0)
    sim.step(200)
    assert np.array_equal(batch.states[1], sim.state)


@pytest.mark.parametrize("simd", ["auto", "off"])
def test_rollout_and_set_states_are_the_single_runs_bit_for_bit(simd):
    n, horizon = 6, 40
    rng = np.random.default_rng(2)
    starts = np.column_stack([rng.uniform(-1, 1, n), np.full(n, 1.2), rng.uniform(-2, 2, n),
                              np.zeros(n)])
    plan = rng.uniform(-10, 10, (n, horizon))
    batch = kane_sim.BatchSimulator(n, config_path(), simd=simd)
    batch.set_states(starts)
    trajectory = batch.rollout(plan, steps=5)
    assert trajectory.shape == (n, horizon + 1, 4)
    for i in range(n):
        sim = kane_sim.Simulator(config_path())
        sim.set_state(starts[i])
        assert np.array_equal(trajectory[i, 0], sim.state)
        for t in range(horizon):
            sim.set_torque(plan[i, t])
            sim.step(5)
            assert np.array_equal(trajectory[i, t + 1], sim.state), (i, t)
    # One refused state changes nothing, and names the mechanism.
    before = batch.states
    bad = before.copy()
    bad[0, 0] = 0.3
    bad[4, 2] = np.nan
    with pytest.raises(ValueError, match="mechanism 4: u1 = nan is not finite"):
        batch.set_states(bad)
    assert np.array_equal(batch.states, before)
    with pytest.raises(ValueError, match=r"actions\[2, 7\] = inf"):
        plan[2, 7] = np.inf
        batch.rollout(plan)
    with pytest.raises(ValueError, match=r"shape \(6, T\)"):
        batch.rollout(np.zeros(6))
    assert np.array_equal(batch.states, before)


def test_reads_from_another_thread_see_whole_steps():
    n = 4096
    batch = kane_sim.BatchSimulator(n, config_path())
    done = threading.Event()
    torn = []

    def read():
        while not done.is_set():
            times = batch.times
            if np.ptp(times) != 0.0:  # every mechanism steps together: one time for all
                torn.append(np.ptp(times))
    reader = threading.Thread(target=read)
    reader.start()
    try:
        for _ in range(200):
            batch.step(np.zeros(n), 7)
    finally:
        done.set()
        reader.join()
    assert not torn, torn[:3]
    assert batch.times[0] == pytest.approx(1.4)


def test_a_refused_start_changes_nothing_and_starts_are_typed():
    env = kane_sim.VectorEnv(2, config_path())
    env.reset(seed=0)
    for _ in range(5):
        env.step(np.full(2, 5.0))
    states, times = env.sim.states, env.sim.times
    for bad, kind, words in (([[np.nan, 1, 0, 0], [0.2, 1.1, 0, 0]], ValueError, "q1 = nan"),
                             (np.ones((2, 4)) + 0j, TypeError, "complex"),
                             (np.ones((2, 4), dtype=bool), TypeError, "bool"),
                             ([["a", 1, 0, 0], [0, 1, 0, 0]], TypeError, "<U"),
                             ([[0, 1, 0], [0, 1, 0, 0]], ValueError, "ragged")):
        with pytest.raises(kind, match=words):
            env.reset(seed=9, options={"states": bad})
        assert np.array_equal(env.sim.states, states) and np.array_equal(env.sim.times, times)
    obs, _ = env.reset(options={"states": [[0.1, 1.2, 0.5, 0.0], [0.3, 1.1, 0.0, 0.0]]})
    assert np.array_equal(obs[0], [0.1, 1.2, 0.5, 0.0])


def test_a_seed_list_gives_each_mechanism_its_own_starts():
    env = kane_sim.VectorEnv(3, config_path(), start_noise={"q1": 0.3, "u1": 2.0})
    a = env.reset(seed=[7, 8, 9])[0]
    b = env.reset(seed=[7, 100, 200])[0]
    assert np.array_equal(a[0], b[0]) and not np.array_equal(a[1], b[1])
    c = env.reset(seed=[7, 8, 9])[0]
    assert np.array_equal(a, c)


def test_float32_action_bounds_are_ones_the_mechanisms_accept():
    env = kane_sim.VectorEnv(2, config_path(), {"command.mode": "position"}, dtype=np.float32)
    high = env.single_action_space.high
    assert high.dtype == np.float32 and float(high[0]) <= 2e6 * np.pi
    env.reset()
    env.step(np.full((2, 1), high[0]))  # a clipped action is accepted
    assert float(env.action_space.low[0, 0]) >= -2e6 * np.pi


def test_with_gymnasium_installed_it_is_a_gymnasium_vector_env(monkeypatch):
    import importlib
    import kane_sim.vector_env as batch
    gym = types.ModuleType("gymnasium")
    gym.spaces = types.ModuleType("gymnasium.spaces")
    gym.vector = types.ModuleType("gymnasium.vector")

    class VectorEnv:  # gymnasium.vector.VectorEnv: what its wrappers assert
        metadata = {}

    gym.vector.VectorEnv, gym.vector.AutoresetMode = VectorEnv, batch.AutoresetMode
    gym.spaces.Box = batch.Box
    for name, module in (("gymnasium", gym), ("gymnasium.spaces", gym.spaces),
                         ("gymnasium.vector", gym.vector)):
        monkeypatch.setitem(sys.modules, name, module)
    try:
        reloaded = importlib.reload(batch)
        env = reloaded.VectorEnv(2, config_path())
        assert isinstance(env, VectorEnv) and env.unwrapped is env
    finally:
        monkeypatch.undo()
        importlib.reload(batch)
    assert not isinstance(kane_sim.VectorEnv(2, config_path()), VectorEnv)


def test_randomised_physics_from_a_table_is_the_loaders_configs_bit_for_bit(tmp_path):
    # Numbers of the physics and the initial state go into C++ configs by the loader's rules
    # (from_numbers); a parameter outside them (command.timeout) takes the loader's path, one
    # Config per row. Same mechanisms, same bits, same refusals.
    n = 40
    rng = np.random.default_rng(4)
    physics = {"mechanism.rod_mass": rng.uniform(0.5, 2.0, n),
               "mechanism.spring_stiffness": rng.uniform(100.0, 300.0, n),
               "damping.slider4_joint": rng.uniform(0.0, 0.5, n),
               "initial_state.q1": rng.uniform(-1.0, 1.0, n)}
    fast = kane_sim.BatchSimulator(n, config_path(), physics)
    slow = kane_sim.BatchSimulator(n, config_path(), dict(physics, **{"command.timeout": 0.5}))
    from kane_sim.batch import _numbers_table
    base = kane_sim.Config(config_path())
    assert _numbers_table(n, base, physics) is not None  # the C++ numbers path
    assert _numbers_table(n, base, dict(physics, **{"command.timeout": 0.5})) is None  # loader
    actions = rng.uniform(-5.0, 5.0, (30, n))
    for a in actions:
        fast.step(a, 10)
        slow.step(a, 10)
    assert np.array_equal(fast.states, slow.states)
    # The rod's inertia follows each row's mass as the loader derives it (the base sets none).
    inertia = fast.values("mechanism.rod_inertia")
    for i in (0, 17, n - 1):
        assert inertia[i] == slow.config(i)["mechanism.rod_inertia"] == \
            fast.config(i)["mechanism.rod_inertia"]
        assert fast.config(i)["mechanism.rod_mass"] == physics["mechanism.rod_mass"][i]
    assert fast.values("command.mode") == ["effort"] * n
    for bad, words in ((-1.0, "mechanism 7: config key 'mechanism.rod_mass' must be > 0, got -1"),
                       (np.nan, "mechanism 7: config key 'mechanism.rod_mass' must be finite"),
                       (1e308, "mechanism 7: config key 'mechanism.rod_mass' = 1e\\+308 is beyond the mechanism's scale")):
        masses = np.ones(n)
        masses[7] = bad
        for extra in ({}, {"command.timeout": 0.5}):
            with pytest.raises(kane_sim.ConfigError, match=words):
                kane_sim.BatchSimulator(n, config_path(),
                                        dict({"mechanism.rod_mass": masses}, **extra))


def test_an_int_seed_is_the_list_of_consecutive_seeds_through_autoresets():
    noise = {"q1": 0.3, "u1": 2.0}
    runs = []
    for seed in (11, [11, 12, 13, 14]):
        env = kane_sim.VectorEnv(4, config_path(), start_noise=noise, max_episode_steps=3)
        obs = [env.reset(seed=seed)[0]]
        for _ in range(8):  # two autoresets each
            obs.append(env.step(np.full(4, 2.0))[0])
        runs.append(np.array(obs))
    np.testing.assert_array_equal(runs[0], runs[1])
    env = kane_sim.VectorEnv(2, config_path())
    env.reset(seed=3)
    first = env.np_random.uniform()
    env.reset(seed=3)
    assert env.np_random.uniform() == first  # np_random is seeded by reset


def test_info_names_clamped_actions_and_counts_each_episode():
    env = kane_sim.VectorEnv(3, config_path(), max_episode_steps=2)
    env.reset(seed=0)
    limit = env.action_high[0]
    _, _, _, _, info = env.step([1e6, -1e300, 0.5 * limit])
    assert info["clamped"].tolist() == [True, True, False] and info["_clamped"].all()
    assert info["episode_steps"].tolist() == [1, 1, 1]
    _, _, _, truncated, info = env.step([limit, -limit, 0.0])  # at the limit: not clamped
    assert info["clamped"].tolist() == [False, False, False]
    assert truncated.all() and info["episode_steps"].tolist() == [2, 2, 2]
    _, _, _, _, info = env.step(np.zeros(3))  # next_step: the autoreset step
    assert info["episode_steps"].tolist() == [0, 0, 0]
    assert np.all(info["times"] > 0)  # sim time runs on across episodes


def test_a_reward_that_is_not_finite_is_named_and_the_step_kept():
    def reward(obs, actions):
        r = obs[:, 2].copy()
        r[1] = np.nan
        return r

    env = kane_sim.VectorEnv(3, config_path(), reward=reward)
    env.reset(seed=0)
    before = env.sim.times.copy()
    with pytest.raises(ValueError, match=r"reward\(obs, actions\)\[1\] = nan is not finite \(1 of 3\)"):
        env.step(np.ones(3))
    assert np.all(env.sim.times > before) and env.last_obs.shape == (3, 4)
    np.testing.assert_array_equal(env.last_obs, env._observe())


def test_reset_params_randomise_the_physics_of_each_episode_that_starts():
    """reset_params(np_random, mask) at every reset and autoreset: each mechanism that starts
    takes its row, and runs as the single Simulator of its new config; the same seed gives the
    same draws; the others run on untouched."""
    masks = []

    def draw(rng, mask):
        masks.append(mask.copy())
        return {"mechanism.rod_mass": rng.uniform(0.5, 2.0, mask.size),
                "friction.crank_joint": rng.choice([0.0, 0.2], mask.size)}

    def run(seed):
        env = kane_sim.VectorEnv(6, config_path(), reset_params=draw, substeps=5,
                                 max_episode_steps=4)
        env.reset(seed=seed)
        first = env.sim.values("mechanism.rod_mass").copy()
        masses = [first]
        for k in range(9):
            env.step(np.linspace(-5.0, 5.0, 6))
            masses.append(env.sim.values("mechanism.rod_mass").copy())
        return env, masses

    env, masses = run(3)
    # The reset, then the autoreset at step 5 (next_step: the step after the 4th action).
    assert len(masks) == 2 and masks[0].all() and masks[1].all()
    assert len({tuple(m) for m in masses}) == 2  # a draw per episode, kept within it
    assert not np.array_equal(masses[0], masses[-1])
    _, again = run(3)
    assert all(np.array_equal(a, b) for a, b in zip(masses, again))
    # Mechanism i now is the single run of config(i) from its episode's start (time 0): the
    # four actions of steps 6 to 9.
    for i in range(6):
        sim = kane_sim.Simulator(env.sim.config(i))
        for _ in range(4):
            sim.set_torque(np.linspace(-5.0, 5.0, 6)[i])
            sim.step(5)
        assert env.sim.times[i] == sim.time
        assert np.array_equal(env.sim.states[i], sim.state)


def test_reset_options_params_under_a_mask_and_hostile_rows():
    env = kane_sim.VectorEnv(4, config_path())
    env.reset(seed=0)
    env.step(np.ones(4))
    two = np.arange(4) < 2
    obs, _ = env.reset(options={"reset_mask": two,
                                "params": {"command.torque_limit": 3.0,
                                           "initial_state.q1": [0.1, 0.2, 9.0, 9.0]}})
    np.testing.assert_array_equal(env.action_high, [3.0, 3.0, 50.0, 50.0])
    assert env.action_space.high[:, 0].tolist() == [3.0, 3.0, 50.0, 50.0]
    assert env.single_action_space.high[0] == 3.0
    assert obs[:2, 0].tolist() == [0.1, 0.2] and env.sim.times[2] > 0
    _, _, _, _, info = env.step(np.full(4, 10.0))
    assert info["clamped"].tolist() == [True, True, False, False]
    before = env.sim.states.copy()
    for params, error, words in (
            ({"mechanism.rod_mass": np.nan}, kane_sim.ConfigError,
             r"reset: options\['params'\]: set_params: mechanism 0: .*rod_mass.* finite"),
            ({"mechanism.rod_mass": [1.0, 1.0, -1.0, 1.0]}, kane_sim.ConfigError,
             r"mechanism 2: .*rod_mass"),
            ({"sensors.enabled": True}, ValueError, r"sensors.enabled sets what the observation"),
            ([1.0], TypeError, r"must be a dict")):
        with pytest.raises(error, match=words):
            env.reset(options={"params": params})
        assert np.array_equal(env.sim.states, before)
    for bad, error, words in ((lambda rng, mask: None, TypeError,
                               r"reset_params\(np_random, mask\) must be a dict"),
                              (lambda rng, mask: {"mechanism.rod_mass": np.inf},
                               kane_sim.ConfigError, r"reset_params.*mechanism 0"),
                              (lambda rng, mask: 1 / 0, ZeroDivisionError, r"")):
        env = kane_sim.VectorEnv(2, config_path(), reset_params=bad)
        with pytest.raises(error, match=words):
            env.reset()
    with pytest.raises(TypeError, match=r"reset_params must be callable"):
        kane_sim.VectorEnv(2, config_path(), reset_params=3)


def test_a_refused_reset_changes_nothing_and_a_failed_autoreset_keeps_the_step(tmp_path):
    env = kane_sim.VectorEnv(2, config_path(), max_episode_steps=2, autoreset_mode="same_step")
    env.reset(seed=0)
    env.step(np.ones(2))
    before = (env.sim.states.copy(), env.sim.times.copy(), env.sim.values("mechanism.rod_mass"))
    for options, seed in (({"params": {"mechanism.rod_mass": 1.4},
                            "states": [[np.nan, 0, 0, 0], [0.2, 0, 0, 0]]}, None),
                          ({"params": {"mechanism.rod_mass": 1.4},
                            "states": np.zeros((2, 3))}, None),
                          ({"params": {"mechanism.rod_mass": 1.4}}, -1)):
        with pytest.raises(ValueError):
            env.reset(seed=seed, options=options)
        after = (env.sim.states, env.sim.times, env.sim.values("mechanism.rod_mass"))
        assert all(np.array_equal(a, b) for a, b in zip(before, after)), options
    # same_step: a reset_params that fails at an autoreset keeps the step that ended the
    # episodes (last_obs) and tries again before the next step moves anything.
    failing = [True]

    def draw(rng, mask):
        if failing[0]:
            raise RuntimeError("no draw today")
        return {"mechanism.rod_mass": np.full(mask.size, 1.2)}

    env = kane_sim.VectorEnv(2, config_path(), max_episode_steps=2, autoreset_mode="same_step",
                             reset_params=lambda rng, mask: {})
    env.reset(seed=0)
    env.reset_params = draw
    env.step(np.ones(2))
    with pytest.raises(RuntimeError, match="no draw today") as raised:
        env.step(np.ones(2))
    assert "start at the next step" in "".join(raised.value.__notes__)
    times = env.sim.times.copy()
    assert env.last_obs is not None and times == pytest.approx([0.02, 0.02])
    with pytest.raises(RuntimeError, match="no draw today"):
        env.step(np.ones(2))
    assert np.array_equal(env.sim.times, times)  # nothing moved
    failing[0] = False
    _, _, _, _, info = env.step(np.ones(2))
    assert (env.sim.values("mechanism.rod_mass") == 1.2).all()
    assert info["episode_steps"].tolist() == [1, 1] and env.sim.times == pytest.approx([0.01] * 2)


def test_readings_after_a_seeded_reset_are_a_fresh_simulators(tmp_path):
    cfg = yaml.safe_load(open(config_path()))
    cfg["sensors"] = yaml.safe_load(open(config_path("sensors.yaml")))["sensors"]
    path = tmp_path / "sensors.yaml"
    path.write_text(yaml.safe_dump(cfg))
    env = kane_sim.VectorEnv(2, str(path), reset_params=lambda rng, mask: {
        "mechanism.rod_mass": rng.uniform(0.8, 1.2, mask.size)})
    obs, _ = env.reset(seed=4)
    for _ in range(3):
        obs, *_ = env.step(np.full(2, 2.0))
    for i in range(2):
        sim = kane_sim.Simulator(env.sim.config(i))
        for _ in range(3):
            sim.set_torque(2.0)
            sim.step(env.substeps)
        assert np.array_equal(obs[i, :4], sim.take_readings()["position"][-1]), i
