"""Recorded motion in: a bag's joint_states, a CSV (simulate's or a rig's), arrays or a Result,
checked and put on a uniform time grid (Motion)."""
import math
import os
from collections.abc import Mapping

import numpy as np

from kane_sim import _core, bags, columns
from kane_sim.identify.commands import (commands_from_columns, held_setpoints, held_torque,
                                        on_tick_clock)


# A file larger than this is refused before it is read (a 60 s, 1 kHz CSV of every column is
# ~60 MB; a bag of an hour's joint_states at 1 kHz ~400 MB).
MAX_FILE_BYTES = 2 << 30


# |value| beyond this in SI units is no rig's reading (1e308 would overflow the regressor).
MAX_MAGNITUDE = 1e6


MIN_SAMPLES = 50
MIN_SAMPLE_STEP = 1e-6  # [s] a median step below it is not a rig's sampling (stamps in ns?)
MAX_GAP_STEPS = 20      # a gap of more median steps (and over 0.1 s) is refused, not resampled


class Motion:
    """Recorded motion on a uniform time grid: t (N,), q (N, 2) = (q1, q2), u (N, 2) or None when
    the data has no velocities, torque (N,) the delivered M_m; notes: what was done to the data
    (resampling). A file's times count from its first sample (t[0] = 0; its stamp is `start`):
    a bag's stamps (1e9 s and more) keep only 1e-7 s of precision, and the fit's lag and
    interpolation need far finer than that."""

    def __init__(self, t, q, u, torque, source="arrays", notes=(), start=0.0, commands=None):
        self.t, self.q, self.u, self.torque = t, q, u, torque
        self.source = source
        self.notes = list(notes)
        self.start = start
        # The logged torque commands (commands.Commands, on this clock: t[0] = 0) or None, and
        # the torque they held once checked against the effort samples (identify sets it).
        self.commands = commands
        self.held = None
        # In a servo mode: the setpoints the servo held (commands.held_setpoints) or None; the
        # replays then run the servo's law on the model's state.
        self.servo = None

    def __len__(self):
        return len(self.t)

    @property
    def rate(self):
        return (len(self.t) - 1) / (self.t[-1] - self.t[0])


def _check_file(path):
    if not os.path.exists(path):
        raise ValueError("data: %s does not exist" % path)
    if not os.path.isfile(path):
        raise ValueError("data: %s is not a regular file" % path)
    size = os.path.getsize(path)
    if size > MAX_FILE_BYTES:
        raise ValueError("data: %s is %d bytes, more than the %d this tool reads"
                         % (path, size, MAX_FILE_BYTES))
    if size == 0:
        raise ValueError("data: %s is empty" % path)


def _columns_from_mapping(data, source):
    data = columns.renamed_columns(dict(data))  # "torque" of an older CSV or script

    def column(name, required=True):
        if name not in data:
            if required:
                raise ValueError("data (%s) has no column '%s' (it needs t, q1, q2, applied_torque; u1 and "
                                 "u2 are used when present)" % (source, name))
            return None
        raw = np.asarray(data[name])
        if raw.dtype.kind not in "iuf":  # complex (its imaginary part lost), bools, text
            raise ValueError("data (%s): column '%s' must be real numbers, got %s"
                             % (source, name, raw.dtype))
        values = raw.astype(float)
        if values.ndim != 1:
            raise ValueError("data (%s): column '%s' must be one-dimensional, got shape %s"
                             % (source, name, values.shape))
        return values
    cols = {n: column(n) for n in ("t", "q1", "q2", "applied_torque")}
    u1, u2 = column("u1", False), column("u2", False)
    lengths = {n: len(v) for n, v in cols.items()}
    if u1 is not None and u2 is not None:
        cols["u1"], cols["u2"] = u1, u2
        lengths.update(u1=len(u1), u2=len(u2))
    if len(set(lengths.values())) != 1:
        raise ValueError("data (%s): columns of different lengths %s" % (source, lengths))
    return cols


def _read_csv(path):
    import csv
    try:
        with open(path, newline="") as f:
            header = next(csv.reader(f), None)
            has_rows = next(f, None) is not None
    except UnicodeDecodeError:
        raise ValueError("data: %s is neither a bag (.bag) nor a text CSV (it is binary)"
                         % path) from None
    if not header:
        raise ValueError("data: %s has no header line (simulate --csv writes one)" % path)
    if not has_rows:
        raise ValueError("data: %s has a header and no rows" % path)
    try:
        values = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    except ValueError as e:
        raise ValueError("data: %s: %s" % (path, e)) from None
    if values.shape[1] != len(header):
        raise ValueError("data: %s has %d columns in its header and %d in its rows"
                         % (path, len(header), values.shape[1]))
    return {name.strip(): values[:, i] for i, name in enumerate(header)}


def _read_bag(path, topic=None):
    """A bag's JointState topic: rosbag's C++ reader (kane_sim._bag), ~1 us a message, the
    columns as arrays (an hour at 1 kHz: 3.6 million messages in seconds, 170 MB)."""
    try:
        types = bags.topic_types(path)
        topic = bags.choose_topic(types, path, "sensor_msgs/JointState", "joint_states", topic,
                                  flag="topic= (identify --topic)")
        names = _core.joint_names()
        from kane_sim import _bag
        c = _bag.read_joint_states(path, topic, names[0], names[3])
    except ValueError as e:
        raise ValueError("data: %s" % e) from None
    out = {"t": c["t"], "q1": c["position_a"], "q2": c["position_b"],
           "applied_torque": c["effort_a"]}
    if "velocity_a" in c:
        out.update(u1=c["velocity_a"], u2=c["velocity_b"])
    source = "%s %s" % (path, topic)
    if c["unstamped"]:  # one clock for all: the bag's receive times
        source += " (%d of its %d messages have no header stamp: the bag's receive times used)" \
            % (c["unstamped"], len(c["t"]))
    else:  # the node's ~input_log is stamped on its joint_states' clock
        out.update(_input_log_commands(path, types))
    return out, source


# InputLog.kind of a torque command and of a servo setpoint (msg/InputLog.msg)
INPUT_LOG_TORQUE, INPUT_LOG_SETPOINT = 0, 1


def _input_log_commands(path, types):
    """{"clock_t", "clock_tick"}: the stamps and ticks of every input the bag's one
    kane_sim/InputLog topic (the node's ~input_log) holds, {"command_t", "command",
    "command_tick", "command_source"}: its torque commands, and the same of "setpoint": its servo
    setpoints; {} when the bag has no such topic (or several: which node's would be a
    guess)."""
    logs = bags.topics_of_type(types, "kane_sim/InputLog")
    if len(logs) > 1:
        return {"log_note": "the bag has %d input logs (%s): which is this rig's is a guess, "
                            "none is used; cut the others out (rosbag filter)"
                            % (len(logs), ", ".join(logs))}
    if not logs:
        return {}
    from kane_sim import _bag
    c = _bag.read_input_log(path, logs[0])
    out = {"clock_t": c["t"], "clock_tick": c["tick"], "clock_seq": c["seq"]}
    for name, kind in (("command", INPUT_LOG_TORQUE), ("setpoint", INPUT_LOG_SETPOINT)):
        rows = c["kind"] == kind
        if np.any(rows):
            out.update({name + "_t": c["t"][rows], name: c["value"][rows],
                        name + "_tick": c["tick"][rows], name + "_source": logs[0]})
    return out


def load_motion(data, topic=None, config=None):
    """A Motion from a bag (joint_states: positions, velocities when present, effort = the
    delivered torque; the node's ~input_log when it has one), a CSV of simulate's columns (t,
    q1, q2, u1, u2, torque), a mapping of arrays with those names (a kane_sim Result too;
    command_t and command: the torque commands as a driver received them) or a Motion. With the
    rig's `config` (a Config), a bag's input log puts the stamps on the simulation's clock and
    the logged commands give the torque between samples (commands.held_torque). ValueError names
    what is wrong."""
    if isinstance(data, Motion):
        return data
    if isinstance(data, (str, os.PathLike)):
        path = os.fspath(data)
        _check_file(path)
        if path.endswith(".bag"):
            raw, source = _read_bag(path, topic)
        elif topic is not None:
            raise ValueError("data: topic %s is for a bag; %s is read as a CSV (a bag's name ends "
                             "in .bag)" % (topic, path))
        else:
            raw, source = _read_csv(path), path
    elif isinstance(data, Mapping):
        raw, source = data, "arrays"
    else:
        raise TypeError("data must be a bag or CSV path, a mapping of arrays or a Motion, got %s"
                        % type(data).__name__)
    cols = _columns_from_mapping(raw, source)
    commands = commands_from_columns(raw, source)
    setpoints = commands_from_columns(raw, source, "setpoint")
    notes = []
    notes += [raw["log_note"]] if "log_note" in raw else []
    if config is not None and "clock_t" in raw:
        cols, (commands, setpoints), note, used = on_tick_clock(
            cols, (raw["clock_t"], raw["clock_tick"], raw["clock_seq"]), [commands, setpoints],
            config)
        regular = None if not used else \
            _regular_despite_jitter(cols["t"], np.diff(cols["t"]), on_tick_clock=True)
        if regular is not None:
            note += ("; the readings a regular %.4g s sampling on it (99 %% within %.3g ms, no "
                     "reading lost), taken as that" % (regular[0], 1e3 * regular[0] / 3))
            cols = dict(cols, t=regular[2])
        notes += [note] if note else []
    held, servo = None, None
    if config is not None:
        held, note = held_torque(commands, cols["t"], cols["applied_torque"], config)
        notes += [note] if note else []
        servo, note = held_setpoints(setpoints, cols["t"], config)
        notes += [note] if note else []
    motion = _uniform(cols, source)
    motion.notes = notes + motion.notes
    motion.commands = commands
    for drive in (held, servo, commands, setpoints):
        if drive is not None:  # onto the motion's clock (its first sample at 0)
            if hasattr(drive, "changes"):
                drive.changes = drive.changes - motion.start
            else:
                drive.t = drive.t - motion.start
    motion.held, motion.servo = held, servo
    return motion


def _regular_despite_jitter(t, dt, on_tick_clock=False):
    """(period, largest stray, the regular stamps) when stamps that repeat or go back are a
    regular sampling's, jittered by less than a period: the line fitted to them by index, when
    no reading was lost (a lost reading moves every stamp after it a period off the line: the
    stamps' running mean about it would step by a period); else None. on_tick_clock: stamps put
    on the simulation's clock by an input log (on_tick_clock), known only to within the log's
    interval where the node fell behind and caught up (a 30 ms stall left one reading 26 ms off
    the line, the 99th percentile 3 ms): the 99th percentile of the strays must be below a third
    of a period, and no lost reading."""
    if not np.any(dt > 0):
        return None
    k = np.arange(len(t))
    slope, offset = np.polyfit(k, t - t[0], 1)
    residual = t - t[0] - (offset + slope * k)
    stray = float(np.max(np.abs(residual)))
    # The jitter's own spread (a robust sigma): one stamp a period off in an otherwise exact
    # recording is a wrong stamp, not a jitter.
    spread = 1.4826 * float(np.median(np.abs(residual - np.median(residual))))
    # The running mean over 101 readings: the jitter averages out (its sd / 10), a lost reading
    # steps it by a period.
    width = min(101, len(t))
    running = np.convolve(residual, np.ones(width) / width, mode="valid")
    if on_tick_clock:
        within = float(np.percentile(np.abs(residual), 99)) < slope / 3
    else:
        within = stray < slope and stray <= 5.0 * spread
    if not (slope > 0 and within and np.ptp(running) < 0.5 * slope):
        return None
    return float(slope), stray, t[0] + offset + slope * k


def _uniform(cols, source):
    n = len(cols["t"])
    if n < MIN_SAMPLES:
        raise ValueError("data (%s): %d samples, too short to identify anything (at least %d)"
                         % (source, n, MIN_SAMPLES))
    for name, values in cols.items():
        bad = np.flatnonzero(~np.isfinite(values))
        if bad.size:
            raise ValueError("data (%s): %s[%d] = %r is not finite (%d such rows)"
                             % (source, name, bad[0], values[bad[0]], bad.size))
        big = np.flatnonzero(np.abs(values) > MAX_MAGNITUDE)
        if big.size and name != "t":
            raise ValueError("data (%s): %s[%d] = %r is beyond any rig's reading (|x| > %g)"
                             % (source, name, big[0], values[big[0]], MAX_MAGNITUDE))
    start = float(cols["t"][0])
    with np.errstate(over="ignore", invalid="ignore"):
        cols = dict(cols, t=cols["t"] - start)
        t = cols["t"]
        dt = np.diff(t)
    if not (np.isfinite(t[-1]) and np.all(np.isfinite(dt))):
        raise ValueError("data (%s): time runs from %r to %r: a span a double cannot hold"
                         % (source, start, float(cols["t"][-1]) + start))
    notes = []
    bad = np.flatnonzero(dt <= 0)
    if bad.size:
        regular = _regular_despite_jitter(t, dt)
        if regular is None:
            i = bad[0]
            what = "repeats" if dt[i] == 0 else "goes backward from %r" % (t[i] + start)
            raise ValueError("data (%s): time t[%d] = %r %s (%d such steps): stamps must "
                             "increase" % (source, i + 1, t[i + 1] + start, what, bad.size))
        # Readings stamped when they arrived, with a jitter as long as their period (a sensor at
        # 500 Hz with 2 ms of it): two in one physics step share a stamp, or swap. None lost, so
        # the k-th reading is the k-th sample of the regular sampling the stamps scatter about.
        notes.append("%d stamps repeat or go back within the jitter (up to %.3g ms about a "
                     "regular %.4g s sampling, no reading lost): taken as that sampling"
                     % (bad.size, 1e3 * regular[1], regular[0]))
        cols = dict(cols, t=regular[2])
        t = cols["t"]
        dt = np.diff(t)
    step = float(np.median(dt))
    if step < MIN_SAMPLE_STEP:
        raise ValueError("data (%s): samples %.3g s apart (the median step): faster than any "
                         "rig's sensors; are the stamps in seconds?" % (source, step))
    gap = int(np.argmax(dt))
    if dt[gap] > MAX_GAP_STEPS * step and dt[gap] > 0.1:
        # A paused recording or one wrong stamp: resampling would make up the motion between.
        raise ValueError("data (%s): a gap of %.6g s between t[%d] = %r and t[%d] = %r (the "
                         "median step is %.3g s): a paused recording or a wrong stamp; cut the "
                         "data there" % (source, dt[gap], gap, t[gap] + start, gap + 1,
                                         t[gap + 1] + start, step))
    if np.max(np.abs(dt - step)) > 1e-6 * step:
        # Jittered stamps (a reading stamped when it arrived) of a regular sampling: a line
        # fitted to the stamps is the sampling, when no stamp strays a third of a period from it.
        k = np.arange(n)
        slope, offset = np.polyfit(k, t - t[0], 1)
        stray = np.max(np.abs(t - t[0] - (offset + slope * k)))
        if stray < slope / 3:
            notes.append("stamps jitter up to %.3g ms about a regular %.4g s sampling: taken as "
                         "regular" % (1e3 * stray, slope))
            cols = dict(cols, t=t[0] + offset + slope * k)
        else:
            # Irregular sampling (a dropped message, a pause): linear interpolation onto the
            # median step.
            grid = t[0] + step * np.arange(int(math.floor((t[-1] - t[0]) / step + 1e-9)) + 1)
            notes.append("resampled %d irregular stamps (steps %.4g..%.4g s) onto a %.4g s grid"
                         % (n, dt.min(), dt.max(), step))
            cols = {key: (grid if key == "t" else np.interp(grid, t, v))
                    for key, v in cols.items()}
    q = np.column_stack([cols["q1"], cols["q2"]])
    u = np.column_stack([cols["u1"], cols["u2"]]) if "u1" in cols else None
    return Motion(cols["t"], q, u, cols["applied_torque"], source, notes, start)
