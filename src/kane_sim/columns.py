"""Groups of simulate's CSV columns (which are also Result's and the plots' names), read from the
one C++ table of output quantities (_core.output_columns(), sim/csv_format.cpp): a new load's
power column, its key in Result.powers() and its /mechanism_state field come from there."""

from kane_sim import _core

# (column, group, key within the group, MechanismState field or "", array index or -1)
TABLE = tuple(tuple(row) for row in _core.output_columns())


def _names(group):
    return tuple(name for name, g, _, _, _ in TABLE if g == group)


def _keyed(group):
    return tuple((key, name) for name, g, key, _, _ in TABLE if g == group)


# The energy's terms, then their sum.
ENERGIES = tuple(sorted(_names("energy"), key=lambda name: name == "energy"))
LEDGER = _names("ledger")
# The reaction forces (Kane's method, auxiliary speeds) [N], frame (0).
REACTIONS = _names("reaction")
# Each load's power [W] by the load's name: their sum is dT/dt.
POWERS = _keyed("power")
# Each body's kinetic energy [J] by body.
KINETIC_PER_BODY = _keyed("kinetic")
# /mechanism_state's fields as columns: (column, field, index or None), for reading bags.
BAG_FIELDS = tuple((name, field, None if index < 0 else index)
                   for name, _, _, field, index in TABLE if field)
