"""The wheel and rail profiles a table was built from (its resolved config), per side, in
lutmpi's profile coordinates: wheel ``(s, dr(s))``, rail ``(v, z(v))``, m, wear applied."""

from __future__ import annotations

import numpy as np


def table_profiles(config_toml: str) -> dict[str, dict[str, tuple[np.ndarray, np.ndarray]]]:
    """``side -> {"wheel": (s, dr), "rail": (v, z)}`` of a table's ``config_toml``, m."""
    from lutmpi.export.kpf_format import table_config
    from lutmpi.scene import Scene

    scene = Scene.from_config(table_config(config_toml))
    out = {}
    for name, side in scene.sides.items():
        w, r = side.wheel.profile, side.rail.profile
        out[name] = {"wheel": (np.asarray(w.y), np.asarray(w.z)),
                     "rail": (np.asarray(r.y), np.asarray(r.z))}
    return out
