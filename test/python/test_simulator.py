"""kane_sim.Simulator: the same trajectories as `simulate`, the same u' as the C++ equations,
and every hostile input refused with the driver's words."""
import io
import math
import os
import signal
import threading

import numpy as np
import pytest

import kane_sim
from conftest import config_path, run_tool


def simulate_csv(tmp_path, *args):
    out = tmp_path / "run.csv"
    run_tool("simulate", "--config", config_path(), "--csv", out, *args)
    return np.genfromtxt(out, delimiter=",", names=True)


def assert_identical(csv, result):
    assert list(csv.dtype.names) == list(result), "the same columns in the same order"
    for name in csv.dtype.names:
        np.testing.assert_array_equal(result[name], csv[name], err_msg=name)


@pytest.mark.parametrize("args, torque", [
    (["--torque", "0.5"], 0.5),
    (["--torque-sine", "3,0.7,0.2"], kane_sim.TorqueProfile.sine(3, 0.7, 0.2)),
    (["--torque-step", "0.5,0,2"], kane_sim.TorqueProfile.step(0.5, 0, 2)),
])
def test_run_is_simulates_csv_bit_for_bit(tmp_path, args, torque):
    csv = simulate_csv(tmp_path, "--duration", "2", "--output-rate", "100", *args)
    result = kane_sim.Simulator(config_path()).run(2.0, torque=torque, output_rate=100)
    assert_identical(csv, result)


def test_arrays_and_callables_give_the_constant_torques_trajectory(sim):
    steps = 1500
    constant = kane_sim.Simulator(config_path()).run(1.5, torque=0.8)
    array = kane_sim.Simulator(config_path()).run(1.5, torque=np.full(steps, 0.8))
    calls = []

    def law(t, state):
        calls.append(t)
        assert state.shape == (4,)
        return 0.8

    called = sim.run(1.5, torque=law)
    for r in (array, called):
        np.testing.assert_array_equal(r.q, constant.q)
    assert len(calls) == steps + 1 and calls[0] == 0.0


def test_a_pd_law_in_python_holds_the_crank():
    cfg = kane_sim.Config(config_path())
    cfg["damping.slider4_joint"] = 20.0  # so that slider 4 settles too
    sim = kane_sim.Simulator(cfg)
    r = sim.run(5.0, torque=lambda t, x: 400 * (1.0 - x[0]) - 30 * x[2], output_rate=100)
    # settled where the PD torque holds the crank: analyze's static equilibrium under that
    # torque (Newton on the same equations, 1e-10) is where the crank stands
    assert np.max(np.abs(r.u[-100:])) < 1e-4
    q1 = r.q[-1, 0]
    held = kane_sim.analyze(cfg, torque=400 * (1.0 - q1))["equilibrium"]["q1"]
    assert q1 == pytest.approx(held, abs=1e-5)
    assert 0.9 < q1 < 1.0  # a PD offset below the target


def test_rates_equal_the_simulators_u_dot():
    sim = kane_sim.Simulator(config_path())
    rng = np.random.default_rng(5)
    states = np.column_stack([rng.uniform(-3, 3, 50), rng.uniform(0.9, 1.5, 50),
                              rng.uniform(-5, 5, 50), rng.uniform(-2, 2, 50)])
    torques = rng.uniform(-10, 10, 50)
    rates = sim.rates(states, torques)
    assert rates.shape == (50, 4)
    for x, m, r in zip(states, torques, rates):
        sim.set_state(x)
        sim.set_torque(m)
        snap = sim.snapshot()
        assert r[0] == x[2] and r[1] == x[3]
        assert r[2] == snap["u1dot"] and r[3] == snap["u2dot"]
    one = sim.rates(states[0], torques[0])
    np.testing.assert_array_equal(one, rates[0])
    # the generic Kane assembly agrees to rounding
    generic = kane_sim.Config(config_path())
    generic["simulation.equations"] = "generic"
    np.testing.assert_allclose(kane_sim.Simulator(generic).rates(states, torques), rates,
                               rtol=1e-11, atol=1e-11)


def test_large_rates_are_split_over_threads_and_agree():
    sim = kane_sim.Simulator(config_path())
    states = np.tile([0.3, 1.2, 0.5, -0.1], (200000, 1))
    states[:, 0] += np.linspace(0, 1, len(states))
    rates = sim.rates(states, 0.5)
    np.testing.assert_array_equal(rates[123456], sim.rates(states[123456], 0.5))


@pytest.mark.parametrize("bad, match", [
    (lambda s: s.set_state([math.nan, 1, 0, 0]), "q1"),
    (lambda s: s.set_state([0.5, 1, math.inf, 0]), "u1"),
    (lambda s: s.set_state([1e308, 1, 0, 0]), "q1"),
    (lambda s: s.set_state([0.5, 1, 0]), "4 numbers"),
    (lambda s: s.set_torque(math.nan), "finite"),
    (lambda s: s.run(-1.0), "duration"),
    (lambda s: s.run(math.nan), "duration"),
    (lambda s: s.run(1e308), "duration"),
    (lambda s: s.run(0.0105), "output periods"),
    (lambda s: s.run(1.0, output_rate=0), "output_rate"),
    (lambda s: s.run(1.0, output_rate=300), "whole number of physics steps"),
    (lambda s: s.run(1.0, torque=math.inf), "finite"),
    (lambda s: s.run(1.0, torque=np.zeros(10)), "one value per physics step"),
    (lambda s: s.run(0.01, torque=np.array([0.0] * 9 + [math.nan])), r"torque\[9\] is nan"),
    (lambda s: s.run(0.01, torque=lambda t, x: math.nan), "returned nan"),
    (lambda s: s.rates(np.zeros((3, 3))), r"shape \(N, 4\)"),
    (lambda s: s.rates(np.array([[0, 1, math.nan, 0]])), r"states\[0, 2\] is nan"),
    (lambda s: s.rates(np.zeros((3, 4)), np.zeros(2)), "torque"),
    (lambda s: s.rates([[0.5, 1.2, 0, 0], [1e308] * 4]), r"states\[1\]: q1 = 1e\+308"),
    (lambda s: s.rates([0.5, 1.2, 0, 0], torque=1e308), r"torque is 1e\+308: .*torque_limit 50"),
    (lambda s: s.rates([[0.5, 1.2, 0, 0]] * 2, [1.0, -51.0]), r"torque\[1\] is -51"),
    (lambda s: s.step(-1), "n must be"),
    (lambda s: kane_sim.TorqueProfile.sine(math.nan, 1), "amplitude"),
    (lambda s: kane_sim.TorqueProfile.sine(1, 1e308), "sine frequency 1e\\+308 Hz cannot"),
    (lambda s: kane_sim.TorqueProfile.from_csv("/dev/zero"), "not a regular file"),
])
def test_hostile_inputs_raise_and_keep_the_state(sim, bad, match):
    sim.run(0.1, torque=1.0)
    before = sim.state.copy(), sim.time
    with pytest.raises(ValueError, match=match):
        bad(sim)
    np.testing.assert_array_equal(sim.state, before[0])
    assert sim.time == before[1]


def test_wrong_types_raise_type_errors(sim):
    with pytest.raises(TypeError, match="str"):
        sim.run(0.01, torque="fast")
    with pytest.raises(TypeError, match="expected a float"):
        sim.run(0.01, torque=lambda t, x: "fast")
    with pytest.raises(TypeError, match="output_rate"):
        sim.run(0.01, output_rate="fast")
    with pytest.raises(TypeError, match="must hold numbers"):
        sim.run(0.01, torque=["fast"] * 10)
    with pytest.raises(TypeError, match="must hold numbers"):
        sim.run(0.01, torque=np.array(["fast"] * 10, dtype=object))


def test_numbers_that_are_not_real_or_whole_are_type_errors(sim):
    before = sim.state.copy(), sim.time
    with pytest.raises(ValueError, match="more than 1e7 s of sim time"):
        sim.step(2 ** 63)
    for n in (2.7, 1 + 0j, "3", True):
        with pytest.raises(TypeError, match="step: n must be a whole number"):
            sim.step(n)
    with pytest.raises(TypeError, match="real number"):
        sim.set_torque(1 + 2j)
    with pytest.raises(TypeError, match="real number"):
        sim.run(1 + 0j)
    with pytest.raises(TypeError, match="expected a float"):
        sim.run(0.01, torque=lambda t, x: 1 + 2j)
    with pytest.raises(ValueError, match="beyond the range of a float"):
        sim.run(0.01, torque=lambda t, x: 10 ** 400)
    with pytest.raises(ValueError, match="beyond the range of a float"):
        sim.set_torque(10 ** 400)
    np.testing.assert_array_equal(sim.state, before[0])
    assert sim.time == before[1]
    assert sim.step(np.int64(2)) is not None  # NumPy's integers are whole numbers


def test_copies_are_refused_by_name(sim):
    import copy
    import pickle
    with pytest.raises(TypeError, match="Simulator cannot be copied"):
        copy.copy(sim)
    with pytest.raises(TypeError, match="Simulator cannot be deep-copied"):
        copy.deepcopy(sim)
    with pytest.raises(TypeError, match="Simulator cannot be pickled"):
        pickle.dumps(sim)


def test_a_missing_column_lists_the_columns(sim):
    r = sim.run(0.01)
    with pytest.raises(KeyError, match="'q3' is not a column of this result; the columns are: t, "
                                       "q1, q2"):
        r["q3"]


def test_a_held_clamp_is_one_event_not_one_per_resend(sim):
    sim.set_torque(80.0)  # beyond the 50 N m limit; step() re-sends it every 0.25 s
    sim.step(2000)
    clamps = [m for _, m in sim.events() if "clamped" in m]
    assert len(clamps) == 1, clamps


def test_every_public_method_has_a_docstring():
    for cls in (kane_sim.Simulator, kane_sim.Config, kane_sim.Result):
        for name in dir(cls):
            if name.startswith("_") and name not in ("__getitem__", "__setitem__"):
                continue
            member = getattr(cls, name)
            if name in ("__getitem__", "__setitem__") and cls is kane_sim.Result:
                continue
            if callable(member) or isinstance(member, property):
                assert (member.__doc__ or "").strip(), "%s.%s has no docstring" % (
                    cls.__name__, name)


def test_animate_names_a_wrong_type():
    with pytest.raises(TypeError, match="animate: result must be a kane_sim.Result"):
        kane_sim.animate([1, 2, 3])


def test_a_callables_exception_propagates_and_keeps_the_rows_until_then(sim):
    def law(t, x):
        if t >= 0.05:
            raise RuntimeError("controller crashed")
        return 0.0
    with pytest.raises(RuntimeError, match="controller crashed"):
        sim.run(1.0, torque=law)
    assert sim.last_result.t[-1] == pytest.approx(0.049, abs=1e-9)
    assert sim.time == pytest.approx(0.05, abs=1e-12)


def test_ctrl_c_stops_a_long_run_and_keeps_what_it_computed():
    sim = kane_sim.Simulator(config_path())
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        sim.run(36000.0, torque=0.5, output_rate=10)  # 10 h of sim time: minutes
    kept = sim.last_result
    assert 0 < kept.t[-1] < 36000.0 and len(kept.t) > 1
    assert np.all(np.isfinite(kept.q))
    assert sim.time >= kept.t[-1]


def test_ctrl_c_stops_long_steps_where_they_are():
    sim = kane_sim.Simulator(config_path())
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        sim.step(10 ** 10)  # months of sim time
    assert 0 < sim.time < 1e7 and np.all(np.isfinite(sim.state))


def test_ctrl_c_at_a_runs_last_signal_check_is_keyboardinterrupt_not_systemerror():
    # A run of 20 000 steps looks at Python's signals once, on its last step: a Ctrl-C seen there
    # ends the run as finished, and must still come out as KeyboardInterrupt (it once came out
    # as "SystemError: ... returned a result with an exception set", exit 1 in identify).
    import _thread
    import time
    sim = kane_sim.Simulator(config_path())
    in_run = [False]

    def handler(signum, frame):
        if in_run[0]:
            raise KeyboardInterrupt
    previous = signal.signal(signal.SIGINT, handler)
    done = threading.Event()

    def fire():
        while not done.is_set():
            _thread.interrupt_main(signal.SIGINT)
            time.sleep(0.002)
    interrupted = 0
    firing = threading.Thread(target=fire)
    firing.start()
    try:
        for _ in range(15):
            try:
                in_run[0] = True
                sim.run(20.0, torque=0.1, states_only=True)
            except KeyboardInterrupt:
                interrupted += 1
            finally:
                in_run[0] = False
    finally:
        done.set()
        firing.join()
        signal.signal(signal.SIGINT, previous)
    assert interrupted >= 10  # a signal is sent every 2 ms: nearly every run sees one
    assert np.all(np.isfinite(sim.state))


def test_steps_hold_the_torque_past_the_command_timeout(sim):
    sim.set_torque(2.0)
    sim.step(2000)  # 2 s, four command timeouts
    assert sim.snapshot()["applied_torque"] == 2.0
    assert sim.time == pytest.approx(2.0)


def test_runtime_parameters_by_config_name(sim):
    sim.run(0.5, torque=1.0)
    sim["mechanism.slider4_mass"] = 1.6
    assert sim["mechanism.slider4_mass"] == 1.6
    with pytest.raises(kane_sim.ConfigError, match="slider4_mass"):
        sim["mechanism.slider4_mass"] = -2
    assert sim["mechanism.slider4_mass"] == 1.6
    with pytest.raises(ValueError, match="fixed once a Simulator is built"):
        sim["simulation.physics_rate"] = 2000.0
    r = sim.run(0.5)
    assert np.all(np.isfinite(r.q))


def test_reset_keeps_time_and_set_state_restarts_the_ledger(sim):
    sim.run(0.5, torque=3.0)
    sim.reset()
    assert sim.time == pytest.approx(0.5)
    np.testing.assert_array_equal(sim.state, kane_sim.Simulator(config_path()).state)
    sim.set_state([0.2, 1.1, 0.0, 0.0])
    assert sim.snapshot()["motor_work"] == 0.0


def test_a_refused_step_raises_step_refused_with_the_drivers_reason():
    cfg = kane_sim.Config(config_path())
    cfg["command.torque_limit"] = 1e6
    sim = kane_sim.Simulator(cfg)
    with pytest.raises(kane_sim.StepRefused, match="rk4"):
        sim.run(5.0, torque=1e6)
    assert np.all(np.isfinite(sim.state))
    assert np.all(np.isfinite(sim.last_result.q))


def test_sensor_readings_come_back_with_the_run_and_are_the_simulates_bag_readings(tmp_path):
    """With config/sensors.yaml's sensors: the readings Python gets are those `simulate --bag`
    writes on /joint_states (same seed, same driver), none left behind in the driver."""
    import rosbag
    import yaml
    with open(config_path()) as f:
        tree = yaml.safe_load(f)
    with open(config_path("sensors.yaml")) as f:
        tree["sensors"].update(yaml.safe_load(f)["sensors"])
    config_file = tmp_path / "sensors.yaml"
    config_file.write_text(yaml.safe_dump(tree))
    sim = kane_sim.Simulator(tree)
    r = sim.run(1.0, torque=1.0, output_rate=100)
    s = r.sensors
    assert len(s["t"]) >= 95 and s["position"].shape == (len(s["t"]), 4)
    assert np.all(s["t"] >= s["sample_t"]) and np.all(np.diff(s["t"]) >= 0)
    truth = np.interp(s["sample_t"], r.t, r["q1"])
    assert 0 < np.max(np.abs(s["position"][:, 0] - truth)) < 0.05  # noisy, not wrong
    run_tool("simulate", "--config", config_file, "--duration", "1", "--torque", "1",
             "--bag", tmp_path / "run.bag")
    with rosbag.Bag(str(tmp_path / "run.bag")) as bag:
        bagged = [m for _, m, _ in bag.read_messages(topics=["/joint_states"])]
    np.testing.assert_array_equal(np.array([m.position for m in bagged]), s["position"])
    np.testing.assert_array_equal(np.array([m.velocity for m in bagged]), s["velocity"])
    epoch = bagged[0].header.stamp.to_sec() - s["t"][0]  # simulate stamps from a fixed epoch
    np.testing.assert_allclose([m.header.stamp.to_sec() - epoch for m in bagged], s["t"],
                               atol=1e-6)
    sim.step(100)
    assert len(sim.take_readings()["t"]) >= 9
    assert len(sim.take_readings()["t"]) == 0
    plain = kane_sim.Simulator(config_path()).run(0.1, torque=1.0)
    assert len(plain.sensors["t"]) == 0


def test_one_call_at_a_time():
    """A torque callable that calls its own simulator (or a thread that calls in during a run)
    is refused, and the run it interrupted keeps its rows."""
    sim = kane_sim.Simulator(config_path())

    def law(t, x):
        if t > 0.01:
            sim.set_state([0.1, 1.2, 0.0, 0.0])
        return 0.0
    with pytest.raises(RuntimeError, match="one call at a time"):
        sim.run(0.1, torque=law)
    assert sim.last_result.t[-1] == pytest.approx(0.01)
    sim.run(0.1)  # free again
    errors = []

    def other_thread():
        try:
            sim.snapshot()
        except RuntimeError as e:
            errors.append(str(e))
    started = threading.Event()

    def slow_law(t, x):
        if not started.is_set():
            started.set()
            worker = threading.Thread(target=other_thread)
            worker.start()
            worker.join()
        return 0.0
    sim.run(0.01, torque=slow_law)
    assert errors and "one call at a time" in errors[0]


def test_one_name_per_quantity_and_the_former_names_for_one_release(tmp_path):
    from kane_sim import columns, identify, plotting
    # Every column is named once; a scalar of /mechanism_state has its field's name.
    names = [row[0] for row in columns.TABLE]
    assert len(names) == len(set(names))
    for name, _, _, field, index in columns.TABLE:
        if field and index < 0 and name != "t":  # t: sim_time, the one short exception
            assert name == field, (name, field)
    assert all(name.startswith("power_") for _, name in columns.POWERS)
    # A sweep's row: each case's final value of an output column, or one of its own summaries.
    summaries = {"case", "status", "max_abs_q1", "max_abs_q2", "ledger_error", "steps",
                 "wall_time"}
    for name in kane_sim._core.sweep_csv_header([]).strip().split(","):
        assert name in names or name in summaries, name
    assert set(columns.RENAMED) == {"energy", "kinetic", "gravitational", "spring", "torque",
                                    "motor_power", "rail_slider3", "rail_slider4"}
    sim = kane_sim.Simulator(config_path())
    sim.set_torque(1.5)
    r = sim.run(0.6, output_rate=100)
    with pytest.warns(DeprecationWarning, match="'energy' is now 'total_energy'"):
        np.testing.assert_array_equal(r["energy"], r["total_energy"])
    with pytest.warns(DeprecationWarning, match="Result.applied_torque"):
        np.testing.assert_array_equal(r.torque, r.applied_torque)
    with pytest.warns(DeprecationWarning, match="Simulator.commanded_torque"):
        assert sim.torque == sim.commanded_torque == 1.5
    np.testing.assert_array_equal(r.q, np.column_stack([r["q1"], r["q2"]]))
    np.testing.assert_array_equal(r.u_dot, np.column_stack([r["u1dot"], r["u2dot"]]))
    # A CSV written before the renames reads under today's names (one warning naming them).
    old = tmp_path / "old.csv"
    header = [{v: k for k, v in columns.RENAMED.items()}.get(n, n) for n in r]
    old.write_text(",".join(header) + "\n" + "\n".join(
        ",".join(repr(float(r[n][i])) for n in r) for i in range(len(r.t))) + "\n")
    with pytest.warns(FutureWarning, match="an older CSV"):
        table = plotting.read_csv(str(old))
    np.testing.assert_array_equal(table["applied_torque"], r.applied_torque)
    assert "torque" not in table and "power_motor" in table
    with pytest.warns(FutureWarning):
        motion = identify.load_motion(str(old))
    np.testing.assert_array_equal(motion.torque, r.applied_torque)
    env = kane_sim.VectorEnv(2, config_path())
    assert env.observation_names == ("q1", "q2", "u1", "u2")


def test_states_only_runs_are_the_full_runs_states():
    # One truth: a fit's lean replays step exactly as run() does.
    cfg = kane_sim.Config(config_path())
    torque = np.sin(np.arange(2000) * 1e-3 * 3.0) * 2.0
    full = kane_sim.Simulator(cfg).run(2.0, torque=torque, output_rate=100)
    lean = kane_sim.Simulator(cfg).run(2.0, torque=torque, output_rate=100, states_only=True)
    assert list(lean) == ["t", "q1", "q2", "u1", "u2"]
    for name in lean:
        np.testing.assert_array_equal(lean[name], full[name], err_msg=name)
    with pytest.raises(TypeError, match="states_only must be True or False"):
        kane_sim.Simulator(cfg).run(0.1, states_only="yes")


def test_a_tables_header_is_checked_against_the_mode_through_every_door(tmp_path):
    """A table whose header names a setpoint plays only in a servo mode, one naming a torque
    only in effort mode: Simulator.run and sweep (on lanes and alone) refuse the other, the
    pickle a cluster's worker gets keeps the header, and a table without a header plays in
    either."""
    import pickle
    setpoints, torques, bare = (tmp_path / n for n in ("sp.csv", "tq.csv", "bare.csv"))
    setpoints.write_text("t,setpoint\n0,0.6\n")
    torques.write_text("t,torque\n0,2\n")
    bare.write_text("0,0.6\n")
    effort = kane_sim.load_config()
    servo = effort.with_values({"command.mode": "position"})
    read = {p: kane_sim.TorqueProfile.from_csv(str(p)) for p in (setpoints, torques, bare)}
    shipped = {p: pickle.loads(pickle.dumps(t)) for p, t in read.items()}
    for profiles in (read, shipped):
        with pytest.raises(ValueError, match="sp.csv:1: the header 't,setpoint' names a setpoint"):
            kane_sim.Simulator(effort).run(0.01, torque=profiles[setpoints])
        with pytest.raises(ValueError, match="tq.csv:1: the header 't,torque' names a torque"):
            kane_sim.Simulator(servo).run(0.01, torque=profiles[torques])
        kane_sim.Simulator(effort).run(0.01, torque=profiles[torques])
        kane_sim.Simulator(servo).run(0.01, torque=profiles[setpoints])
        for config in (effort, servo):
            kane_sim.Simulator(config).run(0.01, torque=profiles[bare])
        for simd in ("auto", "off"):
            swept = kane_sim.sweep(effort, cases={"mechanism.rod_mass": [1.0, 1.1]}, duration=0.01,
                                   torque=profiles[setpoints], simd=simd)
            assert list(swept["status"]) == ["config_refused"] * 2, swept["status"]
            assert "names a setpoint, not a torque" in swept["error"][0], swept["error"]
            swept = kane_sim.sweep(effort, cases={"mechanism.rod_mass": [1.0]}, duration=0.01,
                                   torque=profiles[torques], simd=simd)
            assert list(swept["status"]) == ["ok"], swept["error"]
