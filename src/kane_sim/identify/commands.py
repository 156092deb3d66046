"""The torque as the driver held it: a recording's logged commands (the node's ~input_log, or a
script's own) turned into the torque at any instant, exactly, where the effort samples give it
only at theirs.

A PD loop at 100 Hz changes the torque between two 100 Hz readings; the replay's cubic spline
through the effort samples then drives the model with a torque that was never applied (a floor
of 0.03-0.19 rad on live recordings). The log says when each command took effect: held from
there, clamped to the torque limit, zero after the command timeout, it is the torque the model
was driven by. It is used only when it reproduces the recorded effort samples (held_torque's
check), so a log that is not this run's, or a drive it cannot describe (a motor line), leaves
the effort samples in charge and says why. A servo's logged setpoints are held the same way
(held_setpoints), for its law to make the torque in the replays.
"""
import numpy as np

# A recorded effort sample matches the held torque when they differ by no more than this (the
# node publishes the double it applied; a CSV's printed digits round it).
MATCH_TOLERANCE = 1e-6
# [s] an effort sample may be stamped this far from the instant its torque took effect (a
# reading stamped on arrival: latency and jitter), so it is matched against every command in
# force within this window of its stamp.
MATCH_WINDOW = 0.01
# The share of effort samples the held torque must reproduce for the log to be used.
MATCH_SHARE = 0.99


class Commands:
    """Torque commands as a driver received them: t (N,) the instants [s] on the recording's
    clock, value (N,) [N m] as received; tick (N,) the physics tick each arrived at, when the
    log says (the node's ~input_log), else None. source: where they came from."""

    def __init__(self, t, value, source, tick=None):
        self.t = np.asarray(t, dtype=float)
        self.value = np.asarray(value, dtype=float)
        self.source = source
        self.tick = None if tick is None else np.asarray(tick, dtype=float)


class HeldCommand:
    """The torque (or a servo's setpoint) in force at any instant, from a Commands (changes: the
    instants it changed, torque: its value from each on); before the first command it is
    unknown."""

    def __init__(self, changes, torque, source):
        self.changes, self.torque, self.source = changes, torque, source

    def at(self, times):
        """The torque in force at `times` (the value of the last change at or before each); NaN
        before the first change."""
        index = np.searchsorted(self.changes, np.asarray(times) + 1e-12, side="right") - 1
        out = self.torque[np.clip(index, 0, len(self.torque) - 1)].astype(float)
        out[index < 0] = np.nan
        return out


def _held(commands, config, step):
    """The changes of the torque the driver applied: each finite command from the physics tick
    it was received at (plus sensors.command_latency when the sensors are on), clamped to
    command.torque_limit, and 0 from command.timeout after a command no other followed."""
    keep = np.isfinite(commands.value)  # the driver refuses NaN and inf: the torque stays
    t, value = commands.t[keep], commands.value[keep]
    if config["sensors.enabled"]:
        t = t + step * round(config["sensors.command_latency"] / step)
    limit = config["command.torque_limit"]
    value = np.clip(value, -limit, limit)
    timeout = config["command.timeout"]
    if timeout > 0 and len(t):
        lapsed = np.flatnonzero(np.diff(np.append(t, np.inf)) > timeout + step)
        t = np.insert(t, lapsed + 1, t[lapsed] + timeout)
        value = np.insert(value, lapsed + 1, 0.0)
    return t, value


def _unmatched(held, t, effort):
    """The effort samples (indices) no command in force within MATCH_WINDOW of their stamp
    explains."""
    lo = np.searchsorted(held.changes, t - MATCH_WINDOW, side="right") - 1
    hi = np.searchsorted(held.changes, t + MATCH_WINDOW, side="right") - 1
    matched = np.zeros(len(t), dtype=bool)
    scale = MATCH_TOLERANCE * np.maximum(1.0, np.abs(effort))
    for offset in range(int(np.max(hi - lo, initial=0)) + 1):
        index = lo + offset
        inside = (index >= 0) & (index <= hi)
        value = held.torque[np.clip(index, 0, len(held.torque) - 1)]
        matched |= inside & (np.abs(value - effort) <= scale)
    return np.flatnonzero(~matched)


def held_torque(commands, t, effort, config):
    """(HeldCommand or None, note): the torque the logged `commands` held, when it reproduces
    MATCH_SHARE of the effort samples (`effort` at stamps `t`, as recorded: before any
    resampling) from the first command on; else None and the note saying why the effort samples
    drive the replays."""
    if commands is None:
        return None, None
    mode = config["command.mode"]
    if mode != "effort":
        return None, ("the recording's %d logged commands are not used: in command.mode %s the "
                      "servo's law makes the torque, and the effort samples give it"
                      % (len(commands.t), mode))
    if config["command.motor_no_load_speed"] > 0:
        return None, ("the logged commands are not used: a motor line "
                      "(command.motor_no_load_speed) makes the torque depend on the speed")
    step = 1.0 / config["simulation.physics_rate"]
    changes, torque = _held(commands, config, step)
    if not len(changes) or changes[0] > t[-1] or changes[-1] < t[0]:
        return None, ("the %d logged commands (%s) fall outside the recording's %.6g..%.6g s: "
                      "another run's, or another clock's; the effort samples used"
                      % (len(commands.t), commands.source, t[0], t[-1]))
    held = HeldCommand(changes, torque, commands.source)
    after = t >= changes[0] + MATCH_WINDOW
    if np.count_nonzero(after) < 0.5 * len(t):
        return None, ("the logged commands (%s) start %.4g s into the recording, after half its "
                      "samples: the effort samples used" % (commands.source, changes[0] - t[0]))
    first = t[0]
    t, effort = t[after], effort[after]
    unmatched = _unmatched(held, t, effort)
    if len(unmatched) > (1.0 - MATCH_SHARE) * len(t):
        k = unmatched[0]
        return None, ("the logged commands (%s) do not reproduce the recorded effort (%d of %d "
                      "samples differ; the first %.6g s into it: effort %.6g N m, the commands "
                      "in force %.6g N m): the effort samples used"
                      % (commands.source, len(unmatched), len(t), t[k] - first, effort[k],
                         float(held.at([t[k]])[0])))
    return held, ("the torque between samples from %d logged commands (%s), held from the tick "
                  "each took effect: it reproduces %d of %d effort samples"
                  % (len(changes), commands.source, len(t) - len(unmatched), len(t)))


def _real_column(source, key, raw):
    """`raw` as a one-dimensional float array, or ValueError naming `key` and what it is."""
    values = np.asarray(raw)
    if values.dtype.kind not in "iuf":
        raise ValueError("data (%s): %s must be real numbers, got %s"
                         % (source, key, "None" if raw is None else values.dtype))
    if values.ndim != 1:
        raise ValueError("data (%s): %s must be one-dimensional, got shape %s"
                         % (source, key, values.shape))
    return values.astype(float)


def commands_from_columns(cols, source, name="command"):
    """Commands from a mapping's optional `name`_t and `name` columns (any length, on the clock
    of t): name "command" the torque commands of effort mode, "setpoint" a servo's setpoints;
    or None."""
    times = name + "_t"
    if times not in cols and name not in cols:
        return None
    source = cols.get(name + "_source", source)
    if times not in cols or name not in cols:
        raise ValueError("data (%s): logged %ss need both %s and %s (has only %s)"
                         % (source, name, times, name, times if times in cols else name))
    from_log = name + "_source" in cols  # a bag's input log: as the node received them
    t, value = (_real_column(source, key, cols[key]) for key in (times, name))
    if len(t) != len(value):
        raise ValueError("data (%s): %s has %d values and %s %d"
                         % (source, times, len(t), name, len(value)))
    if not len(t):
        raise ValueError("data (%s): %s and %s are empty" % (source, times, name))
    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        raise ValueError("data (%s): %s[%d] = %r is not finite"
                         % (source, times, bad[0], t[bad[0]]))
    if np.any(np.diff(t) < 0):
        i = int(np.flatnonzero(np.diff(t) < 0)[0])
        raise ValueError("data (%s): %s[%d] = %r goes backward from %r: %ss in the order "
                         "received" % (source, times, i + 1, t[i + 1], t[i], name))
    bad = np.flatnonzero(~np.isfinite(value))
    if bad.size and not from_log:  # the node logs refused NaN and inf; a script's are its bugs
        raise ValueError("data (%s): %s[%d] = %r is not finite"
                         % (source, name, bad[0], value[bad[0]]))
    big = np.flatnonzero(np.isfinite(value) & (np.abs(value) > 1e6))
    if big.size:
        raise ValueError("data (%s): %s[%d] = %r is beyond any rig's (|x| > 1e6)"
                         % (source, name, big[0], value[big[0]]))
    tick = cols.get(name + "_tick")
    return Commands(t, value, str(cols.get(name + "_source", name + " columns")), tick)


def held_setpoints(setpoints, t, config):
    """(HeldCommand of the setpoints or None, note): in a servo mode, the setpoints the servo
    held (each from the instant it took effect), so that the replays run the servo's own law
    with the config's gains on the model's state, as the driver did: the torque between samples
    is then the law's, not a spline through the effort samples (a position servo driven by
    setpoint steps and read at 200 Hz was written with the rod's inertia 24 % off). None, with
    the note why, when the servo's integral would be needed at each segment's start (its ki not
    0) or the setpoints start after the recording."""
    mode = config["command.mode"]
    if setpoints is None or mode == "effort":
        return None, None if setpoints is None else (
            "the recording's %d logged setpoints are not used: command.mode is effort"
            % len(setpoints.t))
    ki = config["command.%s_ki" % mode]
    if ki != 0:
        return None, ("the logged setpoints are not used: the %s servo's integral (command.%s_ki "
                      "= %g) is not known where each replay starts; the effort samples drive "
                      "the replays" % (mode, mode, ki))
    keep = np.isfinite(setpoints.value)
    changes, values = setpoints.t[keep], setpoints.value[keep]
    if not len(changes) or changes[0] > t[0]:
        return None, ("the logged setpoints (%s) start after the recording's first sample: the "
                      "setpoint before them is not known; the effort samples drive the replays"
                      % setpoints.source)
    step = 1.0 / config["simulation.physics_rate"]
    if config["sensors.enabled"]:
        changes = changes + step * round(config["sensors.command_latency"] / step)
    return HeldCommand(changes, values, setpoints.source), (
        "the %s servo replayed with its law and the config's gains, driven by %d logged "
        "setpoints (%s)" % (mode, len(changes), setpoints.source))


def _log_fault(stamps, ticks, seq, step):
    """Why an input log cannot be trusted (ticks or stamps going back, inputs missing, a tick
    far beyond its stamps), or None."""
    for name, values in (("tick", ticks), ("stamp", stamps)):
        back = np.flatnonzero(np.diff(values) < 0)
        if back.size:
            i = int(back[0]) + 1
            return ("its %s goes back at message %d (%.17g after %.17g)"
                    % (name, i, values[i], values[i - 1]))
    if seq is not None:
        gap = np.flatnonzero(np.diff(seq) != 1)
        if gap.size:
            i = int(gap[0])
            return ("inputs are missing from it (seq %d follows %d: a gap in the bag, or two "
                    "runs' logs)" % (seq[i + 1], seq[i]))
    # Between two inputs the node runs as many ticks as the time allows: real_time_factor
    # within [0.01, 100] of the stamps, a second of slack (a node paused, then run fast).
    far = np.flatnonzero(np.diff(ticks) * step > 100.0 * np.diff(stamps) + 1.0)
    if far.size:
        i = int(far[0]) + 1
        return ("tick %d at message %d is %.3g s of simulation after the one before, %.3g s "
                "later by its stamps" % (ticks[i], i, (ticks[i] - ticks[i - 1]) * step,
                                         stamps[i] - stamps[i - 1]))
    return None


def on_tick_clock(cols, clock, logged, config):
    """(cols, logged, note, used): a recording with the node's ~input_log (clock: its stamps, the
    physics ticks they were taken at and the inputs' seq numbers, of every input logged; logged:
    a list of its Commands, or None), put on the simulation's own clock: each reading's stamp
    becomes the sim time of the tick it was published at (interpolated between the logged
    ticks' stamps, which the node stamps as it stamps its joint_states), each command's instant
    its tick's. Wall-clock stamps then hold no pause: a node that fell behind and caught up (a
    0.12 s stall on a busy 2-core machine) published a run of readings within microseconds,
    which the stamps read as a jump and a sprint of the motion. Readings outside the logged span
    are left out. A log that cannot be trusted (_log_fault) is not used at all: its commands
    neither (logged comes back as Nones), and the note says why."""
    stamps, ticks = (np.asarray(c, dtype=float) for c in clock[:2])
    seq = np.asarray(clock[2]) if len(clock) > 2 else None
    step = 1.0 / config["simulation.physics_rate"]
    fault = _log_fault(stamps, ticks, seq, step)
    if fault:
        return cols, [None] * len(logged), (
            "the input log is not used: %s; the readings' own stamps and the effort samples "
            "drive the fit" % fault), False
    t = cols["t"]
    inside = (t >= stamps[0]) & (t <= stamps[-1])
    if len(stamps) < 2 or np.count_nonzero(inside) < 0.5 * len(t):
        return cols, [None] * len(logged), (
            "the input log is not used: its %d inputs, stamped %.6g..%.6g s, span less than half "
            "the readings (stamped %.6g..%.6g s): another run's, or another clock's"
            % (len(stamps), stamps[0], stamps[-1], t[0], t[-1])), False
    cols = {k: v[inside] for k, v in cols.items()}
    cols["t"] = np.interp(cols["t"], stamps, ticks * step)
    logged = [c if c is None or c.tick is None else
              Commands(c.tick * step, c.value, c.source, c.tick) for c in logged]
    slope = (stamps[-1] - stamps[0]) / max((ticks[-1] - ticks[0]) * step, step)
    note = ("the stamps put on the simulation's clock by the %d ticks the input log holds (its "
            "stamps ran %.4g s per simulated second%s)" % (len(stamps), slope,
                                                 "" if np.count_nonzero(~inside) == 0 else
                                                 "; %d readings outside its span left out"
                                                 % np.count_nonzero(~inside)))
    return cols, logged, note, True
