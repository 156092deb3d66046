"""identify on recordings made under a controller: the logged commands (a script's command_t and
command columns, a bag's ~input_log) give the torque between samples and, in a bag, the
simulation's own clock; what they cannot be is said, and hostile ones are refused by name."""
import math
import os
import sys

import numpy as np
import pytest

import kane_sim
from kane_sim import identify as ki
from kane_sim.identify.commands import held_torque, Commands
from kane_sim.identify.data import load_motion

sys.path.insert(0, os.path.dirname(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))
import rigs  # noqa: E402
from conftest import tool  # noqa: E402

MASSES_AND_K = rigs.MASSES + rigs.STIFFNESS


@pytest.fixture(scope="module")
def pd_rig():
    """Seed 2's rig (masses and k 0.6-1.6 of the defaults) with 100 Hz sensors under a 100 Hz PD
    loop in lockstep, 30 s: the torque steps between every two readings."""
    rig = rigs.draw(2, regime="oscillation", duration=30.0)
    rig.sensors["sensors.rate"] = 100.0
    return rig, rigs.record_closed_loop(rig)


def _base(rig):
    return rig.config().with_values({"sensors.enabled": False})


def test_logged_commands_fit_a_pd_loop_to_the_noise(pd_rig):
    rig, data = pd_rig
    fit = ki.identify(data, _base(rig), validate=False)
    assert fit.refusal is None
    assert any("logged commands (command columns)" in n for n in fit.notes), fit.notes
    assert fit.refined["converged"]
    # The torque is known between samples: no floor from its steps.
    assert fit.refined["torque_sampling"] == (0.0, 0.0)
    rows = rigs.score(rig, fit)
    for name in MASSES_AND_K:
        # 30 s of a 100 Hz PD loop: the family's worst for masses and k is 2 %, and each
        # estimate within 3.5 of its errors (3 for 99.7 % of a normal's, some slack for one draw).
        assert abs(rows[name]["error"]) < 0.02, (name, rows[name])
        assert rows[name]["z"] < 3.5, (name, rows[name])


@pytest.fixture(scope="module")
def stiff_pd_rig():
    """pd_rig's rig under the example controller's gains (kp = 500, kd = 30): the torque
    saturates at 20 N m and swings between the limits from one command to the next."""
    rig = rigs.draw(2, regime="oscillation", duration=30.0)
    rig.sensors["sensors.rate"] = 100.0
    return rig, rigs.record_closed_loop(rig, gains=(500.0, 30.0))


def test_without_the_log_a_guessed_torque_is_refused(stiff_pd_rig):
    rig, data = stiff_pd_rig
    plain = {k: v for k, v in data.items() if not k.startswith("command")}
    # Fitted from the effort samples, the masses came out 20-100 % off, the positions followed
    # to 365 times their noise only: refused, naming the cause and what to record.
    fit = ki.identify(plain, _base(rig), validate=False)
    assert fit.refusal and "steps between its samples" in fit.refusal, fit.refusal
    assert "~input_log" in fit.refusal and "command_t" in fit.refusal
    # With the commands, the same recording is fitted to the noise, masses and k within 0.1 %.
    fit = ki.identify(data, _base(rig), validate=False)
    assert fit.refusal is None and fit.refined["converged"]
    rows = rigs.score(rig, fit)
    for name in MASSES_AND_K:
        assert abs(rows[name]["error"]) < 0.001, (name, rows[name])


def test_without_the_log_the_torque_between_samples_is_a_guess(pd_rig):
    rig, data = pd_rig
    plain = {k: v for k, v in data.items() if not k.startswith("command")}
    motion = load_motion(plain, None, _base(rig))
    assert motion.held is None and motion.commands is None
    # The torque steps between samples: the replay's spline through the samples is not it.
    step = 1.0 / rig.config()["simulation.physics_rate"]
    times = step * np.arange(int(20.0 / step))
    from kane_sim.identify.refinement import _torque_on_grid
    logged = load_motion(data, None, _base(rig))
    exact = _torque_on_grid(logged, times, step)
    spline = _torque_on_grid(motion, times, step)
    assert np.sqrt(np.mean((exact - spline) ** 2)) > 0.05 * np.sqrt(np.mean(exact ** 2))


def test_commands_that_do_not_give_the_effort_are_not_used(pd_rig):
    rig, data = pd_rig
    wrong = dict(data, command=data["command"] * 1.5)
    motion = load_motion(wrong, None, _base(rig))
    assert motion.held is None
    note = " ".join(motion.notes)
    assert "do not reproduce the recorded effort" in note and "effort samples used" in note
    late = dict(data, command_t=data["command_t"] + 1e4)
    motion = load_motion(late, None, _base(rig))
    assert motion.held is None and "fall outside the recording" in " ".join(motion.notes)
    servo = _base(rig).with_values({"command.mode": "position"})
    motion = load_motion(data, None, servo)
    assert motion.held is None and "servo's law makes the torque" in " ".join(motion.notes)


def test_the_held_torque_is_clamped_and_lapses_after_the_timeout():
    config = kane_sim.Config().with_values({"command.torque_limit": 5.0, "command.timeout": 0.5})
    # Commands at 0, 0.1 and 2 s (a gap of 1.9 s: the driver applies 0 from 0.6 s; and from
    # 2.5 s, no command following the last).
    commands = Commands([0.0, 0.1, 2.0], [1.0, 9.0, -2.0], "test")
    t = np.arange(0.0, 3.0, 0.01)
    effort = np.select([t < 0.1, t < 0.6, t < 2.0, t < 2.5], [1.0, 5.0, 0.0, -2.0], 0.0)
    held, note = held_torque(commands, t, effort, config)
    assert held is not None, note
    np.testing.assert_array_equal(held.at([0.05, 0.3, 0.59, 0.61, 1.9, 2.2, 2.6]),
                                  [1.0, 5.0, 5.0, 0.0, 0.0, -2.0, 0.0])
    assert math.isnan(held.at([-0.01])[0])  # before the first command: not known
    # NaN is refused by the driver (the torque in force stays): so it is here.
    commands = Commands([0.0, 0.1, 0.2], [1.0, float("nan"), 2.0], "test")
    held, _ = held_torque(commands, t[:30], np.where(t[:30] < 0.2, 1.0, 2.0), config)
    np.testing.assert_array_equal(held.at([0.15, 0.25]), [1.0, 2.0])


@pytest.mark.parametrize("change, words", [
    ({"command_t": [0.0, float("nan")], "command": [1.0, 2.0]}, "command_t[1] = nan"),
    ({"command_t": [0.0, 1.0, 0.5], "command": [1.0, 2.0, 3.0]}, "command_t[2] = 0.5 goes back"),
    ({"command_t": [0.0, 1.0], "command": [1.0]}, "command_t has 2 values and command 1"),
    ({"command_t": [0.0, 1.0]}, "need both command_t and command"),
    ({"command_t": [], "command": []}, "are empty"),
    ({"command_t": [0.0, 1.0], "command": [1.0, 1e308]}, "command[1] = 1e+308"),
    ({"command_t": [0.0, float("inf")], "command": [1.0, 2.0]}, "command_t[1] = inf"),
    ({"command_t": [0.0, 1.0], "command": [1.0, float("nan")]}, "command[1] = nan is not finite"),
    ({"command_t": [0.0, 1.0], "command": ["a", "b"]}, "command must be real numbers"),
    ({"command_t": np.zeros((2, 2)), "command": [1.0, 2.0]}, "command_t must be one-dimensional"),
    ({"command_t": None, "command": [1.0]}, "command_t must be real numbers, got None"),
    ({"setpoint_t": [0.0, 1.0], "setpoint": [1.0, -float("inf")]}, "setpoint[1] = -inf"),
])
def test_hostile_command_columns_are_refused_by_name(pd_rig, change, words):
    rig, data = pd_rig
    hostile = {k: v for k, v in data.items() if not k.startswith("command")}
    hostile.update(change)
    with pytest.raises(ValueError, match=None) as e:
        load_motion(hostile, None, _base(rig))
    assert words in str(e.value), str(e.value)


def _write_bag(path, data, stamp_of_tick, step, log_ticks, log_values, reading_ticks,
               seqs=None, log_topics=("/kane_sim/input_log",), stamp_ticks=None):
    """A bag as the node writes it: joint_states stamped stamp_of_tick(the tick each was published
    at), the input log's torque commands with their ticks (and seq numbers: 0, 1, ... unless
    given), stamped alike (or as at stamp_ticks), on each of `log_topics`."""
    import rosbag
    import rospy
    from sensor_msgs.msg import JointState
    from kane_sim.msg import InputLog
    names = kane_sim._core.joint_names()
    seqs = range(len(log_ticks)) if seqs is None else seqs
    stamp_ticks = log_ticks if stamp_ticks is None else stamp_ticks
    with rosbag.Bag(str(path), "w") as bag:
        for k, tick, at, value in zip(seqs, log_ticks, stamp_ticks, log_values):
            stamp = rospy.Time.from_sec(stamp_of_tick(at))
            msg = InputLog(seq=int(k), tick=int(tick), kind=InputLog.TORQUE, value=float(value))
            msg.header.stamp = stamp
            for topic in log_topics:
                bag.write(topic, msg, stamp)
        for i, tick in enumerate(reading_ticks):
            stamp = rospy.Time.from_sec(stamp_of_tick(tick))
            msg = JointState(name=list(names), position=[data["q1"][i], 0, 0, data["q2"][i]],
                             velocity=[data["u1"][i], 0, 0, data["u2"][i]],
                             effort=[data["applied_torque"][i], 0, 0, 0])
            msg.header.stamp = stamp
            bag.write("/joint_states", msg, stamp)


def test_a_bag_with_the_input_log_is_read_on_the_simulations_clock(pd_rig, tmp_path):
    """Wall-clock stamps with a 40 ms stall the node then caught up on: the input log's ticks put
    the readings back on the simulation's clock, and its commands give the torque."""
    rig, data = pd_rig
    step = 1.0 / rig.config()["simulation.physics_rate"]
    ticks = np.round(np.asarray(data["t"]) / step).astype(int)
    log_ticks = np.round(np.asarray(data["command_t"]) / step).astype(int)
    stall = int(round(10.0 / step))

    def wall(tick):  # real time 1.001 s a simulated second; 40 ms behind from 10 s, caught up
        behind = 0.04 if stall <= tick < stall + 50 else \
            0.04 - 0.0008 * (tick - stall - 50) if stall + 50 <= tick < stall + 100 else 0.0
        return 1.8e9 + tick * step * 1.001 + behind
    bag = tmp_path / "closed_loop.bag"
    _write_bag(bag, data, wall, step, log_ticks, data["command"], ticks)
    motion = load_motion(str(bag), None, _base(rig))
    notes = " ".join(motion.notes)
    assert "simulation's clock" in notes and "/kane_sim/input_log" in notes, notes
    assert motion.held is not None
    # The readings' instants on the simulation's clock: the arrival ticks' times (regular within
    # the sensors' latency jitter, here none), whatever the wall clock did.
    # (the last reading came after the last logged command: outside the log's span, left out)
    assert len(ticks) - 1 <= len(motion) <= len(ticks)
    np.testing.assert_allclose(motion.t + motion.start, ticks[:len(motion)] * step, atol=1.5e-3)
    # Without the input log the same stamps are the wall clock's: the stall shows.
    stamps = np.array([wall(k) for k in ticks])
    assert np.max(np.abs(np.diff(stamps) - np.diff(ticks) * step)) > 0.03


@pytest.fixture(scope="module")
def servo_rig():
    """Seed 5's position servo driven by setpoint steps (every 0.3-1.5 s), read at 200 Hz for 20
    s, with the setpoints as logged: where each took effect."""
    rig = rigs.draw(5, regime="servo", duration=20.0)
    rig.sensors["sensors.rate"] = 200.0
    step = 1.0 / rig.config()["simulation.physics_rate"]
    n = int(round((rig.start + rig.duration) / step))
    rng = np.random.default_rng(5)
    edges = np.cumsum(rng.uniform(0.3, 1.5, size=100))
    setpoints = rng.uniform(-1.5, 2.5, size=100)[np.searchsorted(edges, step * np.arange(n))]
    data = rigs.record(rig, drive=setpoints)
    changed = np.flatnonzero(np.diff(setpoints, prepend=np.nan) != 0)
    data.update(setpoint_t=step * changed, setpoint=setpoints[changed])
    return rig, data


def test_a_servo_is_replayed_with_its_law_from_the_logged_setpoints(servo_rig):
    rig, data = servo_rig
    fit = ki.identify(data, _base(rig), validate=False)
    assert fit.refusal is None
    assert any("position servo replayed with its law" in n for n in fit.notes), fit.notes
    assert fit.refined["converged"] and fit.refined["torque_sampling"] == (0.0, 0.0)
    rows = rigs.score(rig, fit)
    for name in MASSES_AND_K + ("mechanism.rod_inertia",):
        # From the effort samples (the torque stepping with the setpoints between readings) the
        # rod's inertia was 24 % off on 30 s of this rig; with the law, 0.002 %.
        assert abs(rows[name]["error"]) < 0.005, (name, rows[name])
        assert rows[name]["z"] < 3.5, (name, rows[name])
    # The offset of the effort reading moves nothing in a servo's replay: the least squares'.
    assert fit.std_errors["torque_offset"] > 0


def test_setpoints_a_replay_cannot_use_are_said(servo_rig):
    rig, data = servo_rig
    integral = _base(rig).with_values({"command.position_ki": 5.0})
    motion = load_motion(data, None, integral)
    assert motion.servo is None and "integral" in " ".join(motion.notes)
    late = dict(data, setpoint_t=data["setpoint_t"] + 1.0)
    motion = load_motion(late, None, _base(rig))
    assert motion.servo is None and "start after the recording" in " ".join(motion.notes)
    effort = _base(rig).with_values({"command.mode": "effort"})
    motion = load_motion(data, None, effort)
    assert motion.servo is None and "command.mode is effort" in " ".join(motion.notes)
    with pytest.raises(ValueError, match=r"setpoint\[0\] = 1e\+300"):
        load_motion(dict(data, setpoint=np.full(len(data["setpoint"]), 1e300)), None, _base(rig))


def test_excite_designs_a_servos_setpoints_with_the_servo_in_the_loop(tmp_path):
    import subprocess
    base = kane_sim.Config().with_values({"command.mode": "position",
                                          "command.position_kp": 60.0,
                                          "command.position_kd": 4.0})
    t, setpoint, condition = ki.excitation(base, 10.0, rate=250.0)
    assert len(t) == 2500 and 0.1 < np.max(np.abs(setpoint)) <= 1.5
    assert condition < 1e3  # every parameter the mechanism can tell, told well
    # Played on the base with the servo in the loop, the sliders stay apart and the crank moves.
    sim = kane_sim.Simulator(base)
    run = sim.run(10.0, torque=np.repeat(setpoint, 4), output_rate=100.0)
    assert np.ptp(run.q[:, 0]) > 0.5
    # The CLI writes it as the servo's setpoint, and says how to play it.
    path = tmp_path / "base.yaml"
    path.write_text(base.yaml())
    out = tmp_path / "setpoints.csv"
    r = subprocess.run([tool("identify"), "--excite", "4", "--config", str(path), "-o",
                        str(out)], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert out.read_text().startswith("t,setpoint\n") and "command.mode position" in r.stdout


def test_excite_designs_the_pd_controllers_setpoint_table_with_its_law_in_the_loop(tmp_path):
    import subprocess
    from conftest import config_path
    # The example controller's law is a position servo's: its gains, the smaller torque limit.
    gains = {"kp": 200.0, "kd": 12.0, "torque_limit": 80.0, "setpoint": 1.0, "stamped": True}
    base = ki.pd_controller_base(kane_sim.Config(), gains)
    assert (base["command.mode"], base["command.position_kp"], base["command.position_kd"],
            base["command.position_ki"], base["command.torque_limit"]) == \
        ("position", 200.0, 12.0, 0.0, 50.0)
    # The CLI designs it from config/controller.yaml and says how the controller plays it.
    out = tmp_path / "setpoints.csv"
    r = subprocess.run([tool("identify"), "--excite", "6", "--controller",
                        config_path("controller.yaml"), "-o", str(out)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert "pd_controller _setpoint_table:=%s" % out in r.stdout
    t, setpoint = np.loadtxt(out, delimiter=",", skiprows=1, unpack=True)
    assert t[0] == 0.0 and t[-1] > 5.9 and 0.1 < np.max(np.abs(setpoint)) <= 1.5
    # One truth: the CLI's table is Python's excitation() on pd_controller_base() with the same
    # file's gains, to the digits it writes (t to 1e-6 s, the setpoint to 12 significant).
    import yaml
    with open(config_path("controller.yaml")) as f:
        gains_file = yaml.safe_load(f)
    py_t, py_setpoint, _ = ki.excitation(ki.pd_controller_base(kane_sim.Config(), gains_file),
                                         6.0, seed=0, rate=1000.0)
    np.testing.assert_allclose(t, py_t, rtol=0, atol=5e-7)
    np.testing.assert_allclose(setpoint, py_setpoint, rtol=1e-11, atol=0)
    # Played through the controller's law (its readings at 100 Hz, its clamp), the crank moves
    # and the sliders stay apart.
    law = kane_sim.Config().with_values({"command.torque_limit": 50.0})
    sim = kane_sim.Simulator(law)
    gap = []
    for k in range(600):
        q1, u1 = sim.state[0], sim.state[2]
        sp = setpoint[np.searchsorted(t, k / 100.0, side="right") - 1]
        torque = float(np.clip(500.0 * (sp - q1) - 30.0 * u1, -50.0, 50.0))
        run = sim.run(0.01, torque=torque, output_rate=100.0)
        gap.append(float(np.min(run["slider_separation"])))
    assert min(gap) > law["contact.gap"]


def test_the_gains_defaults_are_the_controllers_own():
    # One truth: a gains file that leaves a key out gets what pd_controller would use, its
    # PdGains defaults, which its usage prints.
    import re
    import subprocess
    usage = subprocess.run([tool("pd_controller"), "--help"], capture_output=True, text=True,
                           timeout=60).stdout
    for key, value in ki.excitation.__globals__["PD_CONTROLLER_GAINS"].items():
        shown = re.search(r"_%s:=([-0-9.e+]+)" % key, usage)
        assert shown and float(shown.group(1)) == value, (key, usage)


@pytest.mark.parametrize("text, words", [
    ("kp: .nan\n", "the controller's kp must be a finite number >= 0, got nan"),
    ("kd: -1e308\n", "the controller's kd must be a finite number >= 0, got -1e+308"),
    ("kp: fast\n", "the controller's kp must be a finite number >= 0, got 'fast'"),
    ("kpp: 3\n", "the controller's 'kpp' is not one of its parameters"),
    ("kp: 0\n", "the controller's kp is 0: its setpoint cannot move the crank"),
    ("- 1\n", "must be a mapping of its parameters"),
    ("", "must be a mapping of its parameters (kp, kd, ki, torque_limit), got None"),
    ("kp: [1\n", "not YAML: while parsing"),
    ("law: upright.yaml\n", "is a state feedback, which has no setpoint"),
    # What the controller refuses (pd_controller's own checks), and what the servo cannot take.
    ("setpoint: .nan\n", "the controller's setpoint must be a finite number, got nan"),
    ("setpoint: 1e308\n", "the controller's setpoint 1e+308 rad is beyond a million turns"),
    ("stamped: \"yes\"\n", "the controller's stamped must be true or false, got 'yes'"),
    ("setpoint_table: 5\n", "the controller's setpoint_table must be a file path, got 5"),
    ("torque_limit: 0\n", "the controller's torque_limit is 0"),
    ("kp: 1e308\n", "the controller's kp as the position servo's: config key "
                     "'command.position_kp' must be in [0, 1e+06], got 1e+308"),
])
def test_a_controller_file_that_is_not_the_pds_gains_is_named(tmp_path, text, words):
    import subprocess
    path = tmp_path / "gains.yaml"
    path.write_text(text)
    r = subprocess.run([tool("identify"), "--excite", "4", "--controller", str(path), "-o",
                        str(tmp_path / "sp.csv")], capture_output=True, text=True, timeout=120)
    assert r.returncode == 1 and words in r.stderr, r.stderr  # a bad config: exit 1
    assert "--controller %s" % path in r.stderr and not (tmp_path / "sp.csv").exists()


@pytest.mark.parametrize("args, words", [
    (["--controller", "/dev/zero", "--excite", "4"], "not a regular file"),
    (["--controller", "/nonexistent.yaml", "--excite", "4"], "no such file"),
    (["--controller", "CONFIG"], "--controller is for --excite"),
    (["--controller", "OUT", "--excite", "4"], "is the --controller file: it would be overwritten"),
])
def test_controller_arguments_are_checked_before_any_work(tmp_path, args, words):
    import subprocess
    from conftest import config_path
    out = tmp_path / "sp.csv"
    out.write_text("kp: 500\n")
    args = [config_path("controller.yaml") if a == "CONFIG" else str(out) if a == "OUT" else a
            for a in args]
    r = subprocess.run([tool("identify")] + args + ["-o", str(out)],
                       capture_output=True, text=True, timeout=60)
    assert r.returncode == 2 and words in r.stderr, r.stderr
    assert out.read_text() == "kp: 500\n"  # nothing written


def test_a_simulate_bag_of_a_servo_replays_its_law_from_the_bags_input_log(tmp_path):
    """simulate --bag logs its inputs as the node does: a position servo's bag (setpoint steps,
    sensors at 200 Hz with sensors.yaml's noise, latency and jitter) is fitted through the
    servo's law, its stamps put on the simulation's clock by the log."""
    import subprocess
    import yaml
    from conftest import config_path
    cfg = yaml.safe_load(open(config_path()))
    cfg["sensors"].update(yaml.safe_load(open(config_path("sensors.yaml")))["sensors"])
    cfg["sensors"]["rate"] = 200.0
    cfg["command"].update(mode="position", position_kp=60.0, position_kd=4.0)
    cfg["mechanism"].update(rod_mass=1.2, spring_stiffness=240.0)
    rig = tmp_path / "rig.yaml"
    rig.write_text(yaml.safe_dump(cfg))
    rng = np.random.default_rng(3)
    t = np.cumsum(np.r_[0.0, rng.uniform(0.3, 1.5, 40)])
    steps = tmp_path / "steps.csv"
    steps.write_text("t,setpoint\n" + "".join("%r,%r\n" % row
                                              for row in zip(t, rng.uniform(-1.5, 2.5, len(t)))))
    bag = tmp_path / "servo.bag"
    subprocess.run([tool("simulate"), "--config", str(rig), "--duration", "20", "--torque-csv",
                    str(steps), "--bag", str(bag)], check=True, capture_output=True, timeout=120)
    cfg["mechanism"].update(rod_mass=1.0, spring_stiffness=200.0)
    cfg["sensors"]["enabled"] = False
    fit = ki.identify(str(bag), kane_sim.Config(cfg), validate=False)
    notes = " ".join(fit.notes)
    assert "simulation's clock" in notes and "position servo replayed with its law" in notes
    assert fit.refusal is None and fit.refined["converged"]
    assert fit.estimates["mechanism.rod_mass"] == pytest.approx(1.2, rel=0.01)
    assert fit.estimates["mechanism.spring_stiffness"] == pytest.approx(240.0, rel=0.01)


@pytest.mark.parametrize("fault, words", [
    ("tick_back", "the input log is not used: its tick goes back at message 1000"),
    ("seq_gap", "inputs are missing from it (seq 1500 follows 999"),
    ("tick_jump", "of simulation after the one before"),
    ("two_logs", "the bag has 2 input logs (/kane_sim/input_log, /other/kane_sim/input_log)"),
    ("other_clock", "span less than half the readings"),
])
def test_an_input_log_that_cannot_be_trusted_is_not_used_and_said(pd_rig, tmp_path, fault,
                                                                 words):
    rig, data = pd_rig
    step = 1.0 / rig.config()["simulation.physics_rate"]
    ticks = np.round(np.asarray(data["t"]) / step).astype(int)
    log_ticks = np.round(np.asarray(data["command_t"]) / step).astype(int)
    stamp_ticks = log_ticks.copy()  # the stamps as the node took them
    seqs = np.arange(len(log_ticks))
    topics = ("/kane_sim/input_log",)
    wall = (lambda tick: 1.8e9 + tick * step)
    if fault == "tick_back":
        log_ticks[1000] -= 5000
    elif fault == "seq_gap":
        seqs[1000:] += 500
    elif fault == "tick_jump":
        log_ticks[1000:] += 10 ** 9
    elif fault == "two_logs":
        topics = ("/kane_sim/input_log", "/other/kane_sim/input_log")
    bag = tmp_path / "faulty.bag"
    _write_bag(bag, data, wall, step, log_ticks, data["command"], ticks, seqs, topics,
               stamp_ticks)
    if fault == "other_clock":  # the log stamped on a clock from 0, the readings from 1.8e9
        bag.unlink()
        _write_bag(bag, data, wall, step, [], [], ticks)
        import rosbag
        import rospy
        from kane_sim.msg import InputLog
        with rosbag.Bag(str(bag), "a") as b:
            for k, (tick, value) in enumerate(zip(log_ticks, data["command"])):
                msg = InputLog(seq=k, tick=int(tick), kind=InputLog.TORQUE, value=float(value))
                msg.header.stamp = rospy.Time.from_sec(tick * step + 1e-3)
                b.write("/kane_sim/input_log", msg, msg.header.stamp)
    motion = load_motion(str(bag), None, _base(rig))
    notes = " ".join(motion.notes)
    assert words in notes, notes
    assert motion.held is None and motion.servo is None


def test_a_servo_whose_gains_are_not_the_rigs_is_refused(servo_rig):
    """With kp and kd 1.5 times the rig's the law still follows the positions, with every mass
    off; the law's torque against the recorded effort tells (a median 0.1-0.6 % of the effort
    with the rig's gains, 40-50 % with these)."""
    rig, data = servo_rig
    base = _base(rig)
    wrong = base.with_values({"command.position_kp": 1.5 * base["command.position_kp"],
                              "command.position_kd": 1.5 * base["command.position_kd"]})
    fit = ki.identify(data, wrong, validate=False, holdout=0)
    assert fit.refusal and "servo's law with the config's gains" in fit.refusal, fit.refusal
    assert "servo replayed with its law gives the recorded effort" in fit.report()


def test_excite_refuses_a_servo_that_cannot_move_the_crank():
    base = kane_sim.Config().with_values({"command.mode": "position", "command.position_kp": 0.0})
    with pytest.raises(ValueError, match=r"command.position_kp = 0: the position servo"):
        ki.excitation(base, 10.0)
