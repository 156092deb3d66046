"""One case, one answer, through every offline door: `simulate` (a single run's last CSV row),
`simulate --sweep` (the case's row), `rosrun kane_sim sweep`'s row, Python's Simulator.run (and
its states_only form, identification's replays),
Python's sweep row and each mechanism of a BatchSimulator (lanes and drivers; built, then
given the case's parameters by set_params) driven step by
step, built from a table of numbers (from_numbers) and given the whole plan (rollout), over every
command mode (effort, velocity, position), with and without a profile, sensors on and off,
the physics options off and on (contact, the five dampers: the joints' and the spring's, and
the four joints' Coulomb friction). All run the one driver, so they agree bit for bit; a door that
applies a different command stream (a servo driven to setpoint 0 because no profile was given,
say) shows up as a different final state. A new option or door joins this matrix: the browser's
kaneSim.run runs it in test/python/browser (every row, against simulate with the browser's libm)."""
import itertools

import numpy as np
import pytest
import yaml

import kane_sim
from conftest import config_path, run_tool

DURATION = 0.5  # [s]: long enough for every mode to move the crank away from where it starts
# A profile in each mode's unit: torque [N m], speed [rad/s], angle [rad].
SINE = {"effort": (2.0, 1.0, 0.5), "velocity": (1.0, 1.0, 0.5), "position": (0.3, 1.0, 0.6)}
MODES = ("effort", "velocity", "position")


def case_config(tmp_path, mode, sensors, contact):
    with open(config_path()) as f:
        cfg = yaml.safe_load(f)
    cfg["command"]["mode"] = mode
    cfg["contact"]["enabled"] = contact
    if contact:  # the options together: every damper, the one beside the spring too
        cfg["damping"] = {"crank_joint": 0.2, "coupler_joint": 0.1, "slider3_joint": 0.5,
                          "slider4_joint": 0.5, "spring": 0.8}
        cfg["friction"] = {"crank_joint": 0.1, "coupler_joint": 0.05, "slider3_joint": 0.4,
                           "slider4_joint": 0.3, "velocity_scale": 0.05}
    if sensors:
        with open(config_path("sensors.yaml")) as f:
            cfg["sensors"] = yaml.safe_load(f)["sensors"]
    path = tmp_path / ("%s_%d_%d.yaml" % (mode, sensors, contact))
    path.write_text(yaml.safe_dump(cfg))
    return str(path)


def final_row(csv_path):
    rows = np.genfromtxt(csv_path, delimiter=",", names=True, dtype=None, encoding="utf-8")
    return np.atleast_1d(rows)[-1]


def batch_run(cfg, torque, n=3):
    """n copies of the case in a BatchSimulator (SIMD lanes where the case allows, and the
    drivers), the profile's value at each mechanism's time sent before every physics step, as
    a single run's profile is: {path: (times, states)}."""
    out = {}
    steps = int(round(DURATION * 1000))
    for simd in ("auto", "off"):
        # Step by step; the same mechanisms from a table of numbers (the domain-randomisation
        # door: the physics stored without the loader's YAML); the whole plan at once (rollout).
        table = {"mechanism.gravity": np.full(n, 9.81)}
        for label, params in (("", None), (" from numbers", table)):
            batch = kane_sim.BatchSimulator(n, cfg, params, simd=simd)
            for _ in range(steps):
                batch.step(np.array([torque.at(t) for t in batch.times]))
            assert not batch.terminated.any(), batch.reasons
            out[batch.path + label] = (batch.times, batch.states)
        # Built as another mechanism, moved, then given the case's parameter (set_params: a
        # fresh start of the new config, as between episodes).
        batch = kane_sim.BatchSimulator(n, cfg, {"mechanism.gravity": np.full(n, 5.0)}, simd=simd)
        batch.step(np.full(n, 0.3), 7)
        batch.set_params({"mechanism.gravity": 9.81})
        for _ in range(steps):
            batch.step(np.array([torque.at(t) for t in batch.times]))
        out[batch.path + " set_params"] = (batch.times, batch.states)
        batch = kane_sim.BatchSimulator(n, cfg, simd=simd)
        plan = np.array([torque.at(k * (1.0 / 1000.0)) for k in range(steps)])
        rolled = batch.rollout(np.tile(plan, (n, 1)))
        out[batch.path + " rollout"] = (batch.times, rolled[:, -1])
    return out


@pytest.mark.parametrize("mode,profile,sensors,contact",
                         list(itertools.product(MODES, (False, True), (False, True),
                                                (False, True))))
def test_every_offline_door_gives_the_same_final_state(tmp_path, mode, profile, sensors,
                                                       contact):
    cfg = case_config(tmp_path, mode, sensors, contact)
    amplitude, frequency, offset = SINE[mode]
    flags = ["--torque-sine", "%r,%r,%r" % SINE[mode]] if profile else []
    torque = kane_sim.TorqueProfile.sine(amplitude, frequency, offset) if profile else None

    single = tmp_path / "single.csv"
    run_tool("simulate", "--config", cfg, "--duration", DURATION, "--csv", single, *flags)
    swept = tmp_path / "sweep.csv"
    # A sweep of one case whose key holds the base config's value: the case is the base config.
    run_tool("simulate", "--config", cfg, "--duration", DURATION, "--csv", swept,
             "--sweep", "mechanism.gravity=9.81:9.81:1", *flags)
    cli_swept = tmp_path / "sweep_cli.csv"  # rosrun kane_sim sweep (here; the cluster: its test)
    run_tool("sweep", "--config", cfg, "--duration", DURATION, "--csv", cli_swept,
             "--sweep", "mechanism.gravity=9.81:9.81:1", *flags)
    run = kane_sim.Simulator(cfg).run(DURATION, torque=torque)
    lean = kane_sim.Simulator(cfg).run(DURATION, torque=torque, states_only=True)  # fits' door
    py_sweep = kane_sim.sweep(cfg, cases={"mechanism.gravity": [9.81]}, duration=DURATION,
                              torque=torque)

    batch = batch_run(cfg, torque) if profile else None

    expected = final_row(single)
    sweep_row = final_row(swept)
    assert sweep_row["status"] == "ok" and py_sweep["status"][0] == "ok"
    for k, name in enumerate(("t", "q1", "q2", "u1", "u2")):
        doors = {"simulate --sweep": sweep_row[name], "Simulator.run": run[name][-1],
                 "Simulator.run(states_only)": lean[name][-1],
                 "sweep()": py_sweep[name][0], "sweep CLI": final_row(cli_swept)[name]}
        if batch is not None:  # every mechanism of the batch, on lanes where it can
            for path, (times, states) in batch.items():
                for i in range(len(times)):
                    doors["BatchSimulator %s #%d" % (path, i)] = \
                        times[i] if name == "t" else states[i, k - 1]
        for door, value in doors.items():
            assert value == expected[name], "%s: %s %r, simulate %r" % (
                name, door, value, expected[name])
    if profile:  # the profile moved the crank: a door that dropped it would not match
        assert abs(expected["q1"] - 0.5235987755982988) > 1e-3, expected["q1"]


def test_a_servo_without_a_profile_holds_its_start_in_every_door(tmp_path):
    """The position servo holds the starting angle (pi/6) without a profile; the sweep used to
    drive its setpoint to 0 (q1 2.8e-09 after 1 s)."""
    cfg = case_config(tmp_path, "position", False, False)
    swept = tmp_path / "sweep.csv"
    run_tool("simulate", "--config", cfg, "--duration", 1, "--csv", swept,
             "--sweep", "command.position_kp=500:500:1")
    q1_sweep = final_row(swept)["q1"]
    q1_python = kane_sim.sweep(cfg, cases={"command.position_kp": [500.0]}, duration=1.0)["q1"][0]
    for q1 in (q1_sweep, q1_python):
        assert abs(q1 - 0.5235987755982988) < 0.05, q1  # held near pi/6 (gravity sags it a bit)
