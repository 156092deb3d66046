"""The mechanism as Python objects over kane_sim._core: Config (the one loader), Simulator (the
one driver: SimDriver, stepped by simulate's loop), analyze (analyze --json), sweep (simulate
--sweep). Errors keep the C++ messages: ConfigError (a ValueError) names the key and the value,
ValueError a refused input, StepRefused (a RuntimeError) a refused step."""
import json
import math
import os
import warnings
from collections.abc import Mapping

import numpy as np
import yaml

from kane_sim import _core, columns
from kane_sim._core import ConfigError, StepRefused, TorqueProfile

__all__ = ["Config", "ConfigError", "Result", "Simulator", "StepRefused", "TorqueProfile",
           "analyze", "load_config", "sweep"]


def _yaml_scalar(value, name):
    """A Python value as the YAML a config file would hold (NaN as .nan: the loader names it);
    anything else a TypeError naming the key."""
    if isinstance(value, (np.generic, np.ndarray)) and np.ndim(value) == 0:
        value = value.item()
    if not isinstance(value, (bool, int, float, str)):
        raise TypeError("config key '%s': a value must be a number, a bool or a string, got %s %r"
                        % (name, type(value).__name__, value))
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):  # repr reads back exactly; YAML spells the non-finite ones
        return repr(value) if math.isfinite(value) else \
            (".nan" if value != value else ("-.inf" if value < 0 else ".inf"))
    return yaml.safe_dump(value)


class Config:
    """A validated config. Config() is the package's config/mechanism.yaml; Config(path) a file;
    Config(dict) the same sections and keys as a file. Values by config name:
    cfg["mechanism.rod_mass"]; cfg["mechanism.rod_mass"] = 2.0 goes through the loader again
    (a refused value raises ConfigError and changes nothing)."""

    def __init__(self, source=None):
        if isinstance(source, Config):
            self._core = source._core
        elif isinstance(source, _core.Config):
            self._core = source
        elif source is None:
            self._core = _core.Config.from_file("")
        elif isinstance(source, (str, os.PathLike)):
            if not os.fspath(source):  # as simulate --config '': not the default in disguise
                raise ConfigError("config '' is not a readable file: give a path, or None for "
                                  "the package's config/mechanism.yaml")
            self._core = _core.Config.from_file(os.fspath(source))
        elif isinstance(source, Mapping):
            self._core = _core.Config.from_yaml(yaml.safe_dump(_plain(source)))
        else:
            raise TypeError("Config takes a file path, a dict or nothing, got %s"
                            % type(source).__name__)

    def __getitem__(self, name):
        """A value by config name: cfg["mechanism.rod_mass"]."""
        return self._core.get(name)

    def __setitem__(self, name, value):
        """Sets a value through the loader again (ConfigError: nothing changes)."""
        self._core = self._core.with_value(name, _yaml_scalar(value, name))

    def with_values(self, values):
        """A copy with {'section.key': value} set, validated as a whole: the loader sees every
        value at once, so the order of the keys does not matter (friction rk4 cannot follow is
        accepted together with simulation.integrator dopri5, whichever comes first)."""
        return Config(self._core.with_values(
            [(name, _yaml_scalar(value, name)) for name, value in values.items()]))

    @staticmethod
    def names(role=None):
        """Every config name ("section.key") a Config takes; with `role`, those of that role
        (Config.role's names: "inertial", "dissipative", ...)."""
        names = list(_core.Config.names())
        return names if role is None else [n for n in names if _core.Config.role(n) == role]

    @staticmethod
    def role(name):
        """What a parameter is (the schema's role): inertial, geometric, gravity, stiffness,
        dissipative, load shape, drive, contact, initial state, operational or measurement."""
        return _core.Config.role(name)

    @staticmethod
    def law(name):
        """The law of the load whose coefficient the parameter is: "viscous" (a damper),
        "coulomb" (friction), "elastic" (the crank's spring), or "" (no such load's). Two
        parameters of one role can differ here: a damper's and friction's are both
        "dissipative"."""
        return _core.Config.law(name)

    @property
    def warnings(self):
        """What the loader said of the source (unknown keys, a jitter longer than the reading
        period, ...)."""
        return list(self._core.warnings)

    @property
    def source(self):
        """The file it was read from ("" for a dict)."""
        return self._core.source

    def yaml(self):
        """The config as YAML text: what `simulate --config` reads."""
        return self._core.yaml()

    def __repr__(self):
        return "Config(%r)" % self.source


def _real(what, value):
    """A real number as a float: TypeError for complex numbers, strings and the like."""
    if isinstance(value, (bool, complex, np.complexfloating)) or not isinstance(
            value, (int, float, np.integer, np.floating)):
        raise TypeError("%s must be a real number, got %r (%s)"
                        % (what, value, type(value).__name__))
    try:
        return float(value)
    except OverflowError:
        raise ValueError("%s %r is beyond the range of a float" % (what, value)) from None


def _plain(value):
    """NumPy scalars and arrays in a dict as plain Python (what yaml.safe_dump writes)."""
    if isinstance(value, Mapping):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return value


def load_config(source=None):
    """Config(source): a file path, a dict, or None for the package's config/mechanism.yaml."""
    return Config(source)


class Result(Mapping):
    """A run's outputs: one NumPy array per column of simulate's CSV (result["pin_o_x"], ...,
    `list(result)` names them), and the usual groups: t, q (N x 2), u, u_dot, applied_torque,
    energies, ledger, reactions, powers, kinetic_per_body."""

    def __init__(self, columns, config=None, sensors=None):
        self.columns = dict(columns)
        self.config = config  # the Config of the run (kane_sim.animate reads L from it)
        # With sensors on (config sensors:), the readings as they reached joint_states: "t"
        # (arrival), "sample_t", "position" and "velocity" (N x 4: crank, coupler, slider 3,
        # slider 4). Empty arrays with the sensors off.
        self.sensors = sensors

    def __getitem__(self, name):
        try:
            return self.columns[columns.current_name(name)]
        except KeyError:
            raise KeyError("%r is not a column of this result; the columns are: %s"
                           % (name, ", ".join(self.columns))) from None

    def __iter__(self):
        return iter(self.columns)

    def __len__(self):
        return len(self.columns)

    def _stack(self, *names):
        return np.column_stack([self.columns[n] for n in names])

    @property
    def t(self):
        """Sim time [s] of each row."""
        return self.columns["t"]

    @property
    def q(self):
        """(q1 [rad], q2 [m]) per row: N x 2."""
        return self._stack(*columns.Q)

    @property
    def u(self):
        """(u1 [rad/s], u2 [m/s]) per row: N x 2."""
        return self._stack(*columns.U)

    @property
    def u_dot(self):
        """(u1', u2') per row: N x 2, from the equations the integrator stepped."""
        return self._stack(*columns.U_DOT)

    @property
    def applied_torque(self):
        """The torque delivered [N m] per row (clamped, the motor line)."""
        return self.columns["applied_torque"]

    @property
    def torque(self):
        """Deprecated: applied_torque (Simulator's held command is commanded_torque)."""
        warnings.warn("Result.torque is now Result.applied_torque (the former name goes in the "
                      "next release)", DeprecationWarning, stacklevel=2)
        return self.applied_torque

    def _group(self, names):
        return {name: self.columns[name] for name in names}

    @property
    def energies(self):
        """Kinetic, potential and total energy [J] by name."""
        return self._group(columns.ENERGIES)

    @property
    def ledger(self):
        """The energy ledger [J]: motor work W, dissipated D, E + D - W and its parts."""
        return self._group(columns.LEDGER)

    @property
    def reactions(self):
        """Reaction forces [N, N m] at the pins and rails (Kane's auxiliary speeds)."""
        return self._group(columns.REACTIONS)

    @property
    def powers(self):
        """Each load's power [W] by its short name; they add up to dT/dt."""
        return {short: self.columns[name] for short, name in columns.POWERS}

    @property
    def kinetic_per_body(self):
        """Each body's kinetic energy [J] by body."""
        return {body: self.columns[name] for body, name in columns.KINETIC_PER_BODY}

    def __repr__(self):
        t = self.t
        span = "t = %g .. %g s" % (t[0], t[-1]) if len(t) else "empty"
        return "Result(%d rows, %s, %d columns)" % (len(t), span, len(self.columns))


class Simulator:
    """The mechanism stepped at simulation.physics_rate by the driver the node runs.

    run(duration, torque=None, output_rate=None) -> Result: torque a number, a TorqueProfile,
    an array of one value per physics step, or a callable f(t, state) -> float called before
    every step (slow: a Python call per step); None holds the torque in force. In servo modes
    (command.mode velocity | position) the values are setpoints. Long runs release the GIL and
    stop at Ctrl-C (KeyboardInterrupt; the rows until then are in last_result)."""

    def __init__(self, config=None):
        self._config = config if isinstance(config, Config) else Config(config)
        self._sim = _core.Simulator(self._config._core)

    def __copy__(self):
        raise TypeError("a Simulator cannot be copied (a copy would share its driver): build "
                        "another from its config, Simulator(sim.config), and set_state(sim.state)")

    def __deepcopy__(self, memo):
        raise TypeError("a Simulator cannot be deep-copied: build another from its config, "
                        "Simulator(sim.config), and set_state(sim.state)")

    def __reduce__(self):
        raise TypeError("a Simulator cannot be pickled: pickle its config's yaml() and state")

    @property
    def config(self):
        """The config in force (runtime changes included)."""
        return Config(self._sim.config)

    @property
    def state(self):
        """(q1 [rad], q2 [m], u1 [rad/s], u2 [m/s]) now, as a NumPy array."""
        return self._sim.state

    @property
    def time(self):
        """Sim time [s] since the start (reset and set_state never move it back)."""
        return self._sim.time

    @property
    def ticks(self):
        """Physics steps taken since the start."""
        return self._sim.ticks

    @property
    def step_size(self):
        """One physics step [s]: 1 / simulation.physics_rate."""
        return self._sim.step_size

    @property
    def commanded_torque(self):
        """The torque [N m] (servo modes: the setpoint) that step() holds: the command, before
        the clamp and the motor line (a run's Result.applied_torque is what was delivered)."""
        return self._sim.commanded_torque

    @property
    def torque(self):
        """Deprecated: commanded_torque."""
        warnings.warn("Simulator.torque is now Simulator.commanded_torque (the former name goes "
                      "in the next release)", DeprecationWarning, stacklevel=2)
        return self.commanded_torque

    def set_state(self, state):
        """(q1, q2, u1, u2); refused (ValueError, the driver's reason) like ~set_state."""
        self._sim.set_state(np.asarray(state, dtype=float))

    def reset(self):
        """Back to the config's initial state, like ~reset: work and ledger 0, the command
        forgotten, sensor readings in flight dropped; sim time runs on."""
        self._sim.reset()

    def set_torque(self, torque):
        """The torque [N m] (servo modes: the setpoint) that step() holds from now on; clamped
        like torque_command, refused (ValueError) when not finite."""
        self._sim.set_torque(_real("set_torque: torque", torque))

    def step(self, n=1):
        """n physics steps (a whole number >= 1) with the torque in force; returns the state.
        Ctrl-C stops them where they are (KeyboardInterrupt)."""
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)):
            raise TypeError("step: n must be a whole number of physics steps, got %r (%s)"
                            % (n, type(n).__name__))
        if int(n) * self.step_size > 1e7:  # simulate's longest run; also keeps n in a C++ long
            raise ValueError("step: n = %d physics steps is more than 1e7 s of sim time" % n)
        return self._sim.step(int(n))

    def run(self, duration, torque=None, output_rate=None, states_only=False):
        """A run of `duration` [s] (on the output grid: a whole number of 1/output_rate) from
        the state now -> Result with every CSV column, rows every 1/output_rate s (default
        simulation.publish_rate). torque: a number, a TorqueProfile, an array of one value
        per physics step, a callable f(t, state) -> float called before every step, or None
        to hold the torque in force (servo modes: setpoints). states_only: the columns t, q1,
        q2, u1, u2 alone (the same numbers, without the snapshot of every other column at each
        row: several times faster, for fits that replay a recording many times). Ctrl-C stops
        it (KeyboardInterrupt; the rows until then are in last_result)."""
        if not isinstance(states_only, (bool, np.bool_)):
            raise TypeError("run: states_only must be True or False, got %r" % (states_only,))
        columns = self._sim.run(_real("run: duration", duration), torque, output_rate,
                                bool(states_only))
        return Result(columns, self.config, self._sim.last_readings)

    @property
    def last_result(self):
        """The last run's rows, also when it ended in an exception."""
        r = self._sim.last_result
        return None if r is None else Result(r, self.config, self._sim.last_readings)

    def take_readings(self):
        """The sensor readings step() collected since the last call (as Result.sensors)."""
        return self._sim.take_readings()

    def snapshot(self):
        """This instant's values by CSV column name (plus resting_contact,
        reactions_determinate)."""
        return self._sim.snapshot()

    def rates(self, states, torque=0.0):
        """x' = (q1', q2', u1', u2') of each row of states (N x 4) at torque (a number or N).
        States whose rates are not finite, and torques beyond command.torque_limit, are refused
        (ValueError naming the row)."""
        return self._sim.rates(np.asarray(states, dtype=float), np.asarray(torque, dtype=float))

    def __getitem__(self, name):
        """A config value in force by name ("mechanism.rod_mass")."""
        return self._sim.get(name)

    def __setitem__(self, name, value):
        """A runtime change (the parameters dynamic_reconfigure offers), at the current state."""
        self._sim.set(name, _yaml_scalar(value, name))

    def events(self):
        """What the driver reported since the last call: [(t, message)]; each report once, at
        its first time (a held torque is clamped at every re-send: one entry)."""
        return self._sim.take_events()


def analyze(config=None, torque=0.0, q1=None):
    """`analyze --json` as a dict: the static equilibrium under a constant torque (or, q1 given,
    the crank held at q1 [rad] by its holding moment, as `analyze --q1`), its stability, the
    linear model A, B (exact derivatives), eigenvalues, natural frequencies, damping ratios, mode
    shapes, notes."""
    cfg = config if isinstance(config, Config) else Config(config)
    if q1 is not None:
        if torque != 0.0:
            raise ValueError("analyze: q1 holds the crank by its own moment: give torque or q1, "
                             "not both")
        q1 = _real("analyze: q1", q1)
        if not math.isfinite(q1) or abs(q1) > 1e6:
            raise ValueError("analyze: q1 must be a finite angle within 1e6 rad, got %r" % q1)
    return json.loads(_core.analyze_json(cfg._core, float(torque), q1))


def equilibria(config=None, torque=0.0):
    """`analyze --equilibria --json` as a list of dicts: every equilibrium (u = 0) around the turn
    under a constant torque, q1 in (-pi, pi] ascending, with q2, its stability ("stable",
    "unstable", "neutral") and the largest real part of A's eigenvalues [1/s]."""
    cfg = config if isinstance(config, Config) else Config(config)
    return [{"q1": q1, "q2": q2, "stability": stability, "largest_real_eigenvalue": rate}
            for q1, q2, stability, rate in _core.equilibria(cfg._core, float(torque))]


def sweep(config=None, grid=None, cases=None, duration=10.0, torque=None, jobs=0, simd="auto",
          vector_trig=False, client=None, chunk=64):
    """`simulate --sweep` as arrays: grid={'section.key': values, ...} (every combination, the
    last key fastest) or cases={'section.key': values} (one case per index). Returns a dict:
    the keys' values, 'status' and 'error' per case, then t, q1 ... wall_time (NaN where the
    loader refused a case's config).

    torque: a number or a TorqueProfile (a servo's setpoint in command.mode velocity |
    position); None holds each case's start (0 N m, or the servo's initial setpoint), as a
    single run does. duration: [0, 1e7] s. jobs: threads, 0 = one per core, at most 4 per core.
    simd: "auto" (the CPU's widest SIMD lanes), "avx512", "avx2", "sse2", "scalar" or "off"
    (every case alone), as simulate's --simd: the same rows either way; vector_trig: lanes with
    xsimd's vector sin/cos, as --vector-trig (not the single runs' bits).

    client: a Dask distributed Client, or a scheduler's address ("tcp://HOST:PORT"): the cases
    run there in chunks of `chunk` per task (kane_sim.cluster), the same rows in case order; a
    scheduler that cannot be reached is a ValueError naming it.
    Ctrl-C stops the sweep: the KeyboardInterrupt raised carries the dict as `.result`, with the
    finished cases and the others marked 'interrupted'."""
    cfg = config if isinstance(config, Config) else Config(config)
    if (grid is None) == (cases is None):
        raise ValueError("sweep: give grid= or cases=, one of them")
    if grid is not None:
        keys, rows = _core.sweep_grid([(k, [float(v) for v in vs]) for k, vs in grid.items()])
    else:
        keys = list(cases)
        columns = [np.asarray(cases[k], dtype=float).ravel() for k in keys]
        if len({len(c) for c in columns}) > 1:
            raise ValueError("sweep: every key of cases= needs as many values")
        rows = [list(r) for r in zip(*columns)]
    if torque is None or isinstance(torque, TorqueProfile):
        profile = torque
    else:
        profile = TorqueProfile.constant(float(torque))
    if not isinstance(simd, str):
        raise TypeError("sweep: simd must be a string, got %r" % (simd,))
    if isinstance(chunk, bool) or not isinstance(chunk, (int, np.integer)) or \
            not 1 <= chunk <= 100000:
        raise ValueError("sweep: chunk must be a whole number of cases in [1, 100000], got %r"
                         % (chunk,))
    if isinstance(jobs, bool) or not isinstance(jobs, (int, np.integer)):
        raise TypeError("sweep: jobs must be a whole number, got %r" % (jobs,))
    # What the sweep refuses before it runs (keys, duration, jobs, simd), refused before
    # anything runs or is sent.
    _core.sweep(cfg._core, list(keys), [], float(duration), profile, int(jobs), simd,
                bool(vector_trig))
    if client is not None:
        from kane_sim import cluster  # distributed is imported only for a cluster sweep
        return cluster.sweep(cfg._core, keys, rows, duration, profile, simd, vector_trig, client,
                             chunk)
    try:
        out = _core.sweep(cfg._core, list(keys), rows, float(duration), profile, int(jobs), simd,
                          bool(vector_trig))
    except KeyboardInterrupt as interrupted:
        partial = getattr(interrupted, "result", None)
        if partial is not None:
            interrupted.result = {k: np.asarray(v) for k, v in partial.items()}
        raise
    return {k: np.asarray(v) for k, v in out.items()}  # status and error as arrays of str too
