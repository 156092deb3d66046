"""kane_sim.Config: the one loader from Python, with its messages; hostile values refused by
name and changing nothing."""
import math

import numpy as np
import pytest
import yaml

import kane_sim
from conftest import config_path, run_tool


def test_file_dict_and_default_load_the_same_values():
    with open(config_path()) as f:
        tree = yaml.safe_load(f)
    from_file = kane_sim.Config(config_path())
    from_dict = kane_sim.Config(tree)
    default = kane_sim.Config()
    for name in kane_sim.Config.names():
        assert from_file[name] == from_dict[name] == default[name], name
    assert from_file["simulation.integrator"] == "rk4"
    assert from_file["simulation.publish_clock"] is False
    assert from_file["mechanism.rod_mass"] == 1.0
    assert len(kane_sim.Config.names()) > 50


def test_errors_carry_the_loaders_message(tmp_path):
    """The same words as `simulate` prints for the same file."""
    bad = tmp_path / "bad.yaml"
    with open(config_path()) as f:
        tree = yaml.safe_load(f)
    tree["mechanism"]["rod_mass"] = -1.0
    bad.write_text(yaml.safe_dump(tree))
    with pytest.raises(kane_sim.ConfigError) as python_error:
        kane_sim.Config(str(bad))
    cli = run_tool("simulate", "--config", bad, "--duration", "0.1", check=False)
    assert cli.returncode == 1
    assert str(python_error.value) in cli.stderr
    assert "mechanism.rod_mass" in str(python_error.value) and "-1" in str(python_error.value)
    with pytest.raises(kane_sim.ConfigError):  # from a dict alike
        kane_sim.Config(tree)
    assert issubclass(kane_sim.ConfigError, ValueError)


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf, 1e308, -1.0, 0.0, "heavy", ""])
def test_hostile_values_are_refused_by_name_and_change_nothing(value):
    cfg = kane_sim.Config()
    with pytest.raises(kane_sim.ConfigError) as e:
        cfg["mechanism.rod_mass"] = value
    # 1e308 kg passes the mass's own rule; the state it makes has a non-finite energy, which the
    # loader names (as simulate and the node do)
    assert "mechanism.rod_mass" in str(e.value) or "non-finite energy" in str(e.value)
    assert cfg["mechanism.rod_mass"] == 1.0


def test_names_typos_and_types():
    cfg = kane_sim.Config()
    with pytest.raises(kane_sim.ConfigError, match="mechanism.rod_mas"):
        cfg["mechanism.rod_mas"]
    with pytest.raises(kane_sim.ConfigError, match="rod_mass"):
        cfg["rod_mass"] = 1.0  # no section
    for bad in ([1.0], {"a": 1}, None, np.array([0.5, 0.6])):
        with pytest.raises(TypeError, match="config key 'friction.slider4_joint'"):
            cfg["friction.slider4_joint"] = bad
    cfg["friction.slider4_joint"] = np.array(0.5)  # a 0-d array is its number
    assert cfg["friction.slider4_joint"] == 0.5
    assert kane_sim.Config.role("friction.slider4_joint") == "dissipative"
    assert kane_sim.Config.role("friction.velocity_scale") == "load shape"
    assert "friction.crank_joint" in kane_sim.Config.names("dissipative")
    assert "mechanism.gravity" not in kane_sim.Config.names("dissipative")
    # One role, two laws: the loads' table tells a damper from friction.
    assert kane_sim.Config.law("friction.slider4_joint") == "coulomb"
    assert kane_sim.Config.law("damping.spring") == "viscous"
    assert kane_sim.Config.law("mechanism.crank_spring_stiffness") == "elastic"
    assert kane_sim.Config.law("mechanism.rod_mass") == ""
    assert kane_sim.Config.law("friction.velocity_scale") == ""
    for name in kane_sim.Config.names("dissipative"):
        assert kane_sim.Config.law(name) in ("viscous", "coulomb"), name
    with pytest.raises(kane_sim.ConfigError, match="damping.sprng"):
        kane_sim.Config.law("damping.sprng")
    with pytest.raises(kane_sim.ConfigError, match="integrator"):
        cfg["simulation.integrator"] = "euler"
    with pytest.raises(TypeError):
        kane_sim.Config(3.0)
    with pytest.raises(kane_sim.ConfigError):
        kane_sim.Config({})  # the required sections are missing
    with pytest.raises(kane_sim.ConfigError, match="file"):
        kane_sim.Config("/nonexistent/kane.yaml")


def test_set_values_go_through_cross_rules():
    cfg = kane_sim.Config()
    cfg["mechanism.rod_mass"] = np.float64(2.5)  # NumPy scalars too
    assert cfg["mechanism.rod_mass"] == 2.5
    cfg["simulation.integrator"] = "dopri5"
    assert cfg["simulation.integrator"] == "dopri5"
    with pytest.raises(kane_sim.ConfigError, match="publish_rate"):
        cfg["simulation.publish_rate"] = 300.0  # must divide physics_rate 1000 Hz
    other = cfg.with_values({"mechanism.spring_stiffness": 50.0, "initial_state.u1": 1.0})
    assert other["mechanism.spring_stiffness"] == 50.0 and cfg["mechanism.spring_stiffness"] == 200
    # the YAML it holds loads back to the same values (a file for simulate)
    again = kane_sim.Config(yaml.safe_load(other.yaml()))
    for name in kane_sim.Config.names():
        assert again[name] == other[name], name


def test_with_values_is_validated_as_a_whole():
    # rk4 cannot follow 1000 N of friction over v_s 0.01; dopri5 can: either key order works.
    values = {"friction.slider4_joint": 1000.0, "simulation.integrator": "dopri5"}
    for ordered in (values, dict(reversed(list(values.items())))):
        cfg = kane_sim.Config().with_values(ordered)
        assert cfg["friction.slider4_joint"] == 1000.0
        assert cfg["simulation.integrator"] == "dopri5"
    with pytest.raises(kane_sim.ConfigError, match="physics_rate"):
        kane_sim.Config().with_values({"friction.slider4_joint": 1000.0})
    with pytest.raises(kane_sim.ConfigError, match="rod_mas"):
        kane_sim.Config().with_values({"mechanism.rod_mas": 1.0})
    with pytest.raises(TypeError, match="friction.crank_joint"):
        kane_sim.Config().with_values({"friction.crank_joint": [1.0]})
    base = kane_sim.Config()
    assert base.with_values({})["mechanism.rod_mass"] == base["mechanism.rod_mass"]

