"""Optimal moves (`design plan`, kane_sim.control.plan) and following them
(kane_sim.control.follow): the CLI and Python plan the same rows; `simulate --torque-csv` and the
Python simulator play a plan alike; a minimum-time plan is the bang-bang move an independent
shooting search finds (SciPy's solve_ivp on the SymPy oracle's equations, least_squares on the
switching times); the shipped swing-up is followed and held; what is refused is refused by name."""
import math
import os
import subprocess
import sys

import numpy as np
import pytest
import scipy.integrate
import scipy.optimize
import yaml

import kane_sim
import kane_sim.control
from conftest import config_path, run_tool, tool

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "tools"))
from sympy_model import sympy_model  # noqa: E402

SWING_UP = config_path("swing_up.yaml")


def plan_rows(text):
    """The rows of a plan CSV (comments and header dropped) as an array."""
    lines = [l for l in text.splitlines() if l and not l.startswith("#")]
    assert lines[0] == "t,q1,q2,u1,u2,M_m,K_q1,K_q2,K_u1,K_u2"
    return np.array([[float(v) for v in l.split(",")] for l in lines[1:]])


def test_cli_and_python_plan_the_same_rows(tmp_path):
    out = tmp_path / "plan.csv"
    args = ["--config", SWING_UP, "--to", "pi", "--duration", "3", "--intervals", "60",
            "--torque-limit", "8", "--Q", "100,1,1,1", "--R", "1", "--rate", "100"]
    r = run_tool("design", "plan", *args, "--out", out)
    assert "IPOPT: solved" in r.stdout, r.stdout
    p = kane_sim.control.plan(SWING_UP, to=math.pi, duration=3, intervals=60, torque_limit=8,
                              Q=[100, 1, 1, 1], R=1, rate=100)
    np.testing.assert_array_equal(plan_rows(out.read_text()), plan_rows(p.csv))
    assert p.max_defect <= 1e-8
    # The collocation's points keep |M_m| <= 8; between them the quadratic turns beyond where it
    # rides the bound (8.68 N m at these 60 intervals of 50 ms), never beyond the drive's 10.
    assert 8 < np.max(np.abs(p.torque)) <= 10
    np.testing.assert_allclose(p.x[-1], [math.pi, p.x[-1][1], 0, 0], atol=1e-12)


def test_simulate_and_python_play_a_plan_alike(tmp_path):
    out = tmp_path / "plan.csv"
    run_tool("design", "plan", "--config", SWING_UP, "--to", "pi", "--duration", "3",
             "--intervals", "200", "--torque-limit", "8", "--out", out)
    # Without the sensors' command latency: the torques in force as planned.
    cfg = kane_sim.Config(SWING_UP).with_values({"sensors.enabled": False})
    config = tmp_path / "no_sensors.yaml"
    config.write_text(cfg.yaml())
    r = run_tool("simulate", "--config", config, "--torque-csv", out, "--duration", "2",
                 "--output-rate", "100")
    rows = np.array([[float(v) for v in l.split(",")[:5]] for l in r.stdout.splitlines()[1:]])
    result = kane_sim.Simulator(cfg).run(2.0, torque=kane_sim.TorqueProfile.from_csv(str(out)),
                                         output_rate=100)
    np.testing.assert_array_equal(rows[:, 1:5], np.column_stack([result.q, result.u]))
    # Open loop it follows the plan for the first two seconds, before upright's instability
    # (a real eigenvalue of 11.6 1/s) takes over: measured 0.0028 rad.
    planned = plan_rows(out.read_text())
    at = np.searchsorted(planned[:, 0], rows[:, 0] - 1e-9)
    assert np.max(np.abs(rows[:, 1] - planned[at, 1])) < 0.01


def sign_changes(t, torque):
    s = np.sign(torque)
    i = np.where(np.abs(np.diff(s)) > 0)[0]
    return t[i]


def test_minimum_time_is_the_bang_bang_move_a_shooting_search_finds():
    cfg_path = config_path("mechanism.yaml")
    limit = 30.0
    p = kane_sim.control.plan(cfg_path, to=1.0, start=0.0, objective="time", duration=1.0,
                              torque_limit=limit, intervals=100)
    assert p.max_defect <= 1e-8
    inside = p.t < p.duration - 1e-9
    switches = sign_changes(p.t[inside], p.torque[inside])
    assert len(switches) == 3, switches
    assert np.mean(np.abs(p.torque[inside]) > 0.99 * limit) > 0.9  # bang-bang
    # The independent check: the SymPy oracle's equations (no code shared with the package),
    # +-limit between the switching times, integrated by solve_ivp; least_squares finds the
    # switching times and the duration that land at rest on the goal.
    with open(cfg_path) as f:
        doc = yaml.safe_load(f)
    mech = doc["mechanism"]
    x0 = (doc["initial_state"]["q1"], doc["initial_state"]["q2"])  # the spring's rest
    start, goal = p.x[0], p.x[-1]
    first = np.sign(p.torque[1])
    rhs = {s: sympy_model(mech, x0, torque=s * limit) for s in (+1.0, -1.0)}

    def land(times):
        t1, t2, t3, T = times
        x = np.array(start, dtype=float)
        edges = [0.0, t1, t2, t3, T]
        for i in range(4):
            if edges[i + 1] <= edges[i]:
                return np.full(4, 1e3)
            sol = scipy.integrate.solve_ivp(rhs[first * (-1) ** i], (edges[i], edges[i + 1]), x,
                                            rtol=1e-11, atol=1e-12, method="DOP853")
            x = sol.y[:, -1]
        return (x - goal) * np.array([1, 10, 0.1, 1])

    guess = np.append(switches, p.duration)
    found = scipy.optimize.least_squares(land, guess, xtol=1e-12, ftol=1e-12)
    assert np.max(np.abs(found.fun)) < 1e-6, found
    T = found.x[-1]
    print("minimum time: collocation %.6f s, shooting %.6f s (%.3f %%)"
          % (p.duration, T, 100 * (p.duration - T) / T))
    assert abs(p.duration - T) <= 0.01 * T


def test_the_shipped_swing_up_is_followed_and_held():
    run = kane_sim.control.follow(SWING_UP, config_path("swing_up_plan.csv"), duration=13.0)
    q1 = run["x"][:, 0]
    after = run["t"] >= 3.005
    assert np.max(np.abs(np.remainder(q1[after] - math.pi + math.pi, 2 * math.pi) - math.pi)) < 0.05
    assert np.max(np.abs(run["torque"])) <= 10.0 + 1e-12


@pytest.mark.parametrize("args,words", [
    (["--to", "nan"], "--to must be a finite number, got 'nan'"),
    (["--to", "pi", "--duration", "-1"], "the duration must be in (0, 3600] s"),
    (["--to", "pi", "--duration", "inf"], "--duration must be a finite number"),
    (["--to", "pi", "--intervals", "1"], "the intervals must be in [2, 20000]"),
    (["--to", "pi", "--torque-limit", "0"], "the torque limit must be finite and >= 1e-06 N m, got 0"),
    (["--to", "pi", "--torque-limit", "1e308"], "beyond the drive's command.torque_limit"),
    (["--to", "pi", "--Q", "1,nan,1,1"], "--Q's weight on q2 must be a finite number"),
    (["--to", "pi", "--Q", "1,-1,1,1"], "--Q's weight on q2 must be >= 0"),
    (["--to", "pi", "--R", "0"], "--R must be > 0"),
    (["--to", "pi", "--q2-range", "1,0"], "slider 4's travel [1, 0] m is empty"),
    (["--to", "pi", "--q2-range", "0,2"], "the goal's q2 = -0.66"),
    (["--to", "pi", "--objective", "fastest"], "--objective must be effort or time"),
    (["--to", "pi", "--q1", "1"], "--q1 is not a flag of design plan"),
    (["--to", "pi", "--rate", "0"], "the plan's row rate must be in [1, 1e6] Hz"),
    (["--to", "pi", "--rate", "1e6", "--duration", "3600"],
     "are more than the 300000 a plan may have"),
    (["--to", "pi", "--gap", "-0.1"], "the gap must be >= 0 m"),
    (["--to", "pi", "--torque-limit", "1e-300"], "the torque limit must be finite and >= 1e-06"),
    (["--to", "pi", "--objectiv", "time"], "unrecognised option '--objectiv'"),
    (["--from", "x", "--to", "pi"], "--from must be a finite number, got 'x'"),
])
def test_design_plan_refuses_bad_arguments_by_name(args, words):
    r = run_tool("design", "plan", "--config", SWING_UP, *args, check=False)
    assert r.returncode in (2, 3), (r.returncode, r.stderr)
    assert words in r.stderr, r.stderr


def test_design_plan_usage_errors_exit_2():
    for args in (["--rate", "0"], ["--rate", "1e6", "--duration", "3600"], ["--gap", "-1"]):
        r = run_tool("design", "plan", "--config", SWING_UP, "--to", "pi", *args, check=False)
        assert r.returncode == 2, (args, r.returncode, r.stderr)


def test_a_move_to_where_the_crank_already_is_is_found():
    # Slider 4 starts 0.039 m above its rest: the crank must move to settle it, and come back.
    p = kane_sim.control.plan(SWING_UP, to=0.0, duration=2.0, intervals=60, torque_limit=8)
    assert p.max_defect <= 1e-8
    np.testing.assert_allclose(p.x[-1, 2:], [0, 0], atol=1e-12)


def test_out_is_written_whole_or_not_at_all(tmp_path):
    out = tmp_path / "plan.csv"
    r = run_tool("design", "plan", "--config", SWING_UP, "--to", "pi", "--out",
                 tmp_path / "no" / "such" / "plan.csv", check=False)
    assert r.returncode == 4 and "cannot write --out" in r.stderr, r.stderr
    assert "iteration" not in r.stderr  # refused before IPOPT ran
    proc = subprocess.Popen([tool("design"), "plan", "--config", SWING_UP, "--to", "pi",
                             "--duration", "3", "--intervals", "2000", "--torque-limit", "8",
                             "--out", str(out)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    import time
    time.sleep(1.0)
    proc.send_signal(15)
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 143 and "stopped by SIGTERM: no plan written" in err, err
    assert not out.exists() and not (tmp_path / "plan.csv.partial").exists()


def test_a_move_out_of_reach_is_refused_with_ipopts_status():
    # 0.3 s and 2 N m cannot lift a crank gravity holds with 22.6 N m.
    r = run_tool("design", "plan", "--config", SWING_UP, "--to", "pi", "--duration", "0.3",
                 "--torque-limit", "2", "--intervals", "30", "--max-iterations", "400",
                 check=False)
    assert r.returncode == 3, r.stderr
    assert "design: no plan: IPOPT: " in r.stderr and "allow more time" in r.stderr, r.stderr
    # A goal the drive cannot hold: refused before IPOPT runs.
    r = run_tool("design", "plan", "--config", SWING_UP, "--to", "1.5707963", check=False)
    assert r.returncode == 3 and "beyond command.torque_limit" in r.stderr, r.stderr


def test_ctrl_c_stops_ipopt(tmp_path):
    proc = subprocess.Popen([tool("design"), "plan", "--config", SWING_UP, "--to", "pi",
                             "--duration", "3", "--intervals", "2000", "--torque-limit", "8"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    import time
    time.sleep(1.0)
    proc.send_signal(2)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 130, err
    assert "stopped by Ctrl-C (SIGINT): no plan written" in err, err


def test_plan_files_are_read_with_their_faults_named(tmp_path):
    good = open(config_path("swing_up_plan.csv")).read().splitlines()
    end = [l for l in good if l.startswith("# end of plan:")]
    assert len(end) == 1 and good[-1] == end[0]
    header = [l for l in good[:-1] if l.startswith("#") or l.startswith("t,")]
    rows = [l for l in good[:-1] if not (l.startswith("#") or l.startswith("t,"))]

    def ended(body):
        return body + ["# end of plan: %d rows" % len(body)]

    cases = {
        "gap": (ended(rows[:10] + rows[12:]), "the rows must be evenly spaced"),
        "nan": (ended(rows[:5] + [rows[5].replace(rows[5].split(",")[2], "nan", 1)] + rows[6:]),
                "(q2): 'nan' is not finite"),
        "extra": (ended([rows[0] + ",1"] + rows[1:]), "more than 10 columns"),
        "empty": ([], "has 0 rows: a plan has at least 2"),
        "cut": (rows[:375], "has no end line '# end of plan: N rows' after its 375 rows"),
        "miscounted": (rows + ["# end of plan: 999 rows"], "says it has 999 rows"),
        "binary": (ended(["\x80\xff" + rows[0]] + rows[1:]), "'\\x80\\xFF0' is not a number"),
        "squeezed": (ended(["%r,%s" % (float(r.split(",")[0]) * 1e-9, r.split(",", 1)[1])
                            for r in rows[:20]]), "a plan's rows are at least 1e-06 s apart"),
    }
    for name, (body, words) in cases.items():
        path = tmp_path / (name + ".csv")
        path.write_text("\n".join(header + body) + "\n", encoding="latin-1")
        with pytest.raises(ValueError) as e:
            kane_sim.control.follow(SWING_UP, str(path), duration=1.0)
        assert words in str(e.value), (name, str(e.value))
    # Another mechanism's plan: refused by the follower, the controller and simulate alike.
    other = config_path("mechanism.yaml")
    with pytest.raises(ValueError, match="initial_state.q1: the plan starts at 0, the config at"):
        kane_sim.control.follow(other, config_path("swing_up_plan.csv"), duration=1.0)
    r = run_tool("simulate", "--config", other, "--torque-csv", config_path("swing_up_plan.csv"),
                 "--duration", "1", check=False)
    assert r.returncode == 2 and "is a plan for another mechanism or start" in r.stderr, r.stderr
    for bad in ("/dev/zero", str(tmp_path)):
        with pytest.raises(ValueError, match="not a regular file"):
            kane_sim.control.follow(SWING_UP, bad, duration=1.0)


def test_python_plan_refusals():
    with pytest.raises(ValueError, match="plan: to must be finite"):
        kane_sim.control.plan(SWING_UP, to=float("nan"))
    with pytest.raises(ValueError, match="plan: objective must be 'effort' or 'time'"):
        kane_sim.control.plan(SWING_UP, to=math.pi, objective="fast")
    with pytest.raises(ValueError, match="plan: intervals must be in"):
        kane_sim.control.plan(SWING_UP, to=math.pi, intervals=-5)
    with pytest.raises(ValueError, match="plan: Q must be 4 numbers"):
        kane_sim.control.plan(SWING_UP, to=math.pi, Q=[1, 2])
    with pytest.raises(ValueError, match="follow: duration must be in"):
        kane_sim.control.follow(SWING_UP, config_path("swing_up_plan.csv"), duration=-1)
    with pytest.raises(ValueError, match=r"follow: duration must be in \(0, 10000\] s"):
        kane_sim.control.follow(SWING_UP, config_path("swing_up_plan.csv"), duration=1e6)
    with pytest.raises(TypeError, match="follow: plan_csv must be a path"):
        kane_sim.control.follow(SWING_UP, None, duration=1)
    with pytest.raises(ValueError, match=r"plan: intervals must be in \[2, 20000\]"):
        kane_sim.control.plan(SWING_UP, to=math.pi, intervals=10**30)
    with pytest.raises(ValueError, match="are more than the 300000 a plan may have"):
        kane_sim.control.plan(SWING_UP, to=math.pi, rate=1e6, duration=3600)
