"""Groups of simulate's CSV columns (which are also Result's and the plots' names), read from the
one C++ table of output quantities (_core.output_columns(), sim/csv_format.cpp): a new load's
power column, its key in Result.powers() and its /mechanism_state field come from there."""

import warnings

from kane_sim import _core

# (column, group, key within the group, MechanismState field or "", array index or -1)
TABLE = tuple(tuple(row[:5]) for row in _core.output_columns())
# Columns renamed on 2026-11-26 (one name per quantity: a scalar of /mechanism_state has its
# field's name, every load power is power_<load>): former name -> name. Readers take the former
# names for one release, with a DeprecationWarning.
RENAMED = {row[5]: row[0] for row in _core.output_columns() if row[5]}


def _names(group):
    return tuple(name for name, g, _, _, _ in TABLE if g == group)


def _keyed(group):
    return tuple((key, name) for name, g, key, _, _ in TABLE if g == group)


def current_name(name, stacklevel=3):
    """`name`, or the column a former name became (with a DeprecationWarning saying so)."""
    if name in RENAMED:
        warnings.warn("column %r is now %r (the former name goes in the next release)"
                      % (name, RENAMED[name]), DeprecationWarning, stacklevel=stacklevel)
        return RENAMED[name]
    return name


def renamed_columns(table):
    """A dict of columns read from an older CSV with its former names replaced by today's (one
    FutureWarning naming them); a current CSV unchanged."""
    old = [name for name in table if name in RENAMED and RENAMED[name] not in table]
    if not old:
        return table
    # A FutureWarning: shown by default (a DeprecationWarning is hidden outside __main__), since
    # the one who must act is whoever holds the file, a tool's user as much as a programmer.
    warnings.warn("an older CSV: columns %s are now %s (read under their new names; the former "
                  "names are read until the next release)"
                  % (", ".join(old), ", ".join(RENAMED[n] for n in old)), FutureWarning,
                  stacklevel=2)
    return {RENAMED.get(name, name) if name in old else name: values
            for name, values in table.items()}


# The energy's terms, then their sum.
ENERGIES = tuple(sorted(_names("energy"), key=lambda name: name == "total_energy"))
LEDGER = _names("ledger")
# The reaction forces (Kane's method, auxiliary speeds) [N], frame (0).
REACTIONS = _names("reaction")
# Each load's power [W] by the load's name: their sum is dT/dt.
POWERS = _keyed("power")
# The potential energy column of each load that has one (beside gravity's and the spring's own
# fields), by the load's name: /mechanism_state's load_energies, keyed by load_names.
_LOAD_NAMES = {index: key for _, g, key, field, index in TABLE if field == "load_powers"}
LOAD_ENERGIES = tuple((_LOAD_NAMES[index], name) for name, _, _, field, index in TABLE
                      if field == "load_energies")
# Each body's kinetic energy [J] by body.
KINETIC_PER_BODY = _keyed("kinetic")
# /mechanism_state's fields as columns: (column, field, index or None), for reading bags.
BAG_FIELDS = tuple((name, field, None if index < 0 else index)
                   for name, _, _, field, index in TABLE if field)


def _field(field):
    """The columns that carry /mechanism_state's array `field`, in its order."""
    rows = sorted((index, name) for name, _, _, f, index in TABLE if f == field)
    return tuple(name for _, name in rows)


# The state and its rates: Result.q, .u, .u_dot and VectorEnv's observation read these.
Q = _field("q")
U = _field("u")
U_DOT = _field("u_dot")
STATE = Q + U
