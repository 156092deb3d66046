"""kane_sim's plots, one module for plot_bag (bags and simulate's CSVs) and for Python results
(kane_sim.Result): the run (motion, torque, energies, the power of each load, the ledger) and
the reaction forces Kane's method brings into evidence. Data are columns named as simulate's
CSV: a dict of sequences, a Result, or what read_run returns."""
import bisect
import csv
import os

import matplotlib

if not os.environ.get("DISPLAY") and "MPLBACKEND" not in os.environ:
    matplotlib.use("Agg")  # headless: write files, no window
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from kane_sim import bags, columns  # noqa: E402

FIGURE_SIZE = (12, 10.5)  # inches
DPI = 100                 # -> 1200 x 1050 pixels

# What every run has (older CSVs and bags too), and what newer ones add.
REQUIRED = ("t", "q1", "q2", "u1", "u2", "applied_torque", "kinetic_energy",
            "gravitational_energy", "spring_energy", "total_energy", "motor_work",
            "dissipated_energy", "energy_balance")
POWERS = tuple((name, "motor M_m u1" if short == "motor" else short.replace("_", " "))
               for short, name in columns.POWERS)  # (column, legend label)
REACTIONS = columns.REACTIONS

# /mechanism_state's fields as CSV columns: (column, field, index or None).
_BAG_FIELDS = columns.BAG_FIELDS
_POWER_KEYS = dict(columns.POWERS)  # load name -> its power column
_ENERGY_KEYS = dict(columns.LOAD_ENERGIES)  # load name -> its potential energy column


def _bag_fields(m):
    """(column, field, index) for one message. The loads' powers by their names in load_names
    (whatever order or loads the recording's version had); a bag recorded before the named
    arrays (2026-11-25) has one <load>_power field per load instead."""
    names = getattr(m, "load_names", None)
    fields = [f for f in _BAG_FIELDS if f[1] not in ("load_powers", "load_energies")]
    if names is not None:
        fields += [(_POWER_KEYS[n], "load_powers", i) for i, n in enumerate(names)
                   if n in _POWER_KEYS]
        if getattr(m, "load_energies", None):  # bags recorded before load_energies lack it
            fields += [(_ENERGY_KEYS[n], "load_energies", i) for i, n in enumerate(names)
                       if n in _ENERGY_KEYS]
    else:
        fields += [(column, key + "_power", None) for key, column in _POWER_KEYS.items()]
    return fields


_ENERGY_LABELS = {"kinetic_energy": "kinetic T", "gravitational_energy": "gravitational V_g",
                  "spring_energy": "spring V_s", "total_energy": "total E"}


def _energy_curves(data):
    """(column, label) of the energy panel: T, each load's potential energy (the output table's
    energy columns: gravity's and the spring's always, another load's when it is not zero
    throughout), E, then W and D."""
    terms = [k for k in columns.ENERGIES if k in data and len(data[k]) and
             (k in _ENERGY_LABELS or np.any(np.asarray(data[k]) != 0))]
    return ([(k, _ENERGY_LABELS.get(k) or k[:-len("_energy")].replace("_", " ") + " V")
             for k in terms] + [("motor_work", "motor work W"), ("dissipated_energy", "dissipated D")])


def require_regular_file(path):
    """Refuses what is not a regular file (a device such as /dev/zero, a pipe, a folder): read
    as a bag or a CSV it would never end and grow without bound."""
    if not os.path.isfile(path):
        raise ValueError("not a regular file (a bag or a CSV): %s" % (
            "no such file" if not os.path.exists(path) else "a device, a pipe or a folder"))


def read_run(path):
    """A bag (/mechanism_state, and the sensors' /joint_states) or a simulate CSV as columns."""
    require_regular_file(path)
    return read_csv(path) if path.endswith(".csv") else read_bag(path)


def read_bag(path):
    columns = {}
    stamps = []  # header stamp -> sim time, for the sensor readings
    readings = []
    with bags.open_bag(path) as bag:
        topics = bag.get_type_and_topic_info().topics
        sensors = "/joint_states_true" in topics
        for topic, m, _ in bag.read_messages(topics=["/mechanism_state", "/joint_states"]):
            if topic == "/joint_states":
                if sensors:
                    readings.append((m.header.stamp.to_sec(), m.position[0]))
                continue
            stamps.append((m.header.stamp.to_sec(), m.sim_time))
            for column, field, index in _bag_fields(m):
                value = getattr(m, field, None)  # bags recorded before a field existed lack it
                if value is not None:
                    columns.setdefault(column, []).append(value if index is None else value[index])
    for key in REQUIRED:
        columns.setdefault(key, [])
    if readings and stamps:
        # The sim time at each reading's arrival stamp (sim-clock bags: stamp - epoch; wall-clock
        # bags: interpolated between the states' stamps).
        stamps.sort()
        wall = [w for w, _ in stamps]
        sim = [t for _, t in stamps]
        columns["sensor_t"] = [_interpolate(stamp, wall, sim) for stamp, _ in readings]
        columns["sensor_q1"] = [q for _, q in readings]
    return columns


def _interpolate(x, xs, ys):
    """ys at x, linear between the neighbours in xs (sorted), extended past the ends."""
    if len(xs) == 1:
        return ys[0] + (x - xs[0])
    i = min(max(bisect.bisect_left(xs, x), 1), len(xs) - 1)
    f = (x - xs[i - 1]) / max(xs[i] - xs[i - 1], 1e-12)
    return ys[i - 1] + f * (ys[i] - ys[i - 1])


def read_csv(path):
    with open(path, newline="") as f:
        reader = csv.DictReader(f)
        rows = list(reader)
        header = reader.fieldnames or []
    table = columns.renamed_columns({k: [float(r[k]) for r in rows] for k in header})
    missing = [k for k in REQUIRED if k not in table]
    if missing:
        raise ValueError("CSV lacks columns %s" % ", ".join(missing))
    return table


def _legend_outside(ax, handles=None, labels=None):
    """The legend right of the panel, never over a curve."""
    if handles is None:
        handles, labels = ax.get_legend_handles_labels()
    ax.legend(handles, labels, loc="upper left", bbox_to_anchor=(1.08, 1.0), fontsize="small",
              borderaxespad=0.0)


def _has(data, keys):
    return all(k in data and len(data[k]) for k in keys)


def plot_run(data, out=None, title="", compare=None, compare_label=""):
    """The run: q1, q2, u1/u2, torque, energies, each load's power (when the data have it), the
    ledger's drift. Returns the figure; writes it to `out` when given."""
    t = data["t"]
    powers = _has(data, [k for k, _ in POWERS])
    ratios = [1, 1, 1, 0.8, 1.3] + ([1.3] if powers else []) + [0.8]
    fig, axes = plt.subplots(len(ratios), 1, figsize=FIGURE_SIZE, dpi=DPI, sharex=True,
                             gridspec_kw={"height_ratios": ratios})
    # Each quantity on an axis of its own unit: q1 [rad] and q2 [m] are not comparable numbers.
    axes[0].plot(t, data["q1"], color="tab:blue", label="q1, crank angle")
    if data.get("sensor_t"):
        axes[0].plot(data["sensor_t"], data["sensor_q1"], ".", color="tab:green", markersize=2,
                     label="q1 as the sensors report it\n(joint_states, at arrival)")
    if compare:
        axes[0].plot(compare["t"], compare["q1"], "--", color="tab:gray",
                     label="q1, %s" % os.path.basename(compare_label))
    axes[0].set_ylabel("q1 [rad]")
    axes[1].plot(t, data["q2"], color="tab:orange", label="q2, slider 4")
    axes[1].set_ylabel("q2 [m]")
    ax = axes[2]
    ax.plot(t, data["u1"], color="tab:blue", label="u1 [rad/s] (left)")
    ax.set_ylabel("u1 [rad/s]", color="tab:blue")
    speed2 = ax.twinx()
    speed2.plot(t, data["u2"], color="tab:orange", label="u2 [m/s] (right)")
    speed2.set_ylabel("u2 [m/s]", color="tab:orange")
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = speed2.get_legend_handles_labels()
    _legend_outside(ax, h1 + h2, l1 + l2)
    axes[3].plot(t, data["applied_torque"], color="tab:red", label="applied M_m")
    axes[3].set_ylabel("torque [N m]")
    ax = axes[4]
    for key, label in _energy_curves(data):
        ax.plot(t, data[key], label=label)
    ax.set_ylabel("energy [J]")
    if powers:
        ax = axes[5]
        for key, label in POWERS:
            values = np.asarray(data[key])
            if np.any(values != 0):  # loads that are off (dampers, contact) stay out
                ax.plot(t, values, label=label)
        ax.plot(t, sum(np.asarray(data[k]) for k, _ in POWERS), "k:", linewidth=1,
                label="sum = dT/dt")
        ax.set_ylabel("power [W]")
    # The ledger's drift is many decades smaller than the energies: a panel of its own, in a
    # unit chosen for its size (no offset text to collide with anything).
    ledger = data["energy_balance"]
    drift = [v - ledger[0] for v in ledger]
    largest = max((abs(v) for v in drift), default=0.0)
    scale, unit = 1.0, "J"
    for factor, name in ((1e-3, "mJ"), (1e-6, "µJ"), (1e-9, "nJ"), (1e-12, "pJ")):
        if largest < 1000 * factor:
            scale, unit = factor, name
    # energy_balance books runtime parameter changes' jumps too (P; 0 in offline runs).
    axes[-1].plot(t, [v / scale for v in drift], color="black",
                  label="E + D - W - P, drift\n(P: parameter changes)")
    axes[-1].set_ylabel("ledger drift\n[%s]" % unit)
    axes[-1].set_xlabel("sim time [s]")
    for a in axes:
        a.grid(True, alpha=0.3)
        a.ticklabel_format(axis="y", useOffset=False)
        if a is not axes[2]:
            _legend_outside(a)
    speed2.ticklabel_format(axis="y", useOffset=False)
    fig.suptitle(title)
    fig.align_ylabels(axes)
    fig.tight_layout(rect=(0, 0, 1, 0.97))
    if out:
        fig.savefig(out)
    return fig


# Within this of q1 = ±90° (|cos q1| < TOGGLE_BAND) the reactions grow as 1/cos q1: the axes are
# scaled to the forces outside it, and the band is shaded.
TOGGLE_BAND = 0.1


def plot_reactions(data, out=None, title="Reaction forces (Kane's method, auxiliary speeds)"):
    """The pins' and the rails' forces and the spring's over the crank angle q1 (in degrees,
    unwrapped as the run went), from the columns pin_o_x ... spring_force. Near q1 = ±90° (B
    passing through O, rod 2 square to the rail: the linkage's toggle) the rail force and the
    pin forces grow as 1/cos q1; those stretches are shaded and drawn off scale."""
    if not _has(data, REACTIONS):
        raise ValueError("the data have no reaction forces (columns %s)" % ", ".join(REACTIONS))
    q1_rad = np.asarray(data["q1"])
    q1 = np.degrees(q1_rad)
    regular = np.abs(np.cos(q1_rad)) >= TOGGLE_BAND
    fig, axes = plt.subplots(4, 1, figsize=(12, 9), dpi=DPI, sharex=True)
    panels = [("pin O: ground on rod 1", (("pin_o_x", "x (down)"), ("pin_o_y", "y")))]
    panels.append(("pin A: rod 1 on rod 2", (("pin_a_x", "x (down)"), ("pin_a_y", "y"))))
    panels.append(("pin B: rod 2 on slider 3", (("pin_b_x", "x (down)"), ("pin_b_y", "y"))))
    panels.append(("rails and spring", (("rail_force_slider3", "rail on slider 3 (y)"),
                                        ("rail_force_slider4", "rail on slider 4 (y)"),
                                        ("spring_force", "spring k e on slider 4 (x)"))))
    for ax, (label, curves) in zip(axes, panels):
        largest = 0.0
        for key, name in curves:
            values = np.asarray(data[key])
            ax.plot(q1, values, label=name)
            if np.any(regular):
                largest = max(largest, np.max(np.abs(values[regular])))
        if largest > 0:
            ax.set_ylim(-1.3 * largest, 1.3 * largest)
        ax.set_ylabel("[N]")
        ax.set_title(label, fontsize="medium", loc="left")
        ax.grid(True, alpha=0.3)
        # the toggle's bands (|cos q1| < TOGGLE_BAND), where the forces leave the scale
        lo, hi = q1.min(), q1.max()
        half = np.degrees(np.arcsin(TOGGLE_BAND))
        for k in range(int(np.floor(lo / 180)) - 1, int(np.ceil(hi / 180)) + 1):
            centre = 90 + 180 * k
            if centre + half >= lo and centre - half <= hi:
                ax.axvspan(max(centre - half, lo), min(centre + half, hi), color="gray",
                           alpha=0.15, label=None)
        _legend_outside(ax)
    axes[0].text(0.0, 1.18, "shaded: |cos q1| < %g, the toggle (B passes through O): forces grow "
                 "as 1/cos q1, drawn off scale" % TOGGLE_BAND, transform=axes[0].transAxes,
                 fontsize="small", color="dimgray")
    axes[-1].set_xlabel("crank angle q1 [deg]")
    fig.suptitle(title)
    fig.tight_layout(rect=(0, 0, 1, 0.97))
    if out:
        fig.savefig(out)
    return fig


def plot_result(result, out=None, kind="run", title=""):
    """A kane_sim.Result (or any columns) as plot_run ('run') or plot_reactions ('reactions')."""
    if kind == "reactions":
        return plot_reactions(result, out, title or "Reaction forces (Kane's method, auxiliary speeds)")
    if kind != "run":
        raise ValueError("kind must be 'run' or 'reactions', got %r" % (kind,))
    return plot_run(result, out, title)


def plot_identification(fit, out, title=""):
    """identify --plot: the recorded q1 and q2 against the fitted model and the base model, each
    driven by the recorded torque from the recorded start (kane_sim.identify's validation)."""
    v = fit.validation
    if not v:
        raise ValueError("plot_identification: the fit was not validated (validate=True)")
    fig, axes = plt.subplots(2, 1, figsize=(10, 6), sharex=True)
    rec = v["recorded"]
    t0 = rec["t"][0]
    for k, (ax, label, unit) in enumerate(zip(axes, ("q1", "q2"), ("rad", "m"))):
        ax.plot(rec["t"] - t0, rec["q"][:, k], color="black", lw=2.2, label="recorded")
        for which, style in (("fitted", dict(color="tab:green", lw=1.0)),
                             ("base", dict(color="tab:red", lw=0.8, ls="--"))):
            run = v[which]
            if "t" in run:
                ax.plot(run["t"] - t0, run["q"][:, k], label="%s model (RMS %.3g %s)"
                        % (which, run["%s_rms" % label], unit), **style)
        ax.set_ylabel("%s [%s]" % (label, unit))
        ax.grid(True, alpha=0.3)
        _legend_outside(ax)
    axes[-1].set_xlabel("t [s]")
    fig.suptitle(title or "identification: recorded motion, fitted and base models")
    fig.tight_layout()
    fig.savefig(out, dpi=100, bbox_inches="tight")
    plt.close(fig)
    return out
