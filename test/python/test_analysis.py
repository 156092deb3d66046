"""kane_sim.analyze and kane_sim.sweep return what `analyze --json` and `simulate --sweep` write."""
import json
import math

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
    for duration in (math.nan, -1.0, math.inf):
        with pytest.raises(ValueError, match="duration"):
            kane_sim.sweep(cases={"mechanism.rod_mass": [1.0]}, duration=duration)
