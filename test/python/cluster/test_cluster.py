"""Sweeps on a Dask cluster (`rosrun kane_sim sweep --scheduler`, kane_sim.sweep(client=)): a
real scheduler and two worker processes on 127.0.0.1. The CSV is simulate --sweep's (every
column but wall_time); a worker killed mid-sweep loses nothing; Ctrl-C cancels the cluster's
tasks and keeps the finished rows; an unreachable scheduler is named."""
import csv
import json
import os
import signal
import subprocess
import sys
import time

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
from conftest import config_path, run_tool, tool  # noqa: E402

import kane_sim  # noqa: E402

distributed = pytest.importorskip("distributed")  # python3-distributed (install_deps.sh)

GRID = ["--sweep", "mechanism.spring_stiffness=100:400:12", "--sweep",
        "damping.slider4_joint=0:1:3"]


def _start(args, log):
    return subprocess.Popen(args, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)


def _worker(scheduler_file, folder, name):
    log = open(os.path.join(folder, name + ".log"), "w")
    return _start(["dask", "worker", "--scheduler-file", scheduler_file, "--nthreads", "1",
                   "--no-nanny", "--no-dashboard", "--name", name], log)


def _workers(client):
    return len(client.scheduler_info()["workers"])


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    """A scheduler and two workers; yields (scheduler file, its address, a Client)."""
    folder = str(tmp_path_factory.mktemp("dask"))
    scheduler_file = os.path.join(folder, "scheduler.json")
    procs = [_start(["dask", "scheduler", "--host", "127.0.0.1", "--port", "0",
                     "--scheduler-file", scheduler_file, "--no-dashboard"],
                    open(os.path.join(folder, "scheduler.log"), "w"))]
    deadline = time.monotonic() + 60
    while not os.path.exists(scheduler_file) and time.monotonic() < deadline:
        time.sleep(0.1)
    procs += [_worker(scheduler_file, folder, "w%d" % i) for i in (1, 2)]
    client = distributed.Client(scheduler_file=scheduler_file, timeout=30)
    client.wait_for_workers(2, timeout=60)
    address = json.load(open(scheduler_file))["address"]
    yield scheduler_file, address, client, folder
    client.close()
    # Workers first, then the scheduler (a worker whose scheduler is gone first may retry the
    # connection instead of exiting); one that outlives 30 s of SIGTERM (seen on a loaded
    # 2-core machine) is killed: the teardown ends either way.
    for p in reversed(procs):
        os.killpg(p.pid, signal.SIGTERM)
        try:
            p.wait(timeout=30)
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)
            p.wait(timeout=30)


def rows_without_wall_time(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    w = rows[0].index("wall_time")
    return [r[:w] + r[w + 1:] for r in rows]


def test_the_cluster_writes_simulates_csv(cluster, tmp_path):
    scheduler_file, address, _, _ = cluster
    table = tmp_path / "torque.csv"
    table.write_text("t,torque\n0,1.5\n0.3,-2\n0.6,0.5\n")
    for profile in (["--torque-sine", "2,0.5"], ["--torque-step", "0.2,0,3"],
                    ["--torque-csv", str(table)]):
        local, remote = tmp_path / "local.csv", tmp_path / "remote.csv"
        run_tool("simulate", "--config", config_path(), "--duration", "1", *profile, *GRID,
                 "--csv", local)
        r = run_tool("sweep", "--config", config_path(), "--duration", "1", *profile, *GRID,
                     "--csv", remote, "--scheduler", address, "--chunk", "5")
        assert "on %s in tasks of 5" % address in r.stderr
        assert rows_without_wall_time(remote) == rows_without_wall_time(local), profile
        assert len(rows_without_wall_time(local)) == 37


def test_python_sweep_with_a_client_is_the_local_sweep(cluster):
    _, address, client, _ = cluster
    grid = {"mechanism.rod_mass": [0.5, 1.0, 1.5, 2.0, -1.0], "initial_state.u1": [0.0, 2.0]}
    local = kane_sim.sweep(config_path(), grid=grid, duration=0.5, torque=1.0)
    for c in (client, address):
        remote = kane_sim.sweep(config_path(), grid=grid, duration=0.5, torque=1.0, client=c,
                                chunk=3)
        assert list(remote) == list(local)
        for name in local:
            if name in ("status", "error"):
                assert list(remote[name]) == list(local[name])
            elif name != "wall_time":
                assert remote[name].tobytes() == local[name].tobytes(), name
    assert list(local["status"]).count("config_refused") == 2  # rod mass -1: refused rows


def test_a_worker_killed_mid_sweep_loses_nothing(cluster, tmp_path):
    scheduler_file, address, client, folder = cluster
    extra = _worker(scheduler_file, folder, "doomed")
    deadline = time.monotonic() + 60
    while _workers(client) < 3 and time.monotonic() < deadline:
        time.sleep(0.1)
    assert _workers(client) == 3
    args = ["--config", config_path(), "--duration", "50", "--torque", "1", "--simd", "off",
            "--sweep", "mechanism.spring_stiffness=100:400:300"]
    out = tmp_path / "remote.csv"
    sweep = subprocess.Popen([tool("sweep"), *args, "--csv", str(out), "--scheduler", address,
                              "--chunk", "4"], stderr=subprocess.PIPE, text=True)
    # Kill the third worker once it holds work (SIGKILL: no goodbye to the scheduler).
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        busy = client.processing()
        doomed = [w for w, info in client.scheduler_info()["workers"].items()
                  if info.get("name") == "doomed"]
        if doomed and busy.get(doomed[0]):
            break
        time.sleep(0.05)
    os.killpg(extra.pid, signal.SIGKILL)
    _, err = sweep.communicate(timeout=240)
    assert sweep.returncode == 0, err
    local = tmp_path / "local.csv"
    run_tool("simulate", *args, "--csv", local)
    assert rows_without_wall_time(out) == rows_without_wall_time(local)
    assert _workers(client) == 2


def test_ctrl_c_cancels_the_tasks_and_keeps_the_finished_rows(cluster, tmp_path):
    _, address, client, _ = cluster
    out = tmp_path / "interrupted.csv"
    sweep = subprocess.Popen([tool("sweep"), "--duration", "500", "--torque", "1", "--simd",
                              "off", "--sweep", "mechanism.spring_stiffness=100:400:1000",
                              "--csv", str(out), "--scheduler", address, "--chunk", "4"],
                             stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:  # some chunks finished: rows written
        if os.path.exists(str(out) + ".partial") and \
                open(str(out) + ".partial").read().count("\n") > 8:
            break
        time.sleep(0.05)
    sweep.send_signal(signal.SIGINT)
    _, err = sweep.communicate(timeout=60)
    assert sweep.returncode == 130 and "the cluster's tasks were cancelled" in err, err
    rows = rows_without_wall_time(out)
    assert 8 <= len(rows) - 1 < 1000
    cases = [int(r[0]) for r in rows[1:]]
    assert cases == sorted(cases) and len(set(cases)) == len(cases)
    deadline = time.monotonic() + 20  # the scheduler forgets the cancelled tasks
    while client.run_on_scheduler(lambda dask_scheduler: len(dask_scheduler.tasks)) and \
            time.monotonic() < deadline:
        time.sleep(0.1)
    assert client.run_on_scheduler(lambda dask_scheduler: len(dask_scheduler.tasks)) == 0


def test_python_sweep_refuses_bad_clients_and_takes_no_cases(cluster):
    _, address, client, _ = cluster
    empty = kane_sim.sweep(cases={"mechanism.rod_mass": []}, duration=0.1, client=address)
    assert all(len(v) == 0 for v in empty.values()) and "q1" in empty
    with pytest.raises(TypeError, match="client must be a distributed.Client"):
        kane_sim.sweep(cases={"mechanism.rod_mass": [1.0]}, duration=0.1, client=5)
    closed = distributed.Client(address, timeout=30)
    closed.close()
    with pytest.raises(ValueError, match="the distributed.Client is closed"):
        kane_sim.sweep(cases={"mechanism.rod_mass": [1.0]}, duration=0.1, client=closed)
    for chunk in (0, "x", 1.5):
        with pytest.raises(ValueError, match="chunk"):
            kane_sim.sweep(cases={"mechanism.rod_mass": [1.0]}, duration=0.1, chunk=chunk)


def test_an_unreachable_scheduler_is_named(tmp_path, monkeypatch):
    r = run_tool("sweep", "--duration", "1", *GRID, "--scheduler", "tcp://127.0.0.1:1",
                 "--connect-timeout", "2", check=False)
    assert r.returncode == 2 and "scheduler tcp://127.0.0.1:1 cannot be reached" in r.stderr
    from kane_sim import cluster
    monkeypatch.setattr(cluster, "CONNECT_TIMEOUT", 2.0)
    with pytest.raises(ValueError, match="scheduler tcp://127.0.0.1:1 cannot be reached"):
        kane_sim.sweep(grid={"mechanism.rod_mass": [1.0]}, duration=0.1,
                       client="tcp://127.0.0.1:1")


@pytest.mark.parametrize("args, words", [
    (["--duration", "1", "--chunk", "0", *GRID], "--chunk must be in [1, 100000]"),
    (["--duration", "1", "--chunk", "x", *GRID], "--chunk takes a whole number"),
    (["--duration", "1", "--jobs", "-1", *GRID], "--jobs must be in"),
    (["--duration", "nan", *GRID], "--duration must be finite"),
    (["--duration", "1e308", *GRID], "duration must be in [0, 1e+07] s"),
    (["--duration", "1", "--torque", "inf", *GRID], "--torque must be finite"),
    (["--duration", "1", "--torque-sine", "2,x", *GRID], "--torque-sine: 'x' is not a number"),
    (["--duration", "1", "--torque-csv", "/dev/zero", *GRID], "--torque-csv"),
    (["--duration", "1", "--sweep", "mechanism.spring_stiffness=1:2"], "spring_stiffness"),
    (["--duration", "1", "--sweep", "mechanism.spring_stifness=1:2:3"], "a typo?"),
    (["--duration", "1", "--sweep-file", "/dev/zero"], "--sweep-file"),
    (["--duration", "1", "--simd", "avx9", *GRID], "avx9"),
    (["--duration", "1", "--csv", "", *GRID], "--csv needs a file name"),
    (["--duration", "1", "--csv", "/tmp", *GRID], "is a folder"),
    (["--duration", "1"], "give --sweep KEY=START:STOP:COUNT"),
    (["--duration", "1", "--swee", "a=1:2:3", *GRID], "unrecognised option '--swee'"),
    (["--duration", "1", "--torque", "1", "--torque-sine", "1,1", *GRID], "at most one of"),
    (["--duration", "1_0", *GRID], "('1_0') for option '--duration' is invalid"),
    (["--duration", "2 ", *GRID], "for option '--duration' is invalid"),
    (["--duration", "1", "--duration", "2", *GRID], "'--duration' cannot be specified more than once"),
    (["--duration", "1", "--chunk", "2", "--chunk", "3", *GRID], "--chunk given more than once"),
    (["--duration", "1", "--scheduler", "--sweep", "a=1:2:3"], "--scheduler needs a value"),
    (["--dur", "1", *GRID], "unrecognised option '--dur'"),
    (["--duration", "1", "--replay", "x.bag", *GRID], "--replay takes the bag's inputs"),
    (["--duration", "1", "--bag", "x.bag", *GRID], "--bag writes one run's topics"),
    (["--duration", "1", "--jobs", "2", "--scheduler", "tcp://127.0.0.1:1", *GRID],
     "with --scheduler the cluster's workers decide"),
    (["--duration", "1", "--jobs", "100000", *GRID], "--jobs must be in [1,"),
    (["--duration", "1", "--scheduler", "", *GRID], "--scheduler needs"),
    (["--duration", "1", "--scheduler", "nofile.json", *GRID], "nofile.json does not exist"),
    (["--duration", "1", "--scheduler", "garbage", *GRID], "scheduler garbage cannot be reached"),
    (["--duration", "1", "--connect-timeout", "0", *GRID], "--connect-timeout must be in"),
])
def test_cli_refuses_by_name(args, words):
    r = run_tool("sweep", *args, check=False)
    assert r.returncode == 2 and words in r.stderr, (args, r.returncode, r.stderr)
    assert "Traceback" not in r.stderr


def test_cli_takes_what_simulate_takes(tmp_path):
    # Values that start with '-', an integrator, a link as --csv (written through, as simulate).
    for extra in (["--torque-sine", "-1,2"], ["--torque-step", "-0.5,0,-2"], ["--torque", "-1e-3"],
                  ["--integrator", "dopri5"]):
        local, mine = tmp_path / "local.csv", tmp_path / "target.csv"
        mine.write_text("")
        link = tmp_path / "link.csv"
        if link.is_symlink():
            link.unlink()
        link.symlink_to(mine)
        run_tool("simulate", "--duration", "0.5", *extra, *GRID, "--csv", local)
        run_tool("sweep", "--duration", "0.5", *extra, *GRID, "--csv", link)
        assert link.is_symlink() and not os.path.exists(str(link) + ".partial")
        assert rows_without_wall_time(mine) == rows_without_wall_time(local), extra


@pytest.mark.parametrize("signum, code", [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_cli_local_stop_keeps_the_finished_rows(tmp_path, signum, code):
    out = tmp_path / "local.csv"
    sweep = subprocess.Popen([tool("sweep"), "--duration", "2000", "--torque", "1", "--simd",
                              "off", "--jobs", "1", "--sweep",
                              "mechanism.spring_stiffness=100:400:50", "--csv", str(out)],
                             stderr=subprocess.PIPE, text=True)
    time.sleep(3.0)
    sweep.send_signal(signum)
    _, err = sweep.communicate(timeout=60)
    assert sweep.returncode == code and "interrupted: kept the" in err, err
    rows = rows_without_wall_time(out)
    assert 1 <= len(rows) - 1 < 50 and all(r[2] == "ok" for r in rows[1:])


def test_a_lost_scheduler_and_a_worker_without_kane_sim_are_named(tmp_path):
    folder = str(tmp_path)
    scheduler_file = os.path.join(folder, "s.json")
    scheduler = _start(["dask", "scheduler", "--host", "127.0.0.1", "--port", "0",
                        "--scheduler-file", scheduler_file, "--no-dashboard"],
                       open(os.path.join(folder, "scheduler.log"), "w"))
    deadline = time.monotonic() + 60
    while not os.path.exists(scheduler_file) and time.monotonic() < deadline:
        time.sleep(0.1)
    # A worker started without the build's environment: it cannot import kane_sim.
    bare = subprocess.Popen(["dask", "worker", "--scheduler-file", scheduler_file, "--nthreads",
                             "1", "--no-nanny", "--no-dashboard"], env={"PATH": "/usr/bin:/bin"},
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            start_new_session=True)
    client = distributed.Client(scheduler_file=scheduler_file, timeout=30)
    client.wait_for_workers(1, timeout=60)
    r = run_tool("sweep", "--duration", "1", *GRID, "--scheduler", scheduler_file, check=False)
    assert r.returncode == 5 and "a worker cannot import kane_sim" in r.stderr, r.stderr
    assert "Traceback" not in r.stderr
    os.killpg(bare.pid, signal.SIGKILL)
    good = _worker(scheduler_file, folder, "good")
    out = tmp_path / "lost.csv"
    sweep = subprocess.Popen([tool("sweep"), "--duration", "100", "--torque", "1", "--simd", "off",
                              "--sweep", "mechanism.spring_stiffness=100:400:600", "--csv",
                              str(out), "--scheduler", scheduler_file, "--chunk", "4"],
                             stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:  # some rows in: then the scheduler dies
        if os.path.exists(str(out) + ".partial") and \
                open(str(out) + ".partial").read().count("\n") > 8:
            break
        time.sleep(0.05)
    client.close()
    os.killpg(scheduler.pid, signal.SIGKILL)
    _, err = sweep.communicate(timeout=120)
    os.killpg(good.pid, signal.SIGKILL)
    assert sweep.returncode == 5 and "tasks were lost on the cluster" in err and "kept the" in err, err
    assert "Traceback" not in err
    assert 8 <= len(rows_without_wall_time(out)) - 1 < 600


@pytest.mark.parametrize("bad", [["--duration", "-1"], ["--torque-sine", "2,x"], ["--dur", "1"],
                                 ["--simd", "avx9"], ["--integrator", "euler"],
                                 ["--output-rate", "0"]])
def test_cli_gives_simulates_message_for_simulates_flags(bad):
    # One grammar: sweep reads simulate's flags with simulate's parser, so the words agree.
    args = [*(["--duration", "1"] if "--duration" not in bad else []), *bad, *GRID]
    mine = run_tool("sweep", *args, check=False)
    theirs = run_tool("simulate", *args, check=False)
    assert mine.returncode == theirs.returncode == 2, (mine.stderr, theirs.stderr)
    message = theirs.stderr.splitlines()[0].replace("error: ", "", 1)
    assert "sweep: error: " + message in mine.stderr, (mine.stderr, theirs.stderr)
