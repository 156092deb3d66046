"""Controllers from the twin: kane_sim.control.lqr and `design lqr` give the same law, its Riccati
solution is SciPy's (an independent solver: solve_continuous_are, Schur method) on the same A
and B, and what the design refuses it refuses in words, with exit 3 (no design) or 2 (usage)."""
import math
import subprocess

import numpy as np
import pytest
import scipy.linalg
import yaml

import kane_sim.control
from conftest import config_path, run_tool, tool

CASES = [  # (config changes, q1)
    ({}, 0.0),
    ({}, math.pi),
    ({}, 1.0),
    ({"damping.crank_joint": 0.3, "damping.slider4_joint": 2.0}, math.pi),
    ({"friction.crank_joint": 0.2, "friction.slider4_joint": 0.5}, -2.5),
    ({"mechanism.crank_spring_stiffness": 30.0, "mechanism.crank_spring_rest_angle": 0.5}, 1.0),
]


def config_with(changes):
    cfg = kane_sim.Config(config_path())
    return cfg.with_values(changes) if changes else cfg


@pytest.mark.parametrize("changes,q1", CASES)
def test_riccati_solution_is_scipys(changes, q1):
    rng = np.random.default_rng(abs(hash((q1, len(changes)))) % 2**32)
    for Q, R in [(None, None), (rng.uniform(0.1, 100, 4), float(rng.uniform(1e-4, 1)))]:
        g = kane_sim.control.lqr(config_with(changes), q1=q1, Q=Q, R=R)
        # SciPy on the states the torque moves (all 4 but at q1 = 0 and pi, where slider 4 is
        # out of the crank's reach).
        T = g.controllable_basis
        assert T.shape[1] == (2 if math.sin(q1) ** 2 < 1e-20 else 4), T.shape
        P1 = scipy.linalg.solve_continuous_are(T.T @ g.A @ T, T.T @ g.B, T.T @ g.Q @ T,
                                               np.array([[g.R]]))
        P = T @ P1 @ T.T
        assert np.allclose(g.P, P, rtol=1e-8, atol=1e-8 * np.abs(P).max()), (g.P, P)
        K = (g.B.T @ P) / g.R
        assert np.allclose(g.K, K, rtol=1e-8, atol=1e-8 * np.abs(K).max())
        closed = np.linalg.eigvals(g.A - g.B @ g.K)
        assert np.allclose(np.sort_complex(closed), np.sort_complex(g.closed_loop_eigenvalues),
                           rtol=1e-8, atol=1e-9)
        assert closed.real.max() < 1e-9 * np.abs(closed).max()  # slider 4's mode may stay
        assert g.riccati_residual < 1e-10
        if T.shape[1] == 4:  # then SciPy's on the whole A, B too
            P = scipy.linalg.solve_continuous_are(g.A, g.B, g.Q, np.array([[g.R]]))
            assert np.allclose(g.P, P, rtol=1e-8, atol=1e-8 * np.abs(P).max())


def test_cli_and_python_write_the_same_law(tmp_path):
    out = tmp_path / "upright.yaml"
    run_tool("design", "lqr", "--config", config_path(), "--q1", "pi", "--Q", "10,1000,1,10",
             "--R", "0.01", "--out", out)
    g = kane_sim.control.lqr(config_path(), q1=math.pi, Q=[10, 1000, 1, 10], R=0.01)
    law = yaml.safe_load(out.read_text())["state_feedback"]
    assert np.array_equal(np.array(law["K"], dtype=float), g.K[0])
    assert np.array_equal(np.array(law["state"], dtype=float), g.state)
    assert float(law["torque"]) == g.torque and law["periodic"] is True
    assert yaml.safe_load(g.yaml)["state_feedback"] == law
    x = g.state + np.array([0.05, -0.01, 0.2, 0.0])
    assert g.command(x) == pytest.approx(g.torque - g.K[0] @ (x - g.state), rel=1e-15)
    # A crank a turn away is the same state (no crank spring).
    assert g.command(x + [2 * math.pi, 0, 0, 0]) == pytest.approx(g.command(x), rel=1e-9)


@pytest.mark.parametrize("args,words", [
    (["--q1", "nan"], "--q1 must be a finite number"),
    (["--q1", "1e999"], "--q1 must be a finite number"),
    (["--q1", ""], "--q1 must be a finite number"),
    (["--q1", "3,1"], "--q1 must be a finite number"),
    ([], "--q1 is required"),
    (["--q1", "0", "--Q", "1,2,3"], "--Q takes 4 weights"),
    (["--q1", "0", "--Q", "1,2,3,-4"], "--Q's weight on u2 must be >= 0, got '-4'"),
    (["--q1", "0", "--Q", "1,2,3,inf"], "--Q's weight on u2 must be a finite number, got 'inf'"),
    (["--q1", "0", "--Q", "1,0x2,3,4"], "--Q's weight on q2 must be a finite number"),
    (["--q1", "0", "--R", "0x1p-11"], "--R must be a finite number"),
    (["--q1", "1e308"], "--q1 must be an angle within 1e6 rad"),
    (["--q1", " 1"], "--q1 must be a finite number"),
    (["--q1", "0", "--R", "0"], "--R must be > 0"),
    (["--q1", "0", "--R", "-1e308"], "--R must be > 0"),
    (["--q1", "0", "--bogus"], "unrecognised option"),
])
def test_cli_refuses_bad_arguments_by_name(args, words):
    r = run_tool("design", "lqr", "--config", config_path(), *args, check=False)
    assert r.returncode == 2 and words in r.stderr, r.stderr


def test_cli_refuses_a_method_it_does_not_know():
    r = run_tool("design", "plan9", "--config", config_path(), "--q1", "0", check=False)
    assert r.returncode == 2 and "the method must be lqr or plan, got 'plan9'" in r.stderr
    r = run_tool("design", "--config", config_path(), "--q1", "0", check=False)
    assert r.returncode == 2 and "name the method" in r.stderr


def test_cli_says_what_it_cannot_write(tmp_path):
    r = run_tool("design", "lqr", "--config", config_path(), "--q1", "pi", "--out", tmp_path,
                 check=False)
    assert r.returncode == 4 and "cannot write --out" in r.stderr, r.stderr
    with open("/dev/full", "w") as full:
        r = subprocess.run([tool("design"), "lqr", "--config", config_path(), "--q1", "pi",
                            "--out", "-"], stdout=full, stderr=subprocess.PIPE, text=True,
                           timeout=60)
    assert r.returncode == 4 and "cannot write to stdout" in r.stderr, r.stderr
    copy = tmp_path / "copy.yaml"
    copy.write_text(open(config_path()).read())
    r = run_tool("design", "lqr", "--config", copy, "--q1", "pi", "--out", copy, check=False)
    assert r.returncode == 2 and "is the config itself" in r.stderr
    assert copy.read_text() == open(config_path()).read()


def test_a_holding_moment_beyond_the_torque_limit_is_refused():
    cfg = kane_sim.Config(config_path()).with_values({"command.torque_limit": 5.0})
    with pytest.raises(ValueError, match="needs 22.5.* N m, beyond command.torque_limit 5 N m"):
        kane_sim.control.lqr(cfg, q1=1.5)
    g = kane_sim.control.lqr(config_path(), q1=1.0)  # Bryson's weights: K[0] ~ 5000 N m/rad
    assert any("the law saturates" in note for note in g.notes), g.notes


def test_the_shipped_upright_law_is_design_lqrs():
    law = yaml.safe_load(open(config_path("upright_lqr.yaml")))["state_feedback"]
    fresh = yaml.safe_load(run_tool("design", "lqr", "--config", config_path(), "--q1", "pi",
                                    "--Q", "100,1,1,1", "--R", "1", "--out", "-").stdout)
    assert law == fresh["state_feedback"]


def test_cli_refuses_a_bad_config_and_no_design(tmp_path):
    r = run_tool("design", "lqr", "--config", "/dev/zero", "--q1", "0", check=False)
    assert r.returncode == 1 and "bad config" in r.stderr
    cfg = tmp_path / "no_spring.yaml"
    cfg.write_text(kane_sim.Config(config_path()).with_values(
        {"mechanism.spring_stiffness": 0.0}).yaml())
    r = run_tool("design", "lqr", "--config", cfg, "--q1", "0", check=False)
    assert r.returncode == 3 and "slider 4 has no static equilibrium" in r.stderr, r.stderr


def test_python_refusals():
    with pytest.raises(ValueError, match="q1 must be finite"):
        kane_sim.control.lqr(config_path(), q1=math.inf)
    with pytest.raises(ValueError, match="R must be a finite number > 0"):
        kane_sim.control.lqr(config_path(), q1=0.0, R=-1.0)
    with pytest.raises(ValueError, match="Q must be 4 numbers"):
        kane_sim.control.lqr(config_path(), q1=0.0, Q=[1, 2, 3])
    with pytest.raises(ValueError, match="Q must be 4 numbers"):
        kane_sim.control.lqr(config_path(), q1=0.0, Q=5.0)
    for bad in (True, "1", None):
        with pytest.raises(ValueError, match="q1 must be a number"):
            kane_sim.control.lqr(config_path(), q1=bad)
    g = kane_sim.control.lqr(config_path(), q1=math.pi)
    for x in ([math.nan, 0, 0, 0], [0, 0, 0], [math.inf, 0, 0, 0]):
        with pytest.raises(ValueError, match="x must be 4 finite numbers"):
            g.command(x)
    with pytest.raises(ValueError, match="Q is not positive semidefinite"):
        kane_sim.control.lqr(config_path(), q1=0.0, Q=[1, 2, 3, -4])
    with pytest.raises(ValueError, match="non-finite"):
        kane_sim.control.lqr(config_path(), q1=0.0, Q=[1, 2, math.nan, 4])
