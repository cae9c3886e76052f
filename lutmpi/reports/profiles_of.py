"""The wheel and rail profiles a table was built from (its resolved config), per side, in
lutmpi's profile coordinates: wheel ``(s, dr(s))``, rail ``(v, z(v))``, m, wear applied."""

from __future__ import annotations

from typing import Any

import numpy as np


def table_profiles(table: Any) -> dict[str, dict[str, tuple[np.ndarray, np.ndarray]]]:
    """``side -> {"wheel": (s, dr), "rail": (v, z)}`` of the pair a
    :class:`~lutmpi.table.Table` was built from, m (its profile files checked against the
    table's record: :meth:`~lutmpi.table.Table.built_config`)."""
    from lutmpi.scene import Scene

    scene = Scene.from_config(table.built_config())
    out = {}
    for name, side in scene.sides.items():
        w, r = side.wheel.profile, side.rail.profile
        out[name] = {"wheel": (np.asarray(w.y), np.asarray(w.z)),
                     "rail": (np.asarray(r.y), np.asarray(r.z))}
    return out
