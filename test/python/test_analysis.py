"""kane_sim.analyze and kane_sim.sweep return what `analyze --json` and `simulate --sweep` write."""
import json
import math
import os
import signal
import threading
import time

import numpy as np
import pytest

import kane_sim
from conftest import config_path, run_tool


@pytest.mark.parametrize("torque", [0.0, 2.5])
def test_analyze_is_the_clis_json(torque):
    cli = json.loads(run_tool("analyze", "--config", config_path(), "--torque", torque,
                              "--json").stdout)
    assert kane_sim.analyze(config_path(), torque=torque) == cli


def test_analyze_refusals():
    with pytest.raises(ValueError, match="finite"):
        kane_sim.analyze(torque=math.nan)
    with pytest.raises(ValueError, match="analyze"):
        kane_sim.analyze(torque=1e6)  # beyond what gravity and the spring can hold


def test_sweep_is_simulates_sweep_csv(tmp_path):
    out = tmp_path / "sweep.csv"
    run_tool("simulate", "--config", config_path(), "--duration", "0.5", "--torque", "1",
             "--sweep", "mechanism.spring_stiffness=100:300:3", "--sweep",
             "initial_state.u1=0:1:2", "--csv", out)
    csv = np.genfromtxt(out, delimiter=",", names=True, dtype=None, encoding="utf-8")
    r = kane_sim.sweep(config_path(), grid={"mechanism.spring_stiffness": [100, 200, 300],
                                            "initial_state.u1": [0, 1]},
                       duration=0.5, torque=1.0)
    assert list(r["status"]) == list(csv["status"]) == ["ok"] * 6
    for name in ("mechanism.spring_stiffness", "initial_state.u1"):
        np.testing.assert_array_equal(r[name], csv[name.replace(".", "")] if name.replace(".", "") in csv.dtype.names else csv[name])
    for name in ("t", "q1", "q2", "u1", "u2", "max_abs_q1", "ledger_error", "motor_work"):
        np.testing.assert_array_equal(r[name], csv[name], err_msg=name)


def test_sweep_on_every_lane_set_is_the_same_rows():
    grid = {"mechanism.spring_stiffness": np.linspace(100, 400, 12),
            "damping.slider4_joint": [0.0, 0.5]}
    columns = ("t", "q1", "q2", "u1", "u2", "max_abs_q1", "max_abs_q2", "ledger_error",
               "motor_work", "dissipated_energy", "slider_crossings")
    alone = kane_sim.sweep(config_path(), grid=grid, duration=1.0, torque=2.0, simd="off")
    for simd in ("auto", "scalar"):
        lanes = kane_sim.sweep(config_path(), grid=grid, duration=1.0, torque=2.0, simd=simd)
        for name in columns:
            np.testing.assert_array_equal(lanes[name], alone[name], err_msg="%s %s" % (simd, name))
    fast = kane_sim.sweep(config_path(), grid=grid, duration=1.0, torque=2.0, vector_trig=True)
    np.testing.assert_allclose(fast["q1"], alone["q1"], rtol=0, atol=1e-9)
    for bad, error in (("avx9", ValueError), (8, TypeError)):
        with pytest.raises(error, match="simd"):
            kane_sim.sweep(config_path(), grid=grid, duration=0.1, simd=bad)


def test_sweep_refusals():
    with pytest.raises(ValueError, match="rod_mas"):
        kane_sim.sweep(grid={"mechanism.rod_mas": [1, 2]}, duration=0.1)
    r = kane_sim.sweep(cases={"mechanism.rod_mass": [1.0, -1.0]}, duration=0.1)
    assert list(r["status"]) == ["ok", "config_refused"]
    assert "rod_mass" in r["error"][1] and math.isnan(r["q1"][1])
    with pytest.raises(ValueError, match="one of them"):
        kane_sim.sweep(duration=0.1)
    with pytest.raises(ValueError, match="jobs"):
        kane_sim.sweep(cases={"mechanism.rod_mass": [1.0]}, duration=0.1, jobs=-1)
    # simulate's duration rule: [0, 1e7] s (1e16 used to return status ok at t = 0)
    for duration in (math.nan, -1.0, math.inf, 1e16, 1.1e7):
        with pytest.raises(ValueError, match=r"duration must be in \[0, 1e\+07\] s"):
            kane_sim.sweep(cases={"mechanism.rod_mass": [1.0]}, duration=duration)
    for key in ("", "nosuch", "a.b.c", "."):  # '' once crashed the interpreter
        with pytest.raises(ValueError, match="sweep key '%s'" % key.replace(".", r"\.")):
            kane_sim.sweep(cases={key: [1.0]}, duration=0.1)
        with pytest.raises(ValueError, match="sweep key"):
            kane_sim.sweep(grid={key: [1.0]}, duration=0.1)
    with pytest.raises(ValueError, match="at least one key to vary, the grid has none"):
        kane_sim.sweep(grid={}, duration=0.1)
    with pytest.raises(ValueError, match=r"jobs must be in \[0, \d+\]"):
        kane_sim.sweep(cases={"mechanism.rod_mass": [1.0]}, duration=0.1, jobs=10 ** 6)


def test_ctrl_c_stops_a_sweep_and_keeps_the_finished_cases():
    """Each case 2 h of sim time (seconds of wall time): Ctrl-C after 0.5 s ends the sweep
    within a second, the running cases unfinished, nothing new started."""
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    cases = {"initial_state.u1": [0.0] + [0.1] * 7}
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt) as raised:
        kane_sim.sweep(cases=cases, duration=7200.0, jobs=2)
    assert time.monotonic() - start < 3.0
    kept = raised.value.result
    assert len(kept["status"]) == 8
    assert set(kept["status"]) <= {"ok", "interrupted"} and "interrupted" in set(kept["status"])
    unfinished = kept["status"] == "interrupted"
    assert np.all(np.isnan(kept["q1"][unfinished]))
    assert np.all(np.isfinite(kept["q1"][~unfinished]))


@pytest.mark.parametrize("q1", [math.pi, 1.0, -2.5])
def test_analyze_held_at_an_angle_is_the_clis_json(q1):
    cli = json.loads(run_tool("analyze", "--config", config_path(), "--q1", q1, "--json").stdout)
    assert kane_sim.analyze(config_path(), q1=q1) == cli
    assert cli["stability"] == ("unstable" if abs(q1) > math.pi / 2 else "stable")


def test_pi_is_an_angle_for_analyze_as_for_design():
    a = json.loads(run_tool("analyze", "--config", config_path(), "--q1", "pi", "--json").stdout)
    assert a["equilibrium"]["q1"] == math.pi


def test_equilibria_near_the_holding_limit_and_with_a_crank_spring():
    limit = 4 * 9.81 * 0.25 * (1.0 + 0.5 + 0.8)  # 4 g L (m + M1 + M2) of the shipped config
    found = kane_sim.equilibria(config_path(), torque=0.999999 * limit)
    assert [e["stability"] for e in found] == ["stable", "unstable"]  # a fold: both found
    assert abs(found[0]["q1"] + found[1]["q1"] - math.pi) < 1e-9
    spring = kane_sim.Config(config_path()).with_values(
        {"mechanism.crank_spring_stiffness": 30.0})
    for torque in (0.0, 90.0, 100.0):  # beyond gravity's limit the spring still holds it
        found = kane_sim.equilibria(spring, torque=torque)
        assert any(e["stability"] == "stable" for e in found), (torque, found)
        held = kane_sim.analyze(spring, torque=torque)
        assert held["stability"] == "stable"
    # A weak spring spreads its equilibria over many turns: the stable one by the hanging crank
    # is still found; the whole list is refused by name, not searched for seconds.
    weak = kane_sim.Config(config_path()).with_values({"mechanism.crank_spring_stiffness": 0.01})
    assert abs(kane_sim.analyze(weak, torque=1.0)["equilibrium"]["q1"] - 0.0443) < 1e-3
    with pytest.raises(ValueError, match="more than a search covers"):
        kane_sim.equilibria(weak, torque=1.0)
    nothing = kane_sim.Config(config_path()).with_values({"mechanism.gravity": 0.0})
    with pytest.raises(ValueError, match="every crank angle is an equilibrium"):
        kane_sim.equilibria(nothing)


def test_equilibria_are_the_clis_and_hold():
    for torque in (0.0, 10.0):
        cli = json.loads(run_tool("analyze", "--config", config_path(), "--torque", torque,
                                  "--equilibria", "--json").stdout)
        py = kane_sim.equilibria(config_path(), torque=torque)
        assert py == cli and [e["stability"] for e in py] == ["stable", "unstable"]
        sim = kane_sim.Simulator(config_path())
        for e in py:  # at rest there under the torque, the mechanism stays (u' = 0)
            sim.set_state([e["q1"], e["q2"], 0.0, 0.0])
            sim.set_torque(torque)
            q1, q2, u1, u2 = sim.step(200)
            assert abs(q1 - e["q1"]) < 1e-8 and abs(q2 - e["q2"]) < 1e-8, (e, q1, q2)


def test_analyze_refuses_a_held_angle_that_is_not_one():
    for q1 in (math.nan, math.inf, 1e308):
        with pytest.raises(ValueError, match="q1 must be a finite angle"):
            kane_sim.analyze(config_path(), q1=q1)
    r = run_tool("analyze", "--config", config_path(), "--q1", "nan", check=False)
    assert r.returncode == 2 and "--q1 must be a finite number, got 'nan'" in r.stderr
    r = run_tool("analyze", "--config", config_path(), "--q1", "1e7", check=False)
    assert r.returncode == 2 and "--q1 must be an angle within 1e6 rad" in r.stderr
    r = run_tool("analyze", "--config", config_path(), "--equilibria", "extra", check=False)
    assert r.returncode == 2
    with pytest.raises(ValueError, match="give torque or q1"):
        kane_sim.analyze(config_path(), q1=1.0, torque=3.0)
    r = run_tool("analyze", "--config", config_path(), "--q1", "1", "--torque", "2", check=False)
    assert r.returncode == 2 and "--q1 holds the crank by its own moment" in r.stderr
