"""kane_sim.BatchSimulator and kane_sim.VectorEnv: every mechanism of a batch is the single
Simulator of its config, bit for bit (SIMD lanes of every instruction set this CPU runs, and the
drivers), terminations included; hostile inputs refused by name, nothing moved."""
import threading

import numpy as np
import pytest
import yaml

import kane_sim
from conftest import config_path
from kane_sim import _core

N = 24
SUBSTEPS = 10
ACTIONS = 50


def lane_params(n=N):
    """Masses, a damper on every other mechanism and friction on every third (every variant of
    the equations), starts, and two
    mechanisms driven hard enough to end: crossed sliders, a refused step (1e6 N m allowed)."""
    rng = np.random.default_rng(7)
    limits = np.full(n, 50.0)
    limits[1] = 1e6
    return {"mechanism.rod_mass": rng.uniform(0.5, 2.0, n),
            "damping.slider4_joint": np.where(np.arange(n) % 2 == 0, 0.0, 0.4),
            "friction.crank_joint": np.where(np.arange(n) % 3 == 0, 0.3, 0.0),
            "initial_state.q1": np.concatenate([[0.5], rng.uniform(-1.0, 1.0, n - 1)]),
            "command.torque_limit": limits}


def action_sequence(n=N):
    rng = np.random.default_rng(8)
    a = rng.uniform(-30.0, 30.0, (ACTIONS, n))
    a[:, 0] = -50.0  # sliders cross (at 0.3 s from q1 0.5)
    a[:, 1] = 1e6    # the crank runs away: a refused step
    return a


def single_runs(batch, actions):
    """Each mechanism's Simulator, set_torque then SUBSTEPS single steps per action, stopped at
    its first refused step or crossing (what ends a batch's mechanism)."""
    out = []
    for i in range(len(batch)):
        sim = kane_sim.Simulator(batch.config(i))
        ended = False
        for a in actions[:, i]:
            if ended:
                break
            sim.set_torque(a)
            for _ in range(SUBSTEPS):
                try:
                    sim.step(1)
                except kane_sim.StepRefused:
                    ended = True
                    break
                if any("passed through" in m for _, m in sim.events()):
                    ended = True
                    break
        out.append((sim.time, sim.state, ended))
    return out


@pytest.mark.parametrize("simd", ["off", "auto", "scalar"])
def test_a_bad_simd_cap_is_named_whatever_simd_says(simd):
    """KANE_SIM_SIMD_MAX is read once per process: each case runs in its own. A value naming no
    instruction set is a ValueError naming it, even with simd="off"; "scalar" caps auto."""
    import os
    import subprocess
    import sys
    program = ("import kane_sim\n"
               "try:\n"
               "    b = kane_sim.BatchSimulator(2, %r, simd=%r)\n"
               "    print('path', b.path)\n"
               "except ValueError as e:\n"
               "    print('refused', e)\n" % (config_path(), simd))
    for cap, want in (("avx9", "refused environment variable KANE_SIM_SIMD_MAX 'avx9'"),
                      ("scalar", "path drivers" if simd == "off" else "path scalar lanes")):
        out = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True,
                             env=dict(os.environ, KANE_SIM_SIMD_MAX=cap), timeout=600)
        assert out.stdout.startswith(want), (cap, out.stdout, out.stderr)


@pytest.fixture(scope="module")
def reference():
    batch = kane_sim.BatchSimulator(N, config_path(), lane_params(), simd="off")
    return single_runs(batch, action_sequence())


@pytest.mark.parametrize("simd", ["off"] + [a for a in ("scalar", "sse2", "avx2", "avx512")
                                            if a == "scalar" or _core.lane_arch_available(a)])
def test_every_mechanism_is_its_single_run_bit_for_bit(reference, simd):
    batch = kane_sim.BatchSimulator(N, config_path(), lane_params(), simd=simd, threads=2)
    assert batch.path.startswith("drivers" if simd == "off" else simd + " lanes"), batch.path
    for a in action_sequence():
        batch.step(a, SUBSTEPS)
    assert batch.terminated[0] and "slider 4 passed through slider 3" in batch.reasons[0]
    assert batch.terminated[1] and "refused" in batch.reasons[1]
    for i, (t, state, ended) in enumerate(reference):
        assert batch.terminated[i] == ended, (i, batch.reasons[i])
        assert batch.times[i] == t, i
        assert np.array_equal(batch.states[i], state), (i, batch.states[i], state)
    # Reset: running again from the start, the clock running on.
    times = batch.times.copy()
    states = batch.reset(np.arange(N) < 2)
    assert not batch.terminated[:2].any() and batch.terminated.sum() == sum(
        e for _, _, e in reference[2:])
    assert states[0, 0] == lane_params()["initial_state.q1"][0]
    assert np.array_equal(batch.times, times)


def test_vector_trig_within_rounding_of_the_exact_lanes():
    params = {k: v for k, v in lane_params().items() if k != "command.torque_limit"}
    exact = kane_sim.BatchSimulator(N, config_path(), params)
    fast = kane_sim.BatchSimulator(N, config_path(), params, vector_trig=True)
    assert "vector" in fast.path
    actions = np.random.default_rng(3).uniform(-5.0, 5.0, (100, N))
    for a in actions:
        exact.step(a, 10)
        fast.step(a, 10)
    # 1 s of moderate motion: xsimd's sin/cos round within an ulp or two of libm's; measured
    # 1e-13 here (doc/guide/batches.md), bounded at 1e-10 for other CPUs' orders.
    assert np.max(np.abs(exact.states - fast.states)) < 1e-10


@pytest.mark.parametrize("mode", ["velocity", "position"])
def test_servo_modes_and_sensors_on_the_drivers(tmp_path, mode):
    cfg = yaml.safe_load(open(config_path()))
    cfg["command"]["mode"] = mode
    cfg["sensors"] = yaml.safe_load(open(config_path("sensors.yaml")))["sensors"]
    path = tmp_path / "servo.yaml"
    path.write_text(yaml.safe_dump(cfg))
    batch = kane_sim.BatchSimulator(4, str(path))
    assert batch.path.startswith("drivers (lane 0: command.mode %s" % mode)
    batch.reset(seed=11)
    setpoints = np.array([0.5, 1.0, -0.5, 2.0])
    for _ in range(30):
        batch.step(setpoints, 10)
    positions, velocities = batch.readings()
    for i in range(4):
        sim = kane_sim.Simulator(kane_sim.Config(str(path)).with_values({"sensors.seed": 11 + i}))
        sim.set_torque(setpoints[i])
        for _ in range(30):
            sim.step(10)
        assert np.array_equal(batch.states[i], sim.state)
        last = sim.take_readings()
        assert np.array_equal(positions[i], last["position"][-1])
        assert np.array_equal(velocities[i], last["velocity"][-1])
    with pytest.raises(ValueError, match=r"actions\[1\]: servo_setpoint .* rad"):
        batch.step(np.array([0.0, 1e7 if mode == "position" else 1e4, 0.0, 0.0]))


def test_hostile_inputs_are_refused_by_name_and_move_nothing():
    batch = kane_sim.BatchSimulator(3, config_path())
    before = batch.states.copy()
    for actions, steps, words in (([0.0, np.nan, 0.0], 1, r"actions\[1\] = nan is not finite"),
                                  ([0.0, 0.0, np.inf], 1, r"actions\[2\] = inf"),
                                  ([0.0, 0.0], 1, r"one value per mechanism \(3\), got shape "
                                                  r"\(2,\)"),
                                  ([0.0, 0.0, 0.0], 0, "steps must be"),
                                  ([0.0, 0.0, 0.0], 1.5, "steps must be"),
                                  ([0.0, 0.0, 0.0], True, "steps must be")):
        with pytest.raises(ValueError, match=words):
            batch.step(np.array(actions), steps)
    with pytest.raises(ValueError, match="got a scalar"):
        batch.step(1.0)
    for actions in (np.array([1j, 0, 0]), np.array([True, False, True]), np.array(["1", "2", "3"])):
        with pytest.raises(TypeError, match="actions must be real numbers"):
            batch.step(actions)
    import copy
    import pickle
    for attempt in (lambda: copy.copy(batch), lambda: copy.deepcopy(batch),
                    lambda: pickle.dumps(batch)):
        with pytest.raises(TypeError, match="BatchSimulator cannot be"):
            attempt()
    with pytest.raises(ValueError, match="sensors are off"):
        batch.readings()
    with pytest.raises(ValueError, match=r"seed must be a whole number in \[0, 2147483645\]"):
        batch.reset(seed=2 ** 31 - 1)
    assert np.array_equal(batch.states, before) and np.all(batch.times == 0.0)
    for kwargs, words in (({"n": 0}, "n must be"), ({"n": True}, "n must be"),
                          ({"n": 2.5}, "n must be"), ({"n": 2, "simd": "avx9"}, "avx9"),
                          ({"n": 2, "threads": 0}, "threads"),
                          ({"n": 2, "params": {"mechanism.rod_mass": [1.0, 2.0, 3.0]}},
                           r"one value or 2"),
                          ({"n": 2, "params": {"mechanism.rod_mass": [1.0, -1.0]}},
                           "mechanism 1: .*rod_mass"),
                          ({"n": 2, "params": {"mechanism.rod_mas": 1.0}}, "rod_mas")):
        with pytest.raises((ValueError, TypeError)):
            try:
                kane_sim.BatchSimulator(**kwargs)
            except (ValueError, TypeError) as e:
                assert __import__("re").search(words, str(e)), (kwargs, e)
                raise
    with pytest.raises(TypeError, match="mask must be booleans"):
        batch.reset(np.array([1, 0, 1]))
    with pytest.raises(ValueError, match="one bool per mechanism"):
        batch.reset(np.array([True]))
    with pytest.raises(ValueError, match="seed"):
        batch.reset(seed=-1)


def test_a_held_torque_outlasts_the_command_timeout_as_a_single_run(tmp_path):
    # Simulator.step(n) re-sends its command within command.timeout: so does every mechanism,
    # on lanes and on drivers, whatever its physics rate (mechanisms 1, 3 at 500 Hz: drivers).
    params = {"initial_state.q1": [0.3, 0.4, 0.5, 0.6]}
    for rates, path in (([1000.0] * 4, "lanes"), ([1000.0, 500.0, 1000.0, 500.0], "drivers")):
        batch = kane_sim.BatchSimulator(4, config_path(),
                                        dict(params, **{"simulation.physics_rate": rates}))
        assert path in batch.path
        batch.step(np.full(4, 3.0), 1500)  # 1.5 s or 3 s, beyond the 0.5 s timeout
        for i in range(4):
            sim = kane_sim.Simulator(batch.config(i))
            sim.set_torque(3.0)
            sim.step(1500)
            assert np.array_equal(batch.states[i], sim.state) and batch.times[i] == sim.time


def test_modes_per_mechanism_and_their_own_noise(tmp_path):
    cfg = yaml.safe_load(open(config_path()))
    cfg["sensors"] = yaml.safe_load(open(config_path("sensors.yaml")))["sensors"]
    path = tmp_path / "sensors.yaml"
    path.write_text(yaml.safe_dump(cfg))
    modes = ["effort", "velocity", "position", "effort"]
    batch = kane_sim.BatchSimulator(4, str(path), {"command.mode": modes,
                                                   "contact.enabled": [True, False, True, False]})
    assert [batch.config(i)["sensors.seed"] for i in range(4)] == [1, 2, 3, 4]
    actions = np.array([2.0, 1.0, 0.5, 2.0])
    for _ in range(20):
        batch.step(actions, 10)
    positions, _ = batch.readings()
    # Mechanisms 0 and 3 are the same but for their noise: their readings differ, their states
    # do not.
    assert np.array_equal(batch.states[0], batch.states[3])
    assert not np.array_equal(positions[0], positions[3])
    for i in range(4):
        sim = kane_sim.Simulator(batch.config(i))
        assert sim["command.mode"] == modes[i]
        sim.set_torque(actions[i])
        for _ in range(20):
            sim.step(10)
        assert np.array_equal(batch.states[i], sim.state), i
    with pytest.raises(TypeError, match="params"):
        kane_sim.BatchSimulator(2, config_path(), {"mechanism.rod_mass": [1j, 1.0]})


def _interrupted(setup, call, after, then="()"):
    """In a fresh Python: `setup`, then `call` with Ctrl-C (SIGINT) sent `after` s into it.
    Returns the seconds from the call's start to its KeyboardInterrupt and the tuple `then`
    evaluated there (the test fails if the call ends without one)."""
    import subprocess
    import sys
    script = (
        "import signal, time, threading, os, numpy as np, kane_sim\n" + setup + "\n"
        "threading.Timer(%r, lambda: os.kill(os.getpid(), signal.SIGINT)).start()\n" % after +
        "t = time.monotonic()\n"
        "try:\n"
        "    " + call + "\n"
        "    print('finished after', time.monotonic() - t)\n"
        "except KeyboardInterrupt:\n"
        "    print(repr((time.monotonic() - t, " + then + ")))\n")
    r = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0 and r.stdout.startswith("("), r.stdout + r.stderr
    return eval(r.stdout)


@pytest.mark.parametrize("simd", ["auto", "off"])
def test_ctrl_c_stops_a_long_step_where_it_is(simd):
    seconds, (first, last) = _interrupted(
        "b = kane_sim.BatchSimulator(64, params={'command.timeout': 0.0}, simd='%s')" % simd,
        "b.step(np.full(64, 0.1), 10_000_000)", 1.0, "(b.times.min(), b.times.max())")
    # Each lane ends where it is: some ran (blocks, drivers run one after another), none all
    # 10 000 s of the 1e7 steps.
    assert seconds < 5.0 and first < 10000.0 and last > 0, (seconds, first, last)


def test_ctrl_c_stops_building_many_mechanisms():
    # 10^6 mechanisms with their own numbers take ~9 s to build (their start-up checks): Ctrl-C
    # ends the build within its 20 ms watch, not when it ends. Here 4 x 10^5 on one thread
    # (8.8 s to build, measured), Ctrl-C 0.5 s in. The machine's pace is measured first, on a
    # tenth of them: the build must stop before a quarter of the whole would have been built
    # (measured 0.5-0.6 s against a bound of ~2.7 s; on a box busy with two other test suites,
    # 2.9 s, as its pace was slower too).
    seconds, tenth = _interrupted(
        "masses = np.random.default_rng(0).uniform(0.8, 1.2, 400_000)\n"
        "start = time.monotonic()\n"
        "kane_sim.BatchSimulator(40_000, params={'mechanism.rod_mass': masses[:40_000]}, "
        "threads=1)\n"
        "tenth = time.monotonic() - start",
        "kane_sim.BatchSimulator(400_000, params={'mechanism.rod_mass': masses}, threads=1)",
        0.5, "tenth")
    assert seconds < 0.5 + 0.25 * 10 * tenth, (seconds, tenth)


@pytest.mark.parametrize("simd", ["auto", "off"])
def test_a_refused_step_is_told_in_the_single_runs_words(simd):
    # The lanes know only that a check refused the step; its reason is the single run's own.
    params = {"command.torque_limit": 1e308}
    batch = kane_sim.BatchSimulator(3, config_path(), params, simd=simd)
    batch.step(np.array([1e308, 1e5, 0.0]))
    single = kane_sim.Simulator(batch.config(0))
    single.set_torque(1e308)
    with pytest.raises(kane_sim.StepRefused) as refused:
        single.step(1)
    assert batch.terminated[0] and not batch.terminated[2]
    assert batch.reasons[0] == "t = 0 s: " + str(refused.value), batch.reasons[0]


def test_a_forked_child_steps_and_drops_a_two_thread_batch():
    # Python's multiprocessing forks: the child has none of the pool's helper threads. It steps
    # the inherited batch on its own thread (the parent's numbers) and drops it; joining the
    # helpers there hung the child or aborted it.
    import os
    import time
    batch = kane_sim.BatchSimulator(64, config_path(), threads=2)
    batch.step(np.full(64, 0.5))
    expected = kane_sim.BatchSimulator(64, config_path(), threads=1)
    expected.step(np.full(64, 0.5))
    expected.step(np.full(64, -0.5), 10)
    pid = os.fork()
    if pid == 0:  # the child: no pytest from here on, only an exit status
        code = 1
        try:
            batch.step(np.full(64, -0.5), 10)
            code = 0 if np.array_equal(batch.states, expected.states) else 2
            del batch
            __import__("gc").collect()
        finally:
            os._exit(code)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        done, status = os.waitpid(pid, os.WNOHANG)
        if done:
            break
        time.sleep(0.05)
    else:
        os.kill(pid, 9)
        os.waitpid(pid, 0)
        pytest.fail("the forked child hung")
    assert os.WIFEXITED(status) and os.WEXITSTATUS(status) == 0, status
    batch.step(np.full(64, -0.5), 10)  # the parent's batch and its helper still work
    assert np.array_equal(batch.states, expected.states)


def test_one_call_at_a_time():
    batch = kane_sim.BatchSimulator(4096, config_path())
    errors = []

    def hammer():
        for _ in range(50):
            try:
                batch.step(np.zeros(4096), 50)
            except RuntimeError as e:
                errors.append(str(e))
    threads = [threading.Thread(target=hammer) for _ in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors and "one call at a time" in errors[0]
    assert not batch.terminated.any()


def test_vector_env_shapes_truncation_and_next_step_autoreset():
    seen = []

    def reward(obs, actions):
        seen.append(obs.shape)
        return -np.abs(obs[:, 0])
    env = kane_sim.VectorEnv(5, config_path(), reward=reward, substeps=10, max_episode_steps=3)
    obs, info = env.reset(seed=0)
    assert obs.shape == (5, 4) and info == {} and env.num_envs == 5
    assert np.all(env.action_high == 50.0)
    start = obs.copy()
    for k in range(3):
        obs, r, term, trunc, info = env.step(np.full(5, 1.0))
        assert obs.shape == (5, 4) and r.shape == term.shape == trunc.shape == (5,)
        assert not term.any()
        assert trunc.all() == (k == 2)
        assert np.array_equal(r, -np.abs(obs[:, 0]))
    # Next-step autoreset: the step after truncation returns the first observation, reward 0.
    obs, r, term, trunc, info = env.step(np.full(5, 1.0))
    assert np.array_equal(obs, start) and not r.any() and not (term | trunc).any()
    obs, r, term, trunc, _ = env.step(np.full(5, 1.0))
    assert not np.array_equal(obs, start) and seen[-1] == (5, 4)
    with pytest.raises(ValueError, match=r"shape \(5,\)"):
        env.step(np.zeros(4))
    for reward in (lambda o, a: 0.0, lambda o, a: np.full(2, np.nan), lambda o, a: np.ones(2) * 1j):
        bad = kane_sim.VectorEnv(2, config_path(), reward=reward)
        with pytest.raises(RuntimeError, match="reset"):
            bad.step(np.zeros(2))
        bad.reset()
        with pytest.raises(ValueError, match="reward"):
            bad.step(np.zeros(2))
    with pytest.raises(ValueError, match="options takes reset_mask, states and params, got maks"):
        env.reset(options={"maks": [True] * 5})
    with pytest.raises(ValueError, match=r"actions\[1\] = nan"):
        env.step(np.array([0.0, np.nan, 0.0, 0.0, 0.0]))


def test_vector_env_default_reward_is_the_crank_speed_with_sensors_too(tmp_path):
    cfg = yaml.safe_load(open(config_path()))
    cfg["sensors"] = yaml.safe_load(open(config_path("sensors.yaml")))["sensors"]
    path = tmp_path / "sensors.yaml"
    path.write_text(yaml.safe_dump(cfg))
    env = kane_sim.VectorEnv(3, str(path), substeps=10)
    obs, _ = env.reset(seed=3)
    assert obs.shape == (3, 8)
    for _ in range(5):
        obs, reward, *_ = env.step(np.array([1.0, 100.0, -100.0]))
    # u1 read by the crank's sensor minus 1e-3 (torque delivered: clamped to 50 N m)^2.
    np.testing.assert_array_equal(reward, obs[:, 4] - 1e-3 * np.array([1.0, 2500.0, 2500.0]))
    servo = kane_sim.VectorEnv(2, config_path(), {"command.mode": "velocity"})
    assert np.all(servo.action_high == 500.0)


def test_vector_env_terminates_a_crossing_and_restarts_it():
    env = kane_sim.VectorEnv(2, config_path(), substeps=10, max_episode_steps=10_000)
    obs0, _ = env.reset()
    ended = None
    for k in range(2000):
        obs, r, term, trunc, info = env.step(np.array([50.0, 0.0]))
        if term[0]:
            ended = k
            assert "passed through" in info["reasons"][0] and not term[1]
            break
    assert ended is not None
    obs, r, term, trunc, info = env.step(np.array([50.0, 0.0]))
    assert np.array_equal(obs[0], obs0[0]) and r[0] == 0.0 and not term[0]


def test_a_refused_step_is_named_in_the_single_runs_words_on_every_path():
    # 1e5 N m with a limit that lets it through: rk4 at 1 kHz cannot follow the crank. The lanes
    # know only that a check refused; they say what the single run's step says.
    cfg = kane_sim.Config(config_path()).with_values({"command.torque_limit": 1e5})
    words = "the crank would turn more than 1 rad in one rk4 step, which rk4 cannot resolve"
    for simd in ("auto", "off"):
        batch = kane_sim.BatchSimulator(4, cfg, simd=simd)
        batch.step(np.full(4, 1e5), 10)
        assert all(words in r for r in batch.reasons), (simd, batch.reasons)
    single = kane_sim.Simulator(cfg)
    with pytest.raises(Exception, match=words):
        for _ in range(10):
            single.set_torque(1e5)
            single.step(1)


@pytest.mark.parametrize("simd", ["off"] + [a for a in ("scalar", "sse2", "avx2", "avx512")
                                            if a == "scalar" or _core.lane_arch_available(a)])
def test_set_params_makes_each_mechanism_its_new_configs_single_run(reference, simd):
    """Parameters changed after the batch is built (between episodes): each mechanism changed is
    the single run of its new config from time 0, bit for bit, whichever variant of the
    equations it moves to (friction and dampers switched on); the others keep their motion."""
    batch = kane_sim.BatchSimulator(N, config_path(), simd=simd, threads=2)
    rng = np.random.default_rng(5)
    for _ in range(5):
        batch.step(rng.uniform(-10.0, 10.0, N), SUBSTEPS)
    kept = np.arange(N) >= N - 4  # left alone: their motion goes on
    states, times = batch.states.copy(), batch.times.copy()
    params = lane_params()
    physics = {k: v for k, v in params.items() if k != "command.torque_limit"}
    batch.set_params(physics, ~kept)  # numbers: the loader's rules in C++
    batch.set_params({"command.torque_limit": params["command.torque_limit"]}, ~kept)  # loader
    assert np.array_equal(batch.states[kept], states[kept])
    assert np.array_equal(batch.times[kept], times[kept])
    assert (batch.times[~kept] == 0).all()
    np.testing.assert_array_equal(batch.values("mechanism.rod_mass")[~kept],
                                  params["mechanism.rod_mass"][~kept])
    assert batch.config(3)["friction.crank_joint"] == 0.3
    assert batch.config(1)["command.torque_limit"] == 1e6
    for a in action_sequence():
        batch.step(np.where(kept, 0.0, a), SUBSTEPS)
    for i, (t, state, ended) in enumerate(reference):
        if kept[i]:
            continue
        assert batch.terminated[i] == ended, (i, batch.reasons[i])
        assert batch.times[i] == t, i
        assert np.array_equal(batch.states[i], state), (i, batch.states[i], state)


def test_set_params_refuses_by_name_and_changes_nothing():
    batch = kane_sim.BatchSimulator(4, config_path())
    batch.step(np.ones(4), 20)
    before, times = batch.states.copy(), batch.times.copy()
    masses = batch.values("mechanism.rod_mass").copy()
    one = np.arange(4) == 2
    for params, mask, error, words in (
            ({"mechanism.rod_mass": np.nan}, one, _core.ConfigError,
             r"mechanism 2: config key 'mechanism.rod_mass' must be finite"),
            ({"mechanism.rod_mass": [1.0, 1.0, -np.inf, 1.0]}, None, _core.ConfigError,
             r"mechanism 2: .*rod_mass"),
            ({"mechanism.rod_mass": -1.0}, one, _core.ConfigError, r"mechanism 2: .*> 0"),
            ({"mechanism.rod_mass": 1e308}, one, _core.ConfigError, r"mechanism 2: "),
            ({"mechanism.rod_mas": 1.0}, one, _core.ConfigError, r"set_params: .*rod_mas"),
            ({"mechanism.rod_mass": "heavy"}, one, _core.ConfigError, r"mechanism 2: .*rod_mass"),
            ({"mechanism.rod_mass": True}, one, _core.ConfigError, r"mechanism 2: .*rod_mass"),
            ({"mechanism.rod_mass": [1.0, 2.0]}, one, ValueError, r"one value or 4"),
            ({"mechanism.rod_mass": 1j}, one, TypeError, r"numbers, strings or bools"),
            ({}, one, TypeError, r"non-empty dict"),
            ({"mechanism.rod_mass": 1.0}, [True, False], ValueError, r"one bool per mechanism"),
            ({"command.mode": "velocity"}, one, ValueError,
             r"mechanism 2: command.mode velocity would take it off the batch's \w+ lanes")):
        with pytest.raises(error, match=words):
            batch.set_params(params, mask)
        assert np.array_equal(batch.states, before) and np.array_equal(batch.times, times)
        np.testing.assert_array_equal(batch.values("mechanism.rod_mass"), masses)
    # Nothing chosen: nothing changes.
    batch.set_params({"mechanism.rod_mass": 2.0}, np.zeros(4, dtype=bool))
    assert np.array_equal(batch.states, before)


def test_set_params_keeps_each_mechanisms_seed_and_config_reads_the_batch(tmp_path):
    """config(i) is read back from the batch: after reset(seed=) and a set_params through the
    loader, each mechanism keeps its own noise and is the single run of config(i), readings
    too; a sensors.seed given by set_params is the one config(i) and values() say."""
    cfg = yaml.safe_load(open(config_path()))
    cfg["sensors"] = yaml.safe_load(open(config_path("sensors.yaml")))["sensors"]
    path = tmp_path / "sensors.yaml"
    path.write_text(yaml.safe_dump(cfg))
    batch = kane_sim.BatchSimulator(3, str(path))
    batch.reset(seed=100)
    batch.set_params({"command.timeout": 0.4, "mechanism.rod_mass": [0.9, 1.0, 1.1]})
    assert [batch.config(i)["sensors.seed"] for i in range(3)] == [100, 101, 102]
    np.testing.assert_array_equal(batch.values("sensors.seed"), [100, 101, 102])
    for _ in range(20):
        batch.step(np.full(3, 1.0), 10)
    positions, _ = batch.readings()
    for i in range(3):
        sim = kane_sim.Simulator(batch.config(i))
        assert sim.config["command.timeout"] == 0.4
        for _ in range(20):
            sim.set_torque(1.0)
            sim.step(10)
        assert np.array_equal(batch.states[i], sim.state), i
        assert np.array_equal(positions[i], sim.take_readings()["position"][-1]), i
    batch.set_params({"sensors.seed": 7})
    assert [batch.config(i)["sensors.seed"] for i in range(3)] == [7, 7, 7]
    np.testing.assert_array_equal(batch.values("sensors.seed", np.array([True, False, True])),
                                  [7, 7])


def test_set_params_from_given_states_judged_by_the_new_params():
    batch = kane_sim.BatchSimulator(2, config_path())
    batch.step(np.ones(2), 10)
    before, times = batch.states.copy(), batch.times.copy()
    start = np.array([[0.3, 0.0, 0.5, 0.0], [np.nan, 0.0, 0.0, 0.0]])
    with pytest.raises(ValueError, match=r"mechanism 1: q1 = nan is not finite; nothing changed"):
        batch.set_params({"mechanism.rod_mass": 2.0}, None, start)
    assert np.array_equal(batch.states, before) and np.array_equal(batch.times, times)
    assert (batch.values("mechanism.rod_mass") == 1.0).all()
    states = batch.set_params({"mechanism.rod_mass": 2.0}, np.array([True, False]), start)
    assert states[0].tolist() == [0.3, 0.0, 0.5, 0.0] and batch.times[0] == 0.0
    assert np.array_equal(states[1], before[1])


def test_ctrl_c_stops_a_long_set_params_changing_nothing():
    seconds, (changed, times) = _interrupted(
        "b = kane_sim.BatchSimulator(200_000, threads=1); b.step(np.zeros(200_000), 1)",
        "b.set_params({'mechanism.rod_mass': 1.5})", 0.5,
        "((b.values('mechanism.rod_mass') != 1.0).sum(), b.times.min())")
    assert seconds < 2.0, seconds
    assert changed == 0 and times > 0  # nothing changed, nothing restarted
