"""Units at the edge: the SI units of :mod:`lutmpi.table.schema` shown to engineers in mm and deg.

Every export column and report axis derives its unit from the schema field's ``units`` through
:func:`edge_unit`, so a new stored quantity gets its column and its label without another list.
"""

from __future__ import annotations

import math

from lutmpi.equilibrium.result import SIDES
from lutmpi.table.schema import FIELDS, Field

#: SI unit -> (edge unit, factor from SI, token usable in a column name)
EDGE_UNITS: dict[str, tuple[str, float, str]] = {
    "m": ("mm", 1e3, "mm"),
    "rad": ("deg", 180.0 / math.pi, "deg"),
    "1/m": ("1/mm", 1e-3, "per_mm"),
    "N": ("N", 1.0, "N"),
    "N/m": ("N/m", 1.0, "N_per_m"),
    "s": ("s", 1.0, "s"),
    "1": ("1", 1.0, ""),
    "": ("", 1.0, ""),
}
COMPONENTS = ("x", "y", "z")


def edge_unit(si_units: str) -> tuple[str, float, str]:
    """``(unit, factor, token)`` for values stored in ``si_units`` (unknown units pass through)."""
    return EDGE_UNITS.get(si_units, (si_units, 1.0, si_units.replace("/", "_per_")))


def columns(field: Field) -> list[tuple[str, tuple[int, ...]]]:
    """Column names of one schema field at one yaw, with the index into its suffix.

    ``z_g`` -> ``[("z_g_mm", ())]``; ``rolling_radius`` -> ``rolling_radius_left_s0_mm`` ... (both
    wheels, both contact slots); vectors get ``_x/_y/_z`` after the name.
    """
    _, _, token = edge_unit(field.units)
    tail = f"_{token}" if token else ""
    if not field.suffix:
        return [(f"{field.name}{tail}", ())]
    out = []
    n_side = field.suffix[0]
    for i in range(n_side):
        side = SIDES[i]
        if len(field.suffix) == 1:
            out.append((f"{field.name}_{side}{tail}", (i,)))
            continue
        for slot in range(field.suffix[1]):
            if len(field.suffix) == 2:
                out.append((f"{field.name}_{side}_s{slot}{tail}", (i, slot)))
                continue
            for c in range(field.suffix[2]):
                out.append((f"{field.name}_{COMPONENTS[c]}_{side}_s{slot}{tail}", (i, slot, c)))
    return out


def all_columns(names: list[str] | None = None) -> list[tuple[Field, str, tuple[int, ...]]]:
    """``(field, column, index)`` for every schema field (or those in ``names``), schema order."""
    out = []
    for f in FIELDS:
        if names is None or f.name in names:
            out += [(f, col, idx) for col, idx in columns(f)]
    return out
