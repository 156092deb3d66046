"""Reaction forces and power flow as published (Simulator.snapshot, run's columns) against
SymPy's KanesMethod with auxiliary speeds (sympy_reactions.py, an independent derivation) and
the work-energy theorem."""
import numpy as np
import pytest
import yaml

import kane_sim
from conftest import config_path
from sympy_reactions import reaction_model

COLUMNS = {"O_x": "pin_o_x", "O_y": "pin_o_y", "A_x": "pin_a_x", "A_y": "pin_a_y",
           "B_x": "pin_b_x", "B_y": "pin_b_y", "N3": "rail_force_slider3", "N4": "rail_force_slider4"}
DAMPING = {"crank_joint": 0.3, "coupler_joint": 0.2, "slider3_joint": 1.5, "slider4_joint": 2.5}


@pytest.fixture(scope="module")
def damped():
    with open(config_path()) as f:
        tree = yaml.safe_load(f)
    tree["damping"] = dict(DAMPING)
    oracle = reaction_model(tree["mechanism"],
                            (tree["initial_state"]["q1"], tree["initial_state"]["q2"]), DAMPING)
    return tree, oracle


def test_reactions_match_sympy_kanes_method_with_auxiliary_speeds(damped):
    tree, oracle = damped
    rng = np.random.default_rng(3)
    checked = 0
    for _ in range(40):
        state = [rng.uniform(-6, 6), rng.uniform(0.8, 1.6), rng.uniform(-15, 15),
                 rng.uniform(-5, 5)]
        if abs(np.cos(state[0])) < 0.05:  # the toggle, where N3 grows as 1/cos q1
            continue
        torque = rng.uniform(-20, 20)
        sim = kane_sim.Simulator(tree)
        sim.set_state(state)
        sim.set_torque(torque)
        snap = sim.snapshot()
        expected = oracle(state, torque)
        # 1e-9 of the largest force: rounding in two 8x8 solves and SymPy's lambdified terms
        # (~1e-13 relative) leaves four orders of magnitude.
        scale = 1 + max(abs(v) for v in expected.values())
        for name, column in COLUMNS.items():
            assert snap[column] == pytest.approx(expected[name], abs=1e-9 * scale), \
                (name, state, torque)
        assert snap["reactions_determinate"]
        checked += 1
    assert checked >= 35


def test_the_toggle_point_is_flagged_not_infinite():
    sim = kane_sim.Simulator(config_path())
    sim.set_state([np.pi / 2, 1.2, 3.0, 0.0])
    snap = sim.snapshot()
    assert not snap["reactions_determinate"]
    assert all(np.isfinite(snap[c]) for c in COLUMNS.values())


def test_load_powers_sum_to_the_rate_of_kinetic_energy(damped):
    """Σ powers (published columns) = dT/dt, with dT/dt from the published kinetic energy by
    central differences at 10 kHz (truncation ~ h² T''' / 6 ~ 1e-6 W here; 1e-4 of the largest
    power leaves margin). A constant torque: a profile changes the torque in steps (held over each
    physics step), which a central difference straddles."""
    tree, _ = damped
    tree = dict(tree, simulation=dict(tree["simulation"], physics_rate=10000.0))
    r = kane_sim.Simulator(tree).run(1.0, torque=4.0)
    powers = sum(r.powers.values())
    kinetic_rate = np.gradient(r["kinetic_energy"], r.t)[1:-1]
    scale = max(np.max(np.abs(p)) for p in r.powers.values())
    np.testing.assert_allclose(powers[1:-1], kinetic_rate, atol=1e-4 * scale)
    np.testing.assert_allclose(sum(r.kinetic_per_body.values()), r["kinetic_energy"], rtol=1e-12,
                               atol=1e-12)
    # gravity's and the spring's powers are the rates of their potential energies, with sign -
    np.testing.assert_allclose(r["power_gravity"][1:-1],
                               -np.gradient(r["gravitational_energy"], r.t)[1:-1], atol=1e-4 * scale)
    np.testing.assert_allclose(r["power_spring"][1:-1], -np.gradient(r["spring_energy"], r.t)[1:-1],
                               atol=1e-4 * scale)
    for name in ("crank_damper", "coupler_damper", "slider3_damper", "slider4_damper"):
        assert np.all(r.powers[name] <= 0), name
