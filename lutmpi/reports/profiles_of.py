"""The wheel and rail profiles a table was built from (its resolved config), in lutmpi's profile
coordinates: wheel ``(s, dr(s))``, rail ``(v, z(v))``, m, wear applied."""

from __future__ import annotations

import tomllib

import numpy as np


def table_profiles(config_toml: str) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """``{"wheel": (s, dr), "rail": (v, z)}`` of a table's ``config_toml``, m."""
    from lutmpi.config.load import config_from_dict
    from lutmpi.scene import load_scene_profiles

    wheel, rail = load_scene_profiles(config_from_dict(tomllib.loads(config_toml)))
    return {"wheel": (np.asarray(wheel.y), np.asarray(wheel.z)),
            "rail": (np.asarray(rail.y), np.asarray(rail.z))}
